// The regression set's one manifest (tests/data/regression/regression.json): which scenes are
// rendered, at what size, by which layouts, from which views, on which backends, held to which
// tolerances, and what each frame produced (its golden image, its cost per layout). Golden
// images and cost baselines are read from it and written into it; docs/VALIDATION.md
// ("The regression set") describes every field and the two commands that add a scene.
//
//   {"format": "octrace-regression", "version": 2, "octrace": "0.1.0",
//    "backends": ["cpu"],
//    "tolerances": {"golden": {"cpu": {"channel": 0, "max_over_fraction": 0, "max_diff": 0},
//                              "embree": {"channel": 1, "max_over_fraction": 0.0005,
//                                         "max_diff": 255}},
//                   "cost": 0.05},
//    "defaults": {"width": 128, "height": 128, "max_depth": 7, "max_prims": 8, "radius": 0,
//                 "layouts": "all", "views": ["default"]},
//    "scenes": [
//      {"scene": "meshes/teapot.obj", "views": ["default", "+y", "inside"],    <- written by you
//       ("name": "teapot-97x61", "width": 97, "height": 61, "layouts": ["hash"], ...)
//       "frames": [{"view": "default", "image": "teapot.obj.png", "pixels": 16384,  <- derived
//                   "cost": {"linear": {"boxes_tested": 1, "prims_tested": 2,
//                                       "boxes_per_pixel": ..., "prims_per_pixel": ...},
//                            ...}}, ...]}]}
// (version 1, still read: "nodes", "prims", "nodes_per_pixel" for the cost; --update writes 2)
//
// A scene entry may override any field of `defaults` (a frame that is not square, a single-leaf
// or a deep tree, only the layouts that can hold it). `frames`, `octrace` and the images are
// derived: `validate --regression FILE --update` (every scene) or `--regression-add SCENE`
// (one new scene) fill them; a file without them fails the check as `missing`.
//
// Tolerances: `golden` per backend name (ours by their names, the reference by "embree"); a
// backend not listed gets the code's ceiling, and a file may tighten a rule but never loosen it
// past the ceiling (kGoldenCeiling, kCostTolerance): a file that could loosen its own check
// would not be a check.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "validation/regression/cost_baseline.h"
#include "validation/regression/golden.h"
#include "validation/regression/regression_render.h"

namespace oct {

// The ceiling of every backend's golden rule (docs/VALIDATION.md, "Golden images"): at most
// 0.05 % of the pixels over 1/255.
inline GoldenTolerance goldenCeiling() { return GoldenTolerance{}; }

// The views a frame may be rendered from (regression_render.h, viewCamera).
const std::vector<std::string>& regressionViewNames();
bool isRegressionView(const std::string& view);

// One frame of a scene: what the manifest says it produced (absent until --update / --add).
struct RegressionFrame {
    std::string view;
    std::string image;  // file name next to the manifest
    uint64_t pixels = 0;
    std::map<std::string, CostTotals> cost;  // by layout name
};

// What a scene entry may set; unset fields take the manifest's defaults.
struct SceneSettings {
    std::optional<int> width, height, maxDepth;
    std::optional<uint32_t> maxPrims;
    std::optional<float> radius;
    std::optional<double> scale;  // every vertex times this (triangle meshes; default 1)
    std::optional<std::vector<std::string>> layouts;  // names; absent: every layout
    std::optional<std::vector<std::string>> views;
};

struct RegressionScene {
    std::string scene;  // as on the command line (relative to the repository root, or grid:N)
    // The entry's name, for one scene listed in several configurations (a frame that is not
    // square, a single-leaf tree): its images are named after it. Absent: the scene's file name
    // (regressionEntryName).
    std::optional<std::string> name;
    SceneSettings own;  // the entry's overrides, written back as they were
    std::vector<RegressionFrame> frames;
};

struct RegressionManifest {
    std::string path;     // where it was read from (names in errors; images live beside it)
    std::string octrace;  // the version that wrote the derived fields
    std::vector<std::string> backends;              // names, as in the file
    std::map<std::string, GoldenTolerance> golden;  // by backend name
    double costTolerance = kCostTolerance;
    SceneSettings defaults;  // every field set
    std::vector<RegressionScene> scenes;

    // The settings of one scene: its overrides over the defaults.
    RegressionRender render(const RegressionScene& s) const;
    std::vector<std::string> layouts(const RegressionScene& s) const;  // empty: every layout
    std::vector<std::string> views(const RegressionScene& s) const;
    GoldenTolerance goldenTolerance(const std::string& backend) const;
    std::string dir() const;                                     // the folder of the images
    const RegressionScene* find(const std::string& name) const;  // by regressionEntryName
};

// Reads and checks the manifest: one-line IoErrors naming the file and the field (unknown
// layout or view, a tolerance past the ceiling, two frames with one image name); the images are
// read when checked.
RegressionManifest readRegressionManifest(const std::string& path);
nlohmann::json toJson(const RegressionManifest& m);

// A name for a file beside the manifest: letters, digits, '.', '-', '_', '+', at most 200, not
// starting with '.' (so that no name written on --update leaves the folder).
bool isPlainName(const std::string& name);

// An entry's name: its own, or the scene's file name (a generator spec with ':' as '-').
std::string regressionEntryName(const std::string& scene, const std::optional<std::string>& name);
// The image file of an entry's view: its name, then "-VIEW" for a view other than the default
// ("+y" spelled "ypos", "-y" "yneg"), then ".png".
std::string regressionImageName(const std::string& entryName, const std::string& view);

}  // namespace oct
