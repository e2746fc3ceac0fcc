// The topology of a triangle scene as a tracer sees it: which triangles share an edge. Vertices
// are identified by their exact float coordinates (welded by position, -0 equal to +0), not by
// the file's indices: a watertight ray/triangle test (Woop, Benthin & Wald 2013) promises no
// crack between two triangles exactly where their shared endpoints are bit-identical, whatever
// the file's vertex list says (STL has none; OBJ/PLY often split vertices at UV seams).
//
// A mesh is closed when it is edge-manifold without boundary: every edge belongs to exactly two
// triangles. `octrace info` prints it; the edges/vertices ray sets (validation/rays/ray_sets.h)
// and the leak check of `octrace certify` (validation/certify.h) use the adjacency.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/scene/scene.h"

namespace oct {

struct MeshEdge {
    uint32_t a, b;           // welded vertex ids, a < b
    uint32_t triangles = 0;  // how many triangles use it
    uint32_t tri[2];         // the first two of them (primitive ids)
};

struct MeshTopology {
    // Welded vertices, numbered in order of first appearance over the triangles (primitive
    // order, corners v0, v1, v2): the ids `octrace certify` names a leak's edge by.
    std::vector<Vec3> vertices;
    std::vector<std::array<uint32_t, 3>> corners;  // per triangle: its welded vertex ids
    std::vector<MeshEdge> edges;                   // sorted by (a, b)
    // Per vertex, the triangles around it: vertexTriangles[vertexStart[v] .. vertexStart[v+1]).
    std::vector<uint32_t> vertexStart, vertexTriangles;
    uint64_t boundaryEdges = 0;     // in one triangle
    uint64_t nonManifoldEdges = 0;  // in three or more

    bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0 && !edges.empty(); }
    // The edge (a, b) in either order, or null.
    const MeshEdge* findEdge(uint32_t a, uint32_t b) const;
};

// Throws std::invalid_argument for a scene of spheres.
MeshTopology meshTopology(const Scene& scene);

// The link of vertex v: the cycle of its neighbours, each consecutive pair (and the last with
// the first) the far edge of one triangle around v. Empty when v is not a manifold interior
// vertex (on the boundary, on a non-manifold edge, or a pinch where two fans meet).
std::vector<uint32_t> vertexLink(const MeshTopology& topo, uint32_t v);

}  // namespace oct
