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

}  // namespace oct
