// Replication check of the canonical octree: for every primitive, the set of leaves the builder
// listed it in against the set of leaves it truly overlaps, by an exact reference (CGAL, see
// exact_overlap.h) and by a double-precision Akenine-Möller test.
//
// Cost: not every primitive against every leaf. Each primitive walks the tree from the root
// and descends only into nodes it overlaps (by either reference), which finds every leaf it
// overlaps because a node's box contains its children's; the leaves the builder listed it in
// come from an inverse index of the leaf lists. Parallel over primitives (OpenMP).
//
// A false negative (a leaf the primitive truly overlaps but is not listed in) loses hits and
// fails the check; a false positive (listed, not overlapping) costs only time and is counted
// with its gap (exact_overlap.h) relative to the leaf's edge.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/scene/scene.h"

namespace oct {

struct ReplicationEntry {
    uint32_t prim = 0;
    uint32_t node = 0;     // index into Octree::nodes
    uint64_t leafKey = 0;  // Morton key of the leaf
    int depth = 0;
    double gap = 0.0;  // false positives: gap / leaf edge (0 for false negatives)
};

// One overlap test judged against another, over (primitive, leaf) pairs.
struct ReferenceAgreement {
    uint64_t overlaps = 0;        // pairs the judged test says overlap
    uint64_t falseNegatives = 0;  // the reference says overlap, the judged test says no
    uint64_t falsePositives = 0;  // the judged test says overlap, the reference says no
};

// The builder widens each box by 1e-9 of its half-size before its overlap test (builder.cpp,
// kOverlapPad), so a listed primitive that does not overlap the box exactly lies within 0.5e-9
// of the leaf's edge of it. A false positive farther than this (relative to the leaf's edge;
// twice the padding, a margin for the rounding of the gap's own computation) is not rounding:
// the builder's test is wrong there (a dropped separating axis gives gaps of whole cells), and
// it fails the check. A touching configuration (gap 0) is never a false positive.
constexpr double kMaxFalsePositiveGap = 1e-9;

struct ReplicationReport {
    uint64_t primitives = 0;
    uint64_t leaves = 0;       // leaf and empty-leaf nodes
    uint64_t octreeFaces = 0;  // sum of leaf list lengths (the paper's Table 1 column)
    uint64_t exactOverlaps = 0;
    uint64_t falseNegatives = 0;  // builder vs exact: fails the check
    uint64_t falsePositives = 0;  // builder vs exact: counted
    // False positives by gap / leaf edge: <= 1e-12, <= 1e-9, <= 1e-6, <= 1e-3, larger.
    std::array<uint64_t, 5> falsePositiveGaps{};
    double maxFalsePositiveGap = 0.0;    // relative to the leaf's edge
    uint64_t wideFalsePositives = 0;     // gap > kMaxFalsePositiveGap: fails the check
    ReferenceAgreement doublePrecision;  // the unpadded double Akenine-Möller test vs exact
    ReferenceAgreement builderVsDouble;  // the builder's lists vs the unpadded double test
    // Structural problems of the leaf lists (any fails the check).
    uint64_t indexOutOfRange = 0;     // an entry naming no primitive
    uint64_t duplicateEntries = 0;    // a primitive listed twice in one leaf
    uint64_t unlistedPrimitives = 0;  // primitives in no leaf at all
    // Nodes whose ranges point outside the tree's arrays: a leaf's list [primOffset,
    // primOffset + primCount) beyond primIndices, or an internal node's children [firstChild,
    // firstChild + 8) beyond nodes or not after the node (the order is breadth-first). Such a
    // node is not read through (its list counts as empty, its children are not visited).
    uint64_t rangeErrors = 0;
    // Nodes whose box, key or depth is not what the subdivision makes of its parent's (the
    // root: not the tree's root cube): childBox(parent box, octant) bit for bit, childKey,
    // depth + 1. A stored box that is not the cell the lists were made for loses hits that
    // the lists alone cannot show. Any fails the check; named in structuralErrors.
    uint64_t tilingErrors = 0;
    std::vector<std::string> structuralErrors;  // the first range errors, naming the node (32)
    // Replication count (leaves a primitive is listed in) -> number of primitives.
    std::map<uint32_t, uint64_t> distribution;
    uint32_t maxReplication = 0;
    double meanReplication = 0.0;
    std::vector<ReplicationEntry> falseNegativeList;  // first ones, by primitive (up to 32)
    std::vector<ReplicationEntry> falsePositiveList;  // largest gaps (up to 16)
    uint64_t exactTests = 0;                          // CGAL do_intersect calls
    double seconds = 0.0;

    bool passes() const {
        return falseNegatives == 0 && wideFalsePositives == 0 && indexOutOfRange == 0 &&
               duplicateEntries == 0 && rangeErrors == 0 && tilingErrors == 0;
    }
};

// Throws std::invalid_argument when the tree was not built over this scene (kind or count).
ReplicationReport checkReplication(const Scene& scene, const Octree& tree);

}  // namespace oct
