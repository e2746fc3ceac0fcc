// validate's and certify's --diff-image as a person sees it: validate's difference image
// (validation/report/diff_image.h) with a legend band naming what each colour means, how many
// pixels carry it, and whether the wrong ones are ringed.
#pragma once

#include <string>

#include "teach/legend.h"
#include "validation/report/diff_image.h"

namespace oct {

// The legend of a difference image whose marks are `m`, |dt| coloured up to tTolerance.
Legend diffLegend(const DiffMarks& m, double tTolerance);
// Writes the image and its legend as a PNG (the picture at the top left: PNG pixel x, y is the
// frame's pixel x, y).
void writeDiffPicture(const std::string& path, const FilmValidation& v, double tTolerance);

}  // namespace oct
