// A picture of a FilmValidation for a person to look at: a heat map of |dt| / extent on a log
// scale where the primary hits agree, with ambiguous and wrong pixels marked.
//   black             both missed
//   dark grey         both hit at exactly the same t
//   blue -> yellow    |dt| / extent from 1e-10 (blue) up to the t tolerance (yellow), log scale
//   orange            ambiguous primary hit          light orange  ambiguous shadow ray
//   red + red ring    wrong primary hit              magenta ring  wrong shadow ray
// The rings (radius 3 pixels) make a single wrong pixel visible in a large image; they are drawn
// only while at most kMaxRingedPixels pixels are wrong, so that many wrong pixels (a broken
// kernel) show as themselves instead of painting a mostly right picture red.
#pragma once

#include <string>
#include <vector>

#include "validation/policy/hit_validation.h"

namespace oct {

constexpr uint64_t kMaxRingedPixels = 64;

// What the image marks: its legend (apps/diff_picture.h) names these.
struct DiffMarks {
    uint64_t pixels = 0;
    uint64_t wrongPrimary = 0, wrongShadow = 0, ambiguousPrimary = 0, ambiguousShadow = 0;
    bool ringed = false;  // the wrong pixels carry rings
};
DiffMarks diffMarks(const FilmValidation& v);

// RGB, 3 bytes per pixel, row-major, width x height of the validated films.
std::vector<uint8_t> diffImage(const FilmValidation& v, double tTolerance);
void writeDiffImage(const std::string& path, const FilmValidation& v, double tTolerance);

}  // namespace oct
