// The manifest `octrace rays` writes beside a ray file (R.npy -> R.json): what the rows are, so
// that `octrace certify` can report per set and rebuild each set's targets. A small JSON object:
//
//   {"format": "octrace-rays", "version": 1, "octrace": "0.1.0",
//    "scene": {"name": "meshes/teapot.obj", "kind": "triangles", "primitives": 992,
//              "radius": null},
//    "seed": 1, "count": 30000, "rows": 95211, "fnv1a64": "9c0d...",
//    "sets": [{"name": "camera", "begin": 0, "count": 65536}, ...],
//    "camera": {"width": 256, "height": 256, "fov": 45, "eye": null, "target": null, "up": null,
//               "light": null,
//               "frame": {"eye": [..], "forward": [..], "right": [..], "up": [..],
//                         "light": [..], "shadow_bias": ..}}}
//
// `camera` is present when there is a camera or shadow set: the options as given (null: the
// default framing) and, for information, the frame they gave. `fnv1a64` is the 64-bit FNV-1a
// hash of R.npy's data (the rows' float32 little-endian bytes). `radius` is the sphere radius
// of a point cloud (null for meshes). A manifest written by hand may name sets of its own:
// those are ranges only; sets with a standard name are rebuilt and must match byte for byte.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "validation/rays/ray_sets.h"

namespace oct {

const char* octraceVersion();  // the project's version (CMake's PROJECT_VERSION)

struct RayManifest {
    std::string octrace;  // version that wrote it
    std::string scene;    // the scene as named on the command line
    std::string kind;     // "triangles" or "spheres"
    uint32_t primitives = 0;
    std::optional<float> radius;  // point clouds
    uint64_t seed = 0, count = 0, rows = 0;
    std::string checksum;  // hex64(fnv1a64(rays))
    std::vector<RaySetRange> sets;
    std::optional<CameraOptions> camera;
    std::optional<FrameParams> frame;  // informative only
};

// R.npy -> R.json; any other name gets ".json" appended.
std::string manifestPathFor(const std::string& raysPath);

RayManifest describeRaySet(const Scene& scene, const RaySetSpec& spec, const RaySet& rays);
nlohmann::json toJson(const RayManifest& m);
// Throws IoError (one line, naming `path`) for a field that is missing or of the wrong type.
RayManifest manifestFromJson(const nlohmann::json& j, const std::string& path);
// Reads and parses; throws IoError naming the file.
RayManifest readManifest(const std::string& path);

// The ray file's rows as a RaySet: with a manifest, its sets (checked to cover the rows in
// order) and, for every set with a standard name but shadow, the rows rebuilt from the
// manifest and compared with the file's, which also gives the edges/vertices targets; without
// one, a single set "all". Throws std::runtime_error (one line, naming the file, the set and
// its rows) when the rows or the checksum disagree: the file was edited, or `scene` is not
// the scene it was made for. `notes` receives what was not rebuilt (shadow, sets of its own).
RaySet raySetFromFile(const Scene& scene, std::vector<float> rays,
                      const std::optional<RayManifest>& manifest, const std::string& raysPath,
                      std::vector<std::string>& notes);

}  // namespace oct
