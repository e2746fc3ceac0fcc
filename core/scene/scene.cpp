#include "core/scene/scene.h"

#include <cmath>

namespace oct {

Aabb Scene::bounds() const {
    Aabb box = emptyAabb();
    if (kind == PrimKind::Triangles) {
        for (const Triangle& t : triangles) {
            grow(box, t.v0);
            grow(box, t.v1);
            grow(box, t.v2);
        }
    } else {
        for (const Sphere& s : spheres) {
            grow(box, s.center - makeVec3(s.radius));
            grow(box, s.center + makeVec3(s.radius));
        }
    }
    return box;
}

double sceneExtent(const Scene& scene) {
    Aabb b = scene.bounds();
    Vec3 e = b.extent();
    double d = std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
    return d > 0.0 && std::isfinite(d) ? d : 1.0;
}

}  // namespace oct
