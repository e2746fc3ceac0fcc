// Scene loading: a file (or a generator spec) in, a Scene of flat primitive arrays out, with an
// account in scene.report of everything that was dropped on the way.
//
// Formats, chosen by the extension (case-insensitive) from the table of scene_formats.h:
//  - .obj .ply .off .stl: triangle meshes (OBJ, PLY and STL read through OpenMesh's readers into
//    our own importer, OFF by octrace itself), keeping every face in file order, including the
//    non-manifold and duplicated faces an OpenMesh mesh would reject. Polygons are
//    fan-triangulated (v0, vi, vi+1) in face order; triangle i came from file face
//    sourceFace[i]. Dropped and counted: faces with fewer than 3 vertices, faces with an index
//    that names no vertex, faces with a non-finite (or, in OBJ, unparsable) vertex coordinate,
//    and fan triangles of zero area (the cross product of two edges, computed in double from
//    the float vertices, is exactly the zero vector).
//  - .ply with vertices but no faces, and .xyz (whitespace-separated "x y z" per line, further
//    columns ignored, blank lines and lines starting with '#' skipped): point clouds, each
//    point a Sphere. Points with a non-finite coordinate are dropped and counted.
//  - a generator spec of scene_generators.h ("grid:N[:SEED]", the grid cloud of grid_cloud.h;
//    "slivers:N[:SEED]", the square of slivers.h; seed 1 by default), made, not read.
//
// A text file (any but a binary PLY, OFF or STL) may begin with a UTF-8 byte-order mark; it
// loads exactly as without it. docs/ROBUSTNESS.md lists, per format, what loads, what is
// dropped and counted, and what is refused.
//
// Sphere radius of point clouds: LoadOptions::radius when > 0, else defaultPointRadius().
//
// How the loaders read and check each format: loader_detail.h and the format_*.cpp files.
//
// Every failure is a SceneError with a one-line message naming the path, the reason and what to
// do: missing or unreadable file, a directory or other non-regular file, an unknown extension, a
// file OpenMesh cannot read or that its reader would misread, hang on or crash on, a header
// count the file's bytes cannot hold (checked before anything is sized from it), a truncated
// file, a scene outside the numeric range (below), or a scene left without a single usable
// primitive. Running out of memory is a SceneError too. docs/ROBUSTNESS.md lists the malformed
// inputs this is tested and fuzzed against (tests/data/bad/).
//
// Safe to call from several threads: reads through OpenMesh are serialised by a lock, because its
// readers are process-wide singletons with per-read state.
#pragma once

#include <string>
#include <vector>

#include "core/geometry/numeric_range.h"
#include "core/scene/scene.h"

namespace oct {

// Loaded scenes must lie in the numeric range of core/geometry/numeric_range.h, where the
// float32 tests (ours and Embree's) are correct: every coordinate (a sphere's centre plus its
// radius) within +-kMaxCoordinate (beyond it the cube of the coordinates in the triangle
// tests leaves float range and hits came back at t = +inf), an extent of at least
// kMinSceneExtent, twice every triangle's area at least kMinTriangleArea2 and every radius at
// least kMinSphereRadius (below them products of coordinates underflow: t = 0, or a triangle
// that can never be hit). Anything else is refused with the value and "rescale". Generated
// scenes lie in the unit cube by construction (grid_cloud.h, slivers.h).

Scene loadScene(const std::string& path, const LoadOptions& opts = {});

// Default sphere radius for a point cloud:
//   R = 0.5 x the median nearest-neighbour distance, taken over a deterministic sample of at most
//   10,000 points (all points when there are fewer; otherwise the points at indices
//   floor(i * n / 10000), i = 0 .. 9999). Each sample point's nearest neighbour is searched among
//   ALL points with a uniform hash grid, ignoring points at distance zero (exact duplicates), so
//   repeated points cannot force R to 0. The median of k distances is the element of rank
//   floor(k / 2) in ascending order. Spheres of this radius just touch their typical neighbour.
//   When there is a single point, or all points coincide, R = 1e-3 x the bounding-box diagonal,
//   or 1e-3 when that diagonal is 0. Points must be finite; an empty input gives 1e-3.
float defaultPointRadius(const std::vector<Vec3>& points);

}  // namespace oct
