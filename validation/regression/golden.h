// Golden images: regression of the whole per-pixel kernel, shading included. The committed
// scenes are rendered at a small size with the default camera and compared per pixel with
// images committed under tests/data/golden/, so that a faulty kernel is caught even where
// every hit is right (a sign in Phong, a dropped shadow ray, a wrong normal). docs/VALIDATION.md
// ("Golden images") has the tolerance rule and why.
//
// The folder holds golden.json and one PNG per scene:
//
//   {"format": "octrace-golden", "version": 1, "octrace": "0.1.0",
//    "render": {"width": 128, "height": 128, "camera": "default", "max_depth": 7,
//               "max_prims": 8, "radius": 0},
//    "images": [{"scene": "meshes/teapot.obj", "file": "teapot.obj.png"}, ...]}
//
// `scene` is as on the command line (a path relative to the repository root, or grid:N:SEED);
// `radius` 0 is the default point radius rule; `octrace` is the version that wrote the images.
// The render options are fixed by the file; the tolerance is fixed by the code (a file that
// could loosen its own check would not be a check).
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
    std::string scene, file, tracer, backend;
    ImageDiff diff;
    bool pass = false;
    GoldenImages images;  // only for a failing row of a check (empty otherwise)
};

struct GoldenReport {
    std::string dir;
    std::string goldenVersion;  // the octrace version that wrote the images
    RegressionRender render;
    GoldenTolerance tolerance;
    bool updated = false;  // rows compare the new images with the old ones (update mode)
    std::vector<GoldenRow> rows;
    double seconds = 0.0;

    uint64_t failures() const;
    bool passes() const { return failures() == 0; }
};

// Reads DIR/golden.json and checks every image against every tracer. Throws (one line, naming
// the file) on a missing or malformed manifest or image.
// `backends`: those of our kernel to render with (renderRegressionFrames; empty: the host's).
GoldenReport checkGolden(const std::string& dir, const std::string& root, bool embree = true,
                         const GoldenTolerance& tolerance = {},
                         const std::vector<const BackendDesc*>& backends = {});

// Re-renders every image of DIR/golden.json and writes the PNGs and the manifest (with this
// build's version), all or none. The layouts must agree bit for bit (else nothing is written:
// a golden image that depends on the layout is not one). Rows compare each new image with the
// old one (a missing old image counts as every pixel changed), so the report says what changed.
GoldenReport updateGolden(const std::string& dir, const std::string& root);

nlohmann::json toJson(const GoldenReport& r);
std::string humanSummary(const GoldenReport& r);

// Decodes a PNG to RGB8 (stb_image); throws IoError naming `path` and what to do, also for a
// path that is not a regular file or a file above kMaxGoldenPngBytes (refused unread).
constexpr uint64_t kMaxGoldenPngBytes = uint64_t(256) << 20;
std::vector<uint8_t> readPngRgb(const std::string& path, int& width, int& height);

}  // namespace oct
