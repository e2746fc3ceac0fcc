// The box-test contract (docs/VALIDATION.md, "The box-test contract"): the two float tests
// every octree traversal rests on, checked against exact rational arithmetic on the canonical
// octree's own node boxes.
//
//  box       intersectBox (core/geometry/aabb.h): the linear and hash traversals' test of every
//            child, and the compact layout's root and quantised-bounds test;
//  children  compact_detail::childIntervals (core/octree/compact_octree.h): the compact
//            layout's eight children of an internal node in one go.
//
// For a ray o + t d and a closed box, "meets" means: some real t in [tmin, tmax] puts the point
// in the box. With tmin = 0 the contract is
//  conservative  an exact meet is never culled, touching (the exact interval a single t)
//                included: Ize's far-distance scaling (Ize 2013) exists for this;
//  tight         a ray that misses the box grown on every side by kBoxContractSlack of its edge
//                or of its distance from the origin (rounding is relative to t), whichever is
//                larger, is culled: rounding may widen the test, nothing else may.
// A finite tmax is checked only where its entry t is exact in float (axis directions, exact
// differences), because the kernel compares tmax with the rounded entry: a ray whose segment
// ends inside the rounding of its entry may go either way, and that changes a hit by rounding
// only.
//
// Rays are drawn so the hard cases occur by construction: origins on a face, edge or corner
// leaving the box (the exact interval is [0, 0]); segments that end exactly where they enter
// a box; rays through points within a few ulps of an edge or corner (grazing, either side);
// and rays in general position. The exact answer is GMP rational arithmetic on the stored
// floats (o, d, the box's bounds), not on the reciprocal the kernel computes.
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
