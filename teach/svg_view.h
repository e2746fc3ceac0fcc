// `octrace explain --svg`: one explained ray as a 2D figure for a slide. The cells the
// traversal tested are cut by (projected onto) an axis plane that holds the ray, drawn as
// rectangles: visited cells numbered in visit order and coloured by it (viridis), leaves solid,
// internal cells dashed, cells not entered (missed, or dropped beyond the hit) faint; the
// octree's leaf cells that the plane cuts as a light grid behind them; the primitives the ray
// tested, projected; the ray, its shadow ray and the hit. Everything is read from the
// Explanation's steps (teach/explain.h): the figure draws the kernel's own traversal and
// re-traces nothing.
#pragma once

#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/scene/scene.h"
#include "teach/explain.h"
#include "teach/svg.h"

namespace oct {

// How a tested cell is drawn.
enum class CellRole : uint8_t {
    VisitedLeaf,      // popped and visited; its primitives were tested
    VisitedInternal,  // popped and visited; its children were tested
    Dropped,          // met, not visited: entered beyond the closest hit, or culled (compact
                      // bounds), or never popped
    Missed,           // its box test failed
};

// A tested cell in plane coordinates: [u0, u1] x [v0, v1] is its box with axis w dropped.
struct PlaneCell {
    uint64_t key = 0;
    int depth = 0;
    size_t step = 0;  // 1-based step of its box test
    CellRole role = CellRole::Missed;
    int visit = 0;  // 1..n in visit order; 0: not visited
    double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};

// A projected primitive the ray tested: a triangle's three corners, or a sphere's centre and
// radius.
struct PlanePrim {
    uint32_t id = 0;
    bool hit = false;  // the primary ray's closest hit
    bool sphere = false;
    double uv[6] = {0, 0, 0, 0, 0, 0};  // triangle: u, v of each corner; sphere: centre
    double radius = 0;
};

// A ray's drawn part, in plane coordinates: from (u0, v0) to (u1, v1), clipped to the view.
struct PlaneSegment {
    bool drawn = false;  // false: nothing of it lies in the view
    bool endOn = false;  // the ray runs along the dropped axis: drawn as a point
    bool endsAtHit = false;
    double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};

// Where plane coordinates land in the SVG: x = left + (u - viewU0) * scale, y = top + (viewV1 -
// v) * scale (v grows upwards, as on a blackboard).
struct PlaneMapping {
    double left = 0, top = 0, scale = 1;
    double viewU0 = 0, viewV0 = 0, viewU1 = 0, viewV1 = 0;
    double x(double u) const { return left + (u - viewU0) * scale; }
    double y(double v) const { return top + (viewV1 - v) * scale; }
};

struct PlaneFigure {
    AxisPlane plane;
    bool rayInPlane = false;  // the primary ray's w component is 0: it lies in the plane
    PlaneMapping map;
    std::vector<PlaneCell> cells;  // the primary ray's box tests, in step order
    std::vector<PlaneCell> grid;   // the octree's leaf cells cut by the plane (role unused)
    std::vector<PlanePrim> prims;  // the primary ray's primitive tests, first test order
    PlaneSegment primary, shadow;
    bool hit = false;
    double hitU = 0, hitV = 0;
    int visited = 0;  // cells visited (the largest visit number)
};

// The figure of `e` in `plane` (its `at` is used for the grid); `tree` may be null (a layout
// without an octree: no grid). `scene` is the one explained (its primitives are drawn).
PlaneFigure planeFigure(const Explanation& e, const Scene& scene, const Octree* tree,
                        const AxisPlane& plane);
// The SVG document of a figure (title: scene, layout, pixel or ray; a legend on the right).
std::string planeFigureSvg(const PlaneFigure& f, const Explanation& e);
// The figure's heading lines: scene, primitives and layout; the pixel or the ray.
std::string explainFigureTitle(const Explanation& e);
std::string explainFigureQuery(const Explanation& e);
// Both for `octrace explain --svg`: `planeOption` is --svg-plane ("": planeOfRay of the
// primary ray; otherwise that plane through the ray's origin).
std::string explainSvg(const Explanation& e, const Scene& scene, const Octree* tree,
                       const std::string& planeOption);

}  // namespace oct
