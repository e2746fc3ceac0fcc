// What the regression set's checks (golden images, cost baselines) share: the frame of a scene,
// its views, reading JSON with one-line errors, and the frames of one scene by every layout and
// backend, from every view.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "core/octree/octree.h"
#include "core/render/film.h"
#include "core/render/frame.h"
#include "core/scene/scene.h"
#include "core/time_spread.h"

namespace oct {

// Check: compare the manifest's derived fields with this build. Update: rewrite them from this
// build, reporting what changed. Add: a new scene's, the others untouched.
enum class RegressionMode { Check, Update, Add };

// The fixed frame of one scene of the regression set (regression_manifest.h).
struct RegressionRender {
    int width = 128, height = 128;  // default camera (makeFrame) at this size
    BuildParams build;              // max depth, max prims
    float radius = 0.0f;            // point clouds; 0: the default rule
    // Every vertex multiplied by this as loaded (triangle meshes): the same scene at a very small
    // or very large absolute scale, where an epsilon in world units shows.
    double scale = 1.0;
};

nlohmann::json toJson(const RegressionRender& r);

// The camera of a view (regression_manifest.h, regressionViewNames): "default" is makeFrame's
// framing (from +z); "+x", "-x", "+y", "-y", "-z" the same framing from that side (up +y, or
// -z from +y and +z from -y); "inside" validate's inside view (insideViewCamera: the eye at the
// centre, the light just above it, so that shadow rays run with geometry beyond the light).
CameraOptions viewCamera(const std::string& view, const Scene& scene, int width, int height);

// A scene of the manifest `file`: resolved against `root` unless it is a generator spec; a
// missing file is an error naming the manifest and the root; scaled by render.scale (a point
// cloud with a scale other than 1 is refused).
Scene loadRegressionScene(const std::string& scene, const std::string& root,
                          const RegressionRender& render, const std::string& file);

// One frame per view and tracer: each layout of `layoutNames` (empty: every layout of the
// registry, in registry order) converted once and rendered from every view on each backend of
// `backends` (backends of our kernel, available here; empty: the host backend), tracer = the
// layout's name, backend = the backend's; then, with `embree`, for every view the reference
// backend's hits shaded by the same kernel (tracer and backend its name).
struct TracedFrame {
    std::string tracer;
    std::string backend;
    std::string view;
    bool usesLayouts = true;  // false: Embree (no traversal cost of ours)
    Film film;
};
std::vector<TracedFrame> renderRegressionFrames(const Scene& scene, const RegressionRender& render,
                                                const std::vector<std::string>& views,
                                                const std::vector<std::string>& layoutNames,
                                                bool embree,
                                                const std::vector<const BackendDesc*>& backends);

// Reading the regression manifest (regression_manifest.h): one-line IoErrors naming
// the file and the field; a path that is not a regular file, or a file above
// kMaxRegressionJsonBytes, is refused unread (core/io/input_file.h).
constexpr uint64_t kMaxRegressionJsonBytes = uint64_t(16) << 20;
nlohmann::json readRegressionJson(const std::string& path, const char* what);
namespace regression_detail {
[[noreturn]] void badField(const std::string& file, const char* name, bool missing);
template <class T>
T field(const nlohmann::json& j, const char* name, const std::string& file) {
    if (!j.is_object() || !j.contains(name)) badField(file, name, true);
    try {
        return j.at(name).get<T>();
    } catch (const nlohmann::json::exception&) {
        badField(file, name, false);
    }
}
}  // namespace regression_detail

}  // namespace oct
