// The manifest `octrace rays` writes beside a ray file (R.npy -> R.json): what the rows are, so
// that `octrace certify` can report per set and rebuild each set's targets. A small JSON object:
//
//   {"format": "octrace-rays", "version": 1, "octrace": "0.1.0",
//    "scene": {"name": "meshes/teapot.obj", "kind": "triangles", "primitives": 992,
//              "radius": null, "fnv1a64": "5d1e..."},
//    "seed": 1, "count": 30000, "rows": 95211, "fnv1a64": "9c0d...",
//    "sets": [{"name": "camera", "begin": 0, "count": 65536}, ...],
//    "camera": {"width": 256, "height": 256, "fov": 45, "eye": null, "target": null, "up": null,
//               "light": null,
//               "frame": {"eye": [..], "forward": [..], "right": [..], "up": [..],
//                         "light": [..], "shadow_bias": ..}},
//    "expected_ambiguous": {"tracer": "octrace 0.1.0 linear (cpu)",
//                           "policy": {"t_tolerance": 1e-05, "edge_tolerance": 2e-06,
//                                      "grazing_cos": 0.001},
//                           "by_set": {"camera": 0, ..., "tmin-tmax": 845}}}
//
// `camera` is present when there is a camera or shadow set: the options as given (null: the
// default framing) and, for information, the frame they gave. `fnv1a64` is the 64-bit FNV-1a
// hash of R.npy's data (the rows' float32 little-endian bytes). `radius` is the sphere radius
// of a point cloud (null for meshes). The scene's `fnv1a64` is sceneFingerprint: the hash of its
// geometry as loaded (absent in manifests written before it). A manifest written by hand may
// name sets of its own: those are ranges only; sets with a standard name are rebuilt and must
// match byte for byte. `expected_ambiguous` (AmbiguityBaseline, ray_sets.h) is what octrace's
// own kernel scored on the rows when they were made, under that policy: certify bounds each
// set's ambiguous count by it. Absent in manifests written before it and in hand-written ones;
// when present it names every set and no other.
//
// The same scene: rays are certified against the scene they were made for, and "the same" is
// what the scene *is*, never how it was named (a relative path, another spelling, a symlink or
// a copy of the file is the same scene): the same kind, the same primitive count and, when the
// manifest has one, the same geometry fingerprint. So grid:1000 and grid:1000:2 (same count,
// same bounds, other points) are two scenes, and a mesh file edited since is another scene.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "validation/rays/ray_sets.h"

namespace oct {

const char* octraceVersion();  // the project's version (CMake's PROJECT_VERSION)

// A manifest is small (a few sets): a larger file is refused unread.
constexpr uint64_t kMaxManifestBytes = uint64_t(16) << 20;
// The most seeded rays (`octrace rays --count`): 8 floats a ray plus the answers of a tracer.
constexpr uint64_t kMaxSeededRays = 100000000;

struct RayManifest {
    std::string octrace;  // version that wrote it
    std::string scene;    // the scene as named on the command line
    std::string kind;     // "triangles" or "spheres"
    uint32_t primitives = 0;
    std::string fingerprint;      // sceneFingerprint; empty in an older manifest
    std::optional<float> radius;  // point clouds
    uint64_t seed = 0, count = 0, rows = 0;
    std::string checksum;  // hex64(fnv1a64(rays))
    std::vector<RaySetRange> sets;
    std::optional<CameraOptions> camera;
    std::optional<FrameParams> frame;           // informative only
    std::optional<AmbiguityBaseline> baseline;  // expected_ambiguous
};

// R.npy -> R.json; any other name gets ".json" appended.
std::string manifestPathFor(const std::string& raysPath);

// hex64 of the 64-bit FNV-1a of the scene's primitives as loaded, in primitive id order: each
// triangle's nine floats v0 v1 v2, each sphere's centre and radius (float32 little-endian).
std::string sceneFingerprint(const Scene& scene);

RayManifest describeRaySet(const Scene& scene, const RaySetSpec& spec, const RaySet& rays);
nlohmann::json toJson(const RayManifest& m);
// Throws IoError (one line, naming `path` and the field) for a field that is missing, of the
// wrong type or out of its range: primitives beyond 32-bit ids, count above kMaxSeededRays, a
// camera outside 1..kMaxImageSide or with a field of view outside (0, 180), a non-finite
// vector or radius.
RayManifest manifestFromJson(const nlohmann::json& j, const std::string& path);
// Reads (a regular file of at most kMaxManifestBytes, else refused unread) and parses; throws
// IoError naming the file.
RayManifest readManifest(const std::string& path);

// Checks the manifest against the ray file's `rows` before anything is built: the sets cover
// the rows in order, `rows` is the file's count, the camera set has width x height rows and
// every seeded standard set the share of `count` it was made with (so no manifest makes certify
// build more rows than the file has). Throws IoError naming the manifest, the set or field.
void checkManifestRows(const RayManifest& m, uint64_t rows, const std::string& raysPath);
// Throws IoError "these rays were made for ...; certify them against that scene" unless `scene`
// is the scene the manifest names, by the rule above.
void checkSameScene(const RayManifest& m, const Scene& scene, const std::string& raysPath);

// The ray file's rows as a RaySet: with a manifest, its sets (checkManifestRows, then the
// checksum and checkSameScene, all before anything is rebuilt) and, for every set with a
// standard name but shadow, the rows rebuilt from the manifest and compared with the file's,
// which also gives the edges/vertices targets; without one, a single set "all". Throws (one
// line, naming the file, the set and its rows) when the rows or the checksum disagree: the
// file was edited, or `scene` is not the scene it was made for. `notes` receives what was not
// rebuilt (shadow, sets of its own). `truth` (may be null) is a double truth of `scene` to seal
// the rebuilt targets with, so that certify builds one.
RaySet raySetFromFile(const Scene& scene, std::vector<float> rays,
                      const std::optional<RayManifest>& manifest, const std::string& raysPath,
                      std::vector<std::string>& notes, const DoubleTracer* truth = nullptr);

}  // namespace oct
