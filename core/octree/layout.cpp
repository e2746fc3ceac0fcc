#include "core/octree/layout.h"

#include <limits>

namespace oct {

PrimitivesView primitivesView(const Scene& scene) {
    PrimitivesView v{};
    v.kind = scene.kind;
    v.count = scene.primitiveCount();
    v.tris = scene.kind == PrimKind::Triangles ? scene.triangles.data() : nullptr;
    v.spheres = scene.kind == PrimKind::Spheres ? scene.spheres.data() : nullptr;
    return v;
}

std::string mibText(uint64_t bytes) {
    if (bytes == std::numeric_limits<uint64_t>::max()) return "more than 2^64 bytes";
    return std::to_string(bytes / (1024 * 1024)) + " MiB (" + std::to_string(bytes) + " bytes)";
}

}  // namespace oct
