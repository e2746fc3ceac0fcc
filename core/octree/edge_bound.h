// A lower bound on the octree's nodes found before the build: the cells along an edge that more
// than --max-prims triangles share. Host-only (the builder's pre-flight, builder.cpp).
//
// Why: two triangles sharing a diagonal under --max-prims 1 split every cell along the diagonal
// down to --max-depth, doubling the cells each level. The builder's node budget is checked
// level by level, so such a tree is refused only after most of it was built: `info quad.obj
// --max-depth 21 --max-prims 1` with the default budget of 2^25 nodes ran 27-33 s first. The
// cells along a shared edge can be counted without building anything else, and a count past
// the budget refuses the build up front.
//
// Why it is a lower bound: the builder lists a triangle in every cell whose closed float box it
// meets (builderTriangleOverlaps never loses an overlap: TriBox.BuilderTestHasNoFalseNegatives
// and the exact touching cases of TriBox.ExactAgreementOnDyadicGridIncludingTouching). A cell
// that holds the T > maxPrims distinct triangles of an edge is therefore split (they are not all
// one primitive, so no rule keeps it a leaf), and each of its children whose closed box meets
// the edge holds all T again. Counting only cells whose box certainly meets the edge (decided in
// exact integer arithmetic where doubles cannot tell) and whose boxes are made by the builder's
// own float childBox, every cell counted is a cell the builder makes: the count never exceeds
// the tree's nodes.
#pragma once

#include <cstdint>
#include <optional>

#include "core/geometry/aabb.h"
#include "core/scene/scene.h"

namespace oct {

struct SharedEdge {
    Vec3 a, b;               // the edge's end points, as the triangles give them
    uint32_t triangles = 0;  // distinct triangles that have it as an edge
};

struct EdgeNodeCount {
    uint64_t nodes = 0;   // nodes certainly built along the edge, the root included
    bool passed = false;  // counting stopped because nodes passed the limit
};

// Nodes the builder certainly makes along the segment a-b held by more than maxPrims triangles,
// the root included: every cell meeting the segment at depth < splitDepth is split into 8.
// Counting stops once the count passes `limit`. Cells whose meeting cannot be decided exactly
// (coordinates needing more than 60 bits on a common scale) are left out, which only lowers the
// bound.
EdgeNodeCount nodesAlongEdge(const Aabb& root, Vec3 a, Vec3 b, int splitDepth, uint64_t limit);

struct SharedEdgeBound {
    SharedEdge edge;
    uint64_t nodes = 0;  // more than the limit it was counted against
};

// The first edge of the scene's triangles, longest first, shared by more than maxPrims distinct
// triangles whose cells pass `limit` nodes, with cells split down to splitDepth; nullopt when
// none does (or none can: edges too short to pass the limit at that depth are not counted).
std::optional<SharedEdgeBound> sharedEdgePastLimit(const Scene& scene, const Aabb& root,
                                                   uint32_t maxPrims, int splitDepth,
                                                   uint64_t limit);

}  // namespace oct
