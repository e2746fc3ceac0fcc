#include "validation/report/diff_image.h"

#include <algorithm>
#include <cmath>

#include "core/io/output_file.h"

namespace oct {
namespace {

struct Rgb {
    uint8_t r, g, b;
};

Rgb lerp(Rgb a, Rgb b, double u) {
    auto mix = [u](uint8_t x, uint8_t y) { return uint8_t(std::lround(x + (y - x) * u)); };
    return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

Rgb heat(double rel, double tol) {
    if (rel <= 0.0) return {40, 40, 40};
    const double lo = -10.0, hi = std::log10(std::max(tol, 1e-9));
    double u = std::clamp((std::log10(rel) - lo) / (hi - lo), 0.0, 1.0);
    const Rgb blue = {30, 60, 200}, green = {40, 190, 90}, yellow = {250, 230, 40};
    return u < 0.5 ? lerp(blue, green, 2.0 * u) : lerp(green, yellow, 2.0 * u - 1.0);
}

}  // namespace

DiffMarks diffMarks(const FilmValidation& v) {
    DiffMarks m;
    m.pixels = v.primaryClass.size();
    for (size_t i = 0; i < v.primaryClass.size(); ++i) {
        m.wrongPrimary += v.primaryClass[i] == uint8_t(HitClass::Wrong);
        m.ambiguousPrimary += v.primaryClass[i] == uint8_t(HitClass::Ambiguous);
        m.wrongShadow += v.shadowClass[i] == uint8_t(HitClass::Wrong);
        m.ambiguousShadow += v.shadowClass[i] == uint8_t(HitClass::Ambiguous);
    }
    const uint64_t wrong = m.wrongPrimary + m.wrongShadow;
    m.ringed = wrong > 0 && wrong <= kMaxRingedPixels;
    return m;
}

std::vector<uint8_t> diffImage(const FilmValidation& v, double tol) {
    const int w = v.width, h = v.height;
    std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3, 0);
    auto put = [&](int x, int y, Rgb c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        uint8_t* p = &rgb[3 * (size_t(y) * size_t(w) + size_t(x))];
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = size_t(y) * size_t(w) + size_t(x);
            uint8_t pc = v.primaryClass[i], sc = v.shadowClass[i];
            Rgb c = {0, 0, 0};
            if (pc == uint8_t(HitClass::Ambiguous))
                c = {255, 140, 0};
            else if (pc == uint8_t(HitClass::Wrong))
                c = {255, 0, 0};
            else if (pc != 255)
                c = heat(v.relativeDt[i], tol);
            if (sc == uint8_t(HitClass::Ambiguous)) c = {255, 190, 110};
            put(x, y, c);
        }
    // Rings last, so a neighbour never paints over them; without rings the wrong pixels are
    // coloured like the others, red for a wrong primary hit, magenta for a wrong shadow ray.
    const bool ringed = diffMarks(v).ringed;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = size_t(y) * size_t(w) + size_t(x);
            bool wrongP = v.primaryClass[i] == uint8_t(HitClass::Wrong);
            bool wrongS = v.shadowClass[i] == uint8_t(HitClass::Wrong);
            if (!wrongP && !wrongS) continue;
            Rgb ring = wrongP ? Rgb{255, 0, 0} : Rgb{255, 0, 255};
            if (!ringed) {
                put(x, y, ring);
                continue;
            }
            for (int dy = -3; dy <= 3; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    int d2 = dx * dx + dy * dy;
                    if (d2 >= 6 && d2 <= 10) put(x + dx, y + dy, ring);
                }
            put(x, y, ring);
        }
    return rgb;
}

void writeDiffImage(const std::string& path, const FilmValidation& v, double tol) {
    writePng(path, v.width, v.height, diffImage(v, tol));
}

}  // namespace oct
