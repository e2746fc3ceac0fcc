#include "apps/diff_picture.h"

#include <cstdio>

#include "core/io/output_file.h"

namespace oct {

namespace {

std::string count(uint64_t n, const char* what) { return std::to_string(n) + " " + what; }

}  // namespace

// The colours are diffImage's (validation/report/diff_image.cpp).
Legend diffLegend(const DiffMarks& m, double tTolerance) {
    Legend l;
    l.title = "validate: our primary hits and shadow rays against the reference's";
    char tol[96];
    std::snprintf(tol, sizeof tol,
                  "blue -> green -> yellow: |dt| / extent from 1e-10 to %g "
                  "(the t tolerance), log scale",
                  tTolerance);
    l.subtitle.push_back(tol);
    l.swatches = {{{0, 0, 0}, "both miss"},     {{40, 40, 40}, "same t"},
                  {{30, 60, 200}, "dt 1e-10"},  {{250, 230, 40}, "dt at tolerance"},
                  {{255, 140, 0}, "ambiguous"}, {{255, 190, 110}, "ambiguous shadow"},
                  {{255, 0, 0}, "wrong"},       {{255, 0, 255}, "wrong shadow"}};
    l.notes.push_back(count(m.wrongPrimary, "wrong") + ", " +
                      count(m.ambiguousPrimary, "ambiguous") + " primary hits; " +
                      count(m.wrongShadow, "wrong") + ", " + count(m.ambiguousShadow, "ambiguous") +
                      " shadow rays, of " + std::to_string(m.pixels) + " pixels");
    const uint64_t wrong = m.wrongPrimary + m.wrongShadow;
    if (wrong > 0)
        l.notes.push_back(m.ringed ? "wrong pixels ringed (radius 3) so that each shows"
                                   : "wrong pixels not ringed: more than " +
                                         std::to_string(kMaxRingedPixels) +
                                         " are wrong, each is its own colour");
    return l;
}

void writeDiffPicture(const std::string& path, const FilmValidation& v, double tTolerance) {
    RgbImage picture;
    picture.width = v.width;
    picture.height = v.height;
    picture.rgb = diffImage(v, tTolerance);
    const RgbImage out = withLegend(picture, diffLegend(diffMarks(v), tTolerance));
    writePng(path, out.width, out.height, out.rgb);
}

}  // namespace oct
