// Golden images: regression of the whole per-pixel kernel, shading included. The scenes of the
// regression set (regression_manifest.h) are rendered at a small size from their views and
// compared per pixel with images committed beside the manifest (tests/data/regression/), so
// that a faulty kernel is caught even where every hit is right (a sign in Phong, a dropped
// shadow ray, a wrong normal). docs/VALIDATION.md ("Golden images") has the tolerance rule
// and why. This file holds the comparison and its report; regression_run.h runs the set.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/render/film.h"
#include "validation/regression/regression_render.h"

namespace oct {

// Per-pixel difference of two RGB8 images of the same size: d(pixel) = the largest absolute
// difference of its three channels, in 1/255 steps; `over` counts d > `channel`.
struct ImageDiff {
    bool sizeMismatch = false;
    uint64_t pixels = 0;
    uint64_t differing = 0;  // d > 0
    uint64_t over = 0;       // d > channel
    int maxDiff = 0;
    int worstX = -1, worstY = -1;  // first pixel with d == maxDiff (when maxDiff > 0)
};
ImageDiff compareImages(int width, int height, const std::vector<uint8_t>& golden,
                        const std::vector<uint8_t>& rgb, int channel);

// The pass rule (docs/VALIDATION.md, "Golden images"): at most `maxOverFraction` of the pixels
// may differ by more than `channel` levels, and none by more than `maxDiff` levels. By default
// there is no cap on a single pixel: what another build or Embree legitimately changes is
// either rounding (1 level) or an isolated flip (hit/miss at a silhouette, lit/occluded at a
// shadow edge), large in colour but rare; a shading fault changes many pixels.
struct GoldenTolerance {
    int channel = 1;
    double maxOverFraction = 5e-4;  // 8 pixels of 128 x 128
    int maxDiff = 255;              // 255: no cap
    bool passes(const ImageDiff& d) const;
};

// The pixels of a failing comparison, for the artefacts (validation/regression/artifacts.h):
// the frame rendered and the golden image, RGB8 row-major.
struct GoldenImages {
    int width = 0, height = 0;              // the frame's
    int goldenWidth = 0, goldenHeight = 0;  // the golden image's (they differ on a size
                                            // mismatch)
    std::vector<uint8_t> actual, golden;
};

struct GoldenRow {
    std::string scene, view, file, tracer, backend;
    RegressionRender render;    // the frame's size and tree
    GoldenTolerance tolerance;  // the backend's rule
    ImageDiff diff;
    bool missing = false;  // the manifest has no image for this frame: --update
    bool pass = false;
    GoldenImages images;  // only for a failing row of a check (empty otherwise)
};

// Compares a rendered frame with its golden image under `tolerance` (keeps the pixels of a
// failing row for the artefacts).
GoldenRow judgeImage(GoldenRow row, const Film& frame, int goldenWidth, int goldenHeight,
                     const std::vector<uint8_t>& golden);

struct GoldenReport {
    std::string manifest;
    std::string goldenVersion;  // the octrace version that wrote the images
    bool updated = false;       // rows compare the new images with the old ones (update mode)
    std::vector<GoldenRow> rows;
    double seconds = 0.0;

    uint64_t failures() const;  // 0 in update mode
    bool passes() const { return failures() == 0; }
};

nlohmann::json toJson(const GoldenReport& r);
std::string humanSummary(const GoldenReport& r);

// Decodes a PNG to RGB8 (stb_image); throws IoError naming `path` and what to do, also for a
// path that is not a regular file or a file above kMaxGoldenPngBytes (refused unread).
constexpr uint64_t kMaxGoldenPngBytes = uint64_t(256) << 20;
std::vector<uint8_t> readPngRgb(const std::string& path, int& width, int& height);

}  // namespace oct
