// The box-test contract: the kernel's two float slab tests (intersectBox, core/geometry/aabb.h,
// and compact_detail::childIntervals, core/octree/compact_octree.h) checked against exact GMP
// rational arithmetic on the canonical octree's own node boxes. Conservative (an exact meet,
// touching included, is never culled) and tight (a ray missing the box grown by
// kBoxContractSlack is culled). The rules, the rays drawn and why: docs/VALIDATION.md, "The
// box-test contract".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/aabb.h"
#include "core/octree/octree.h"

namespace oct {

constexpr double kBoxContractSlack = 1e-4;

struct BoxContractReport {
    uint64_t rays = 0;                // rays drawn
    uint64_t tests = 0;               // float tests checked (box tests plus child lanes)
    uint64_t meets = 0;               // of them, exact meets
    uint64_t touching = 0;            // exact meets at a single t (t0 == t1 exactly)
    uint64_t culled = 0;              // exact meet, the float test said no: not conservative
    uint64_t loose = 0;               // misses the grown box, the float test said yes: not tight
    std::vector<std::string> errors;  // the first 16, each with the ray, the box and the test
    bool passes() const { return culled == 0 && loose == 0; }
};

// The float tests under contract, as plain functions: the kernel's by default; the tests hand
// in faulty ones to show the check catches them.
struct BoxTests {
    bool (*box)(const RaySlabs& s, const Aabb& b, float tmin, float tmax);
    uint32_t (*children)(const RaySlabs& s, const Aabb& parent, float tmin, float tmax);
};
BoxTests kernelBoxTests();  // intersectBox and compact_detail::childIntervals

// Draws `rays` rays (split over the kinds above) from `seed` against boxes of `canonical`'s
// nodes and checks both tests. Deterministic for a seed. An empty octree gives an empty report.
BoxContractReport checkBoxContract(const Octree& canonical, uint64_t rays, uint64_t seed,
                                   const BoxTests& tests = kernelBoxTests());

}  // namespace oct
