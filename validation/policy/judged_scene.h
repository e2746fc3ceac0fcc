// What validate's and certify's reports both begin with: the scene, its extent (the unit of the
// policy's tolerances) and the policy it was judged by. Both reports print it as one block
// (report/report_util.h).
#pragma once

#include <cstdint>
#include <string>

#include "core/scene/scene.h"
#include "validation/policy/hit_check.h"

namespace oct {

struct JudgedScene {
    std::string scene;
    PrimKind kind = PrimKind::Triangles;
    uint32_t primitives = 0;
    double extent = 0.0;
    ValidationPolicy policy;
};

inline JudgedScene judgedScene(const Scene& scene, const HitClassifier& c) {
    return {scene.name, scene.kind, scene.primitiveCount(), c.extent(), c.policy()};
}

}  // namespace oct
