#include "python/scene_object.h"

namespace oct::python {

std::string SceneObject::structureKey(const LayoutDesc& layout, const BackendDesc& backend) {
    return backend.usesLayouts ? layout.name : "";
}

const BuiltScene& SceneObject::built(const LayoutDesc& layout, const BackendDesc& backend) {
    std::unique_ptr<BuiltScene>& slot = built_[structureKey(layout, backend)];
    if (!slot)
        slot = std::make_unique<BuiltScene>(
            backend.usesLayouts ? buildScene(scene_, layout, options_) : bareScene(scene_));
    return *slot;
}

SceneTracer& SceneObject::tracer(const LayoutDesc& layout, const BackendDesc& backend) {
    std::unique_ptr<SceneTracer>& slot = tracers_[{structureKey(layout, backend), backend.name}];
    if (!slot) slot = backend.prepare(built(layout, backend));
    return *slot;
}

}  // namespace oct::python
