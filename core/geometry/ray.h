// What every tracer exchanges: a ray segment, its closest hit, and the work a query cost. Plain
// OCT_HD structs, so the camera, the kernels, Embree's adapter and the double-precision truth
// share them without seeing any acceleration structure.
#pragma once

#include <cstdint>

#include "core/geometry/vec3.h"

namespace oct {

// The segment org + t * dir, t in [tmin, tmax] (both ends included). 32 bytes.
struct Ray {
    Vec3 org;
    Vec3 dir;
    float tmin;
    float tmax;
};

struct Hit {
    float t;       // +inf on a miss
    int32_t prim;  // -1 on a miss
};

// Work done for one query: the paper's cost measure, reported per pixel in the Film.
struct TraceCost {
    uint32_t nodesVisited;  // node boxes tested
    uint32_t primsTested;   // ray-primitive tests
};

OCT_HD inline Hit missHit() { return {INFINITY, -1}; }

// The answer of a traversal that found its structure inconsistent (a child whose key is not its
// parent's child key, a record or list entry outside its array, a stack that would overflow):
// never a plausible hit, so a faulty kernel or a corrupted layout makes validation and
// certification FAIL (a primitive id below -1 is malformed: invalid_hit, docs/VALIDATION.md)
// instead of reading out of bounds or looping. A correct structure never produces it.
constexpr int32_t kTraversalFault = -2;
OCT_HD inline Hit faultHit() { return {INFINITY, kTraversalFault}; }

}  // namespace oct
