// Scene loading: a file (by its extension, scene_formats.h) or a generator spec
// (scene_generators.h) in, a Scene of flat primitive arrays out. The invariant: nothing is
// dropped silently (every face or point left out is counted in scene.report), and every
// failure is one SceneError naming the path, the reason and what to do. What each format loads,
// drops and refuses is docs/ROBUSTNESS.md ("Per format"); how it is read, loader_detail.h.
// Safe to call from several threads (OpenMesh's readers, process-wide singletons, are locked).
#pragma once

#include <string>
#include <vector>

#include "core/geometry/numeric_range.h"
#include "core/scene/scene.h"

namespace oct {

// Loaded scenes lie in the numeric range (numeric_range.h): coordinates, extent, triangle
// areas and radii outside it are refused with the value and "rescale".

Scene loadScene(const std::string& path, const LoadOptions& opts = {});

// Scenes of the caller's arrays (the Python module's Scene.from_triangles and from_points), held
// to the files' rules, except that nothing is dropped: a row the loaders would drop (a
// non-finite coordinate, a triangle of zero area) is refused naming its row, since the caller
// numbers primitives by row and a dropped one would shift every id after it. Then the numeric
// range as loadScene. `name` names the scene in messages and reports; report.format is "array".
//   triangles: `count` rows of 9 floats, v0 v1 v2 (primitive id = row);
//   points:    `count` rows of 3 floats, spheres of opts.radius or defaultPointRadius.
Scene sceneFromTriangles(const float* rows, uint64_t count, const std::string& name);
Scene sceneFromPoints(const float* rows, uint64_t count, const LoadOptions& opts,
                      const std::string& name);

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
