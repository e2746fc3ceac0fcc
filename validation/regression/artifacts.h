// What a failing regression check leaves for a person (or a CI job's artefact store) to look at
// (`octrace validate --artifacts DIR`): for each failing golden comparison the frame this build
// rendered, the golden image and a diff image; for each failing cost row its numbers; and
// DIR/index.html showing them side by side with the diff's legend. Written all or none
// (OutputSet), and nothing on a pass unless asked.
//
// The diff image (golden's size; the frame's pixels over it):
//   the golden pixel at a third of its brightness   d = 0 (the same)
//   blue                                            0 < d <= the backend's channel tolerance
//   red                                             d > channel levels: counted by the rule
// where d is a pixel's largest channel difference in 1/255 steps (golden.h, compareImages).
#pragma once

#include <string>
#include <vector>

#include "validation/regression/regression_run.h"

namespace oct {

// The diff image of one comparison (images.goldenWidth x goldenHeight, RGB8); a size mismatch
// has none (empty).
std::vector<uint8_t> goldenDiffImage(const GoldenImages& images, int channel);

struct ArtifactsWritten {
    std::vector<std::string> files;  // index.html first
    uint64_t failingImages = 0, failingCostRows = 0;
};

// Writes the artefacts of `r` into `dir` (made when missing): always when `always`, else only
// when something failed or was skipped. Returns what was written (nothing: no files).
ArtifactsWritten writeRegressionArtifacts(const std::string& dir, const RegressionReport& r,
                                          bool always);

}  // namespace oct
