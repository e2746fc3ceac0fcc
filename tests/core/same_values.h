// Comparisons the core tests share (the test binaries are unity builds: a helper defined in two
// files of one batch would be defined twice).
#pragma once

#include "core/geometry/vec3.h"

namespace octtest {

// Equal component by component (+0 equals -0; a NaN equals nothing).
inline bool sameVec(oct::Vec3 a, oct::Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

}  // namespace octtest
