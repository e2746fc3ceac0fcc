// octrace.Scene: a loaded scene with the octree options it was made with, and what tracing it
// builds kept for the next call (the octree and layout of each layout asked for, each backend
// prepared on it: Embree's BVH, a CUDA upload), so that a loop of cast_rays calls builds once.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "core/backend/backend.h"
#include "core/octree/built_scene.h"
#include "core/scene/scene.h"

namespace oct::python {

class SceneObject {
public:
    SceneObject(Scene scene, const LayoutOptions& options)
        : scene_(std::move(scene)), options_(options) {}
    SceneObject(const SceneObject&) = delete;
    SceneObject& operator=(const SceneObject&) = delete;

    const Scene& scene() const { return scene_; }
    const LayoutOptions& options() const { return options_; }

    // The scene built for `layout` (the bare scene for a backend with its own structure),
    // built on first use. Callers hold lock() while they use it.
    const BuiltScene& built(const LayoutDesc& layout, const BackendDesc& backend);
    // `backend` prepared on built(layout, backend), on first use.
    SceneTracer& tracer(const LayoutDesc& layout, const BackendDesc& backend);
    // One call at a time traces a scene (the caches above are not shared between threads); the
    // GIL is released meanwhile, so other scenes trace in parallel.
    std::unique_lock<std::mutex> lock() { return std::unique_lock<std::mutex>(mutex_); }

private:
    // The cache key: the layout's name, or "" for a backend that traces the bare scene.
    static std::string structureKey(const LayoutDesc& layout, const BackendDesc& backend);

    Scene scene_;  // never moved after construction: built scenes point into it
    LayoutOptions options_;
    std::mutex mutex_;
    std::map<std::string, std::unique_ptr<BuiltScene>> built_;
    std::map<std::pair<std::string, std::string>, std::unique_ptr<SceneTracer>> tracers_;
};

}  // namespace oct::python
