#include "core/scene/scene.h"

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

}  // namespace oct
