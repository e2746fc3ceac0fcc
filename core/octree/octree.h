// The canonical octree: what the host builder produces and what every layout of the registry
// is converted from (layout_registry.h). Host-only; kernels see the layouts' views.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/octree/node.h"
#include "core/octree/octree_limits.h"
#include "core/scene/scene.h"

namespace oct {

// Thrown for build parameters or sizes octrace cannot honour; the message says which value
// and what to do instead.
class OctreeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct BuildParams {
    // Defaults: deep enough that the bunny's leaves hold a handful of triangles, shallow enough
    // that the complete linear array (8^(d+1)-1)/7 * 48 bytes stays near 115 MB at d = 7.
    int maxDepth = 7;
    // A node with more than this many primitives is split (unless at maxDepth).
    uint32_t maxPrims = 8;
    // Leaf lists plus the level being built may hold at most this many references (2^30: 4 GiB
    // of indices); the build is refused while building the level that would exceed it.
    uint64_t maxReferences = uint64_t(1) << 30;
    // The tree may hold at most this many nodes (--node-budget); the build is refused while
    // building the level that would pass it, and also where that level's memory is more than
    // the machine has left (core/system/resources.h). Primitives that no split separates, such
    // as two triangles sharing an edge under --max-prims 1, split every cell along the edge
    // down to maxDepth, doubling the cells each level: 100 M nodes at depth 21. Those cells are
    // counted before the build (edge_bound.h), which refuses at once where they alone pass it.
    uint64_t maxNodes = kDefaultNodeBudget;
    // What the layouts the tree is built for can store (LayoutDesc::limitBuild), so that the
    // build refuses the first level past it before making that level, instead of building a
    // tree the layout then refuses: `render quad.obj --max-depth 21 --max-prims 1` built 2^25
    // nodes for 13 s before. Each with its refusal's reason, naming the options; the defaults
    // bound nothing.
    int storableDepth = kMaxOctreeDepth;
    uint64_t storableNodes = UINT64_MAX;
    std::string depthLimit{}, nodeLimit{};  // {}: BuildParams{depth, prims} names no others
    // From this many triangles on, the build reads them in a spatial order, for its caches
    // (builder.cpp, BuildOrder); the tree is the same node for node and list for list. Only
    // the tests that compare the two orders set it.
    uint32_t spatialOrderFrom = uint32_t(1) << 14;
};

struct Octree {
    Aabb root;  // a cube around the scene (or the generator's domain)
    PrimKind kind = PrimKind::Triangles;
    uint32_t primitiveCount = 0;  // primitives in the scene
    BuildParams params;           // as requested
    int effectiveMaxDepth = 0;    // maxDepth after clamping to a grid cloud's cell depth
    int depth = 0;                // deepest node present
    double buildSeconds = 0.0;

    // Nodes in breadth-first order, root at 0; the 8 children of an internal node are
    // adjacent, starting at firstChild[i] (kNoChild for leaves).
    std::vector<OctreeNode> nodes;
    std::vector<uint32_t> firstChild;
    // The one global array of leaf primitive lists (paper, sec. 4): leaf n owns
    // primIndices[n.primOffset, n.primOffset + n.primCount), ascending primitive ids.
    std::vector<uint32_t> primIndices;

    static constexpr uint32_t kNoChild = 0xffffffffu;

    // Sum of leaf list lengths: the paper's "octree faces" (Table 1, last column).
    uint64_t referenceCount() const { return primIndices.size(); }
};

// Root cube: the scene's box made cubic around its centre and padded by a relative 1e-4 so
// primitives on the scene's boundary are strictly inside; a grid cloud's domain is used as is.
Aabb rootCube(const Scene& scene);

// Builds the paper's octree on the host. A node holding more than maxPrims primitives and
// shallower than maxDepth is split into 8; a triangle goes into every child it overlaps
// (Akenine-Möller, tri_box.h), a sphere into every child whose box is within its radius.
// Beyond the paper, a node whose primitives no split could ever separate (all the same
// primitive, or all spheres containing the node) is not split: it stays a leaf (builder.cpp).
// Throws OctreeError for maxDepth outside [0, 21], maxPrims == 0, or an empty scene.
Octree buildOctree(const Scene& scene, const BuildParams& params);

// A triangle up to the order of its vertices: a copy of a face, possibly flipped, has the same.
// The builder keeps a node of copies of one face a leaf (no split separates them), and counts
// distinct triangles so (edge_bound.h).
std::array<std::array<float, 3>, 3> sortedVertices(const Triangle& t);

// Overlap tests exactly as the builder applies them, exposed for tests and validation.
bool builderTriangleOverlaps(const Triangle& tri, const Aabb& box);
bool builderSphereOverlaps(const Sphere& s, const Aabb& box);
// Arvo's test (Graphics Gems, 1990): squared distance, in double, from a sphere's centre to the
// nearest point of the box (0 inside it). Exact up to the final roundings for float inputs.
double sphereCentreBoxDistanceSq(const Sphere& s, const Aabb& box);

}  // namespace oct
