// `octrace explain --svg F.svg --quadtree`: the idea of the paper's Figure 1 (Barboza & Clua
// 2011, Fig. 1: a quadtree's cells over a 2D scene, each named by its Morton key, and the
// cells a ray crosses) for a scene whose primitives all lie in one axis plane. The quadtree is
// built here, over that plane, with the octree's split rule (a node holding more than
// max-prims primitives is split until max-depth; core/octree/octree.h), and its keys are the
// hash octree's keys in 2D: the root is 1 and a child appends its 2-bit quadrant digit. The
// ray is traced through it as traverseOctree traces the octree (core/octree/traversal.h):
// children nearest first, a node entered beyond the closest hit dropped. Teaching code: the 2D
// counterpart of the octree, for the blackboard, not a layout octrace renders with.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/scene/scene.h"
#include "teach/svg.h"

namespace oct {

// The quadtree's Morton keys (Figure 1's cell names): root 1, key(child q of k) = 4k + q,
// quadrant digit q = (upper half in u) + 2 (upper half in v), as the octant digit is
// x + 2y + 4z (core/octree/morton.h). The leading 1 marks the depth.
constexpr uint64_t kQuadRootKey = 1;
inline uint64_t quadChildKey(uint64_t key, int quadrant) { return key << 2 | uint64_t(quadrant); }
int quadKeyDepth(uint64_t key);
// The key in base 4, one digit a level: "1" the root, "132" the root's quadrant 3's quadrant 2.
std::string quadKeyBase4(uint64_t key);
// The key in binary, "0b11110" (the same key: 1, then 2 bits a level).
std::string quadKeyBinary(uint64_t key);

// A cell of the plane: [u0, u1] x [v0, v1].
struct QuadCell {
    double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};
// Quadrant q of a cell split at its centre.
QuadCell quadChildCell(const QuadCell& c, int quadrant);

struct QuadNode {
    uint64_t key = kQuadRootKey;
    int depth = 0;
    QuadCell cell;
    uint32_t firstChild = kNoQuadChild;  // its 4 children are adjacent; kNoQuadChild: a leaf
    std::vector<uint32_t> prims;         // a leaf's primitives, ascending ids
    static constexpr uint32_t kNoQuadChild = 0xffffffffu;
    bool leaf() const { return firstChild == kNoQuadChild; }
};

struct Quadtree {
    AxisPlane plane;              // the scene's plane: u, v kept, w dropped at w = at
    BuildParams params;           // maxDepth and maxPrims as the octree's
    std::vector<QuadNode> nodes;  // breadth first, root at 0
    int depth = 0;                // deepest node
};

// A figure for a slide: a larger quadtree is refused (lower --max-depth or raise --max-prims).
constexpr size_t kMaxQuadtreeNodes = 1365;  // the complete quadtree of depth 5

// The axis plane holding every primitive exactly (every triangle corner, every sphere centre
// has the same w), xy before xz before yz; none when the scene is not flat.
std::optional<AxisPlane> flatPlaneOf(const Scene& scene);
// The plane of `octrace explain --quadtree`: the scene's flat plane; `planeOption`
// (--svg-plane, may be empty) must name it. TeachError naming --quadtree and the scene's
// extents when the scene is not flat, or --svg-plane and the scene's plane when it differs.
AxisPlane quadtreePlane(const Scene& scene, const std::string& planeOption);
// The square the octree's root cube (rootCube) covers in the plane: the quadtree's root, so
// its cells are the octree's cells cut by the plane.
QuadCell quadRootOf(const Scene& scene, const AxisPlane& plane);

// The octree's rule in 2D: a primitive belongs to every cell it overlaps (a triangle as a
// closed region of the plane, a sphere as its circle of centre and radius); a node with more
// than params.maxPrims primitives below params.maxDepth is split in 4, unless no split could
// separate them (all the same primitive, or all circles containing the cell), as buildOctree
// decides. TeachError past kMaxQuadtreeNodes nodes.
Quadtree buildQuadtree(const Scene& scene, const AxisPlane& plane, const QuadCell& root,
                       const BuildParams& params);

// A ray of the plane: origin (ou, ov), unit direction (du, dv), t a distance in the plane.
struct Ray2D {
    double ou = 0, ov = 0, du = 1, dv = 0;
    double tmin = 0, tmax = INFINITY;
};
// The 3D ray projected onto the plane (the ray itself when it lies in it), its direction
// normalised. TeachError when it runs along the dropped axis (it projects to a point).
Ray2D rayInPlane(const Ray& ray, const AxisPlane& plane);

enum class QuadEvent : uint8_t { Box, Skip, Pop, Prim };
// One step of the 2D traversal, as ExplainStep is one of the octree's (teach/explain.h).
struct QuadStep {
    QuadEvent event = QuadEvent::Box;
    uint32_t node = 0;  // Box, Skip, Pop: the node's index
    bool hit = false;   // Box: met; Pop: visited (false: dropped); Prim: hit
    double t = 0;       // Box met, Pop: t enter; Prim hit: t
    uint32_t prim = 0;  // Prim
};
struct QuadTrace {
    Ray2D ray;
    std::vector<QuadStep> steps;
    std::vector<uint32_t> visits;  // nodes visited, in visit order
    int64_t hitPrim = -1;          // the closest hit (ties to the lower id); -1: none
    double hitT = INFINITY;
};
QuadTrace traceQuadtree(const Quadtree& q, const Scene& scene, const Ray2D& ray);

// The figure: every cell with its key written in it (base 4), the visited ones coloured and
// numbered in visit order, the primitives, the ray and its hit; `title` and `query` head it.
std::string quadtreeSvg(const Quadtree& q, const QuadTrace& trace, const Scene& scene,
                        const std::string& title, const std::string& query);

}  // namespace oct
