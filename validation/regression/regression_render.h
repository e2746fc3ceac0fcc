// What the regression files (golden images, cost baselines) share: the fixed frame they pin,
// reading their JSON with one-line errors, and the frames of one scene by every layout. Both
// files are checked against this build or rewritten from it (RegressionMode) by one skeleton
// each: read the file, render each scene it lists, compare or rewrite.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "core/octree/octree.h"
#include "core/render/film.h"

namespace oct {

// Check: compare the file with this build. Update: rewrite it from this build, reporting what
// changed.
enum class RegressionMode { Check, Update };

// The fixed frame of the regression files (golden images and cost baselines).
struct RegressionRender {
    int width = 128, height = 128;  // default camera (makeFrame) at this size
    BuildParams build;              // max depth, max prims
    float radius = 0.0f;            // point clouds; 0: the default rule
};

RegressionRender regressionRenderFromJson(const nlohmann::json& j, const std::string& file);
nlohmann::json toJson(const RegressionRender& r);

// One frame of a scene per tracer: every layout of the registry on each backend of `backends`
// (backends of our kernel, available here; empty: the backend list's host backend), layouts in
// registry order, each converted once and rendered on the backends in list order (tracer = the
// layout's name, backend = the backend's),
// then, with `embree`, the reference backend's hits shaded by the same kernel (tracer and
// backend its name). `scene` is resolved against `root` unless it is a generator spec; a
// missing file is an error naming the listing `file` and the root.
struct TracedFrame {
    std::string tracer;
    std::string backend;
    bool usesLayouts = true;  // false: Embree (no traversal cost of ours)
    Film film;
};
std::vector<TracedFrame> renderRegressionFrames(
    const std::string& scene, const std::string& root, const RegressionRender& render, bool embree,
    const std::string& file, const std::vector<const BackendDesc*>& backends = {});

// Reading the regression files (golden.json, cost_baselines.json): one-line IoErrors naming
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

inline double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace oct
