#include "teach/svg_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "core/octree/morton.h"
#include "core/render/film.h"

namespace oct {
namespace {

// The drawing area: a square of kArea user units at (kLeft, kTop), the legend to its right.
constexpr double kLeft = 20, kTop = 78, kArea = 560, kWidth = 900, kHeight = 660;
constexpr double kLegendX = 604;
// The view is the root cell's square with this much margin (of its side) around it.
constexpr double kMargin = 0.04;
// More leaf cells than this under the plane are not drawn as the grid (a deep octree's grid
// would fill the figure with lines and megabytes): the legend says so.
constexpr size_t kMaxGridCells = 4096;

constexpr const char* kPrimaryColour = "#d6008f";  // magenta, as the page draws the primary ray
constexpr const char* kShadowColour = "#0099b8";   // cyan
constexpr const char* kOccludedColour = "#e07000";
constexpr const char* kHitPrimColour = "#ff9500";

std::string shortNum(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}
std::string vecText(Vec3 v) {
    return "(" + shortNum(v.x) + ", " + shortNum(v.y) + ", " + shortNum(v.z) + ")";
}

// A box with the plane's axis w dropped: its rectangle in plane coordinates.
void projectBox(const Aabb& b, const AxisPlane& p, double& u0, double& v0, double& u1, double& v1) {
    u0 = b.lo[p.u];
    u1 = b.hi[p.u];
    v0 = b.lo[p.v];
    v1 = b.hi[p.v];
}

// Cells some of whose children were tested or skipped: the internal ones. A visited cell that
// is not among them had its primitives tested: a leaf (an empty leaf is never visited).
std::set<uint64_t> parentsOfTestedCells(const std::vector<ExplainStep>& steps) {
    std::set<uint64_t> parents;
    for (const ExplainStep& s : steps)
        if ((s.event == StepEvent::Box || s.event == StepEvent::Skip) && s.key > kRootKey)
            parents.insert(parentKey(s.key));
    return parents;
}

std::vector<PlaneCell> testedCells(const std::vector<ExplainStep>& steps, const AxisPlane& p) {
    const std::map<uint64_t, int> order = visitOrder(steps);
    const std::set<uint64_t> parents = parentsOfTestedCells(steps);
    std::vector<PlaneCell> cells;
    std::set<uint64_t> seen;
    for (size_t i = 0; i < steps.size(); ++i) {
        const ExplainStep& s = steps[i];
        if (s.event != StepEvent::Box || !seen.insert(s.key).second) continue;
        PlaneCell c;
        c.key = s.key;
        c.depth = s.depth;
        c.step = i + 1;
        projectBox(s.box, p, c.u0, c.v0, c.u1, c.v1);
        const auto it = order.find(s.key);
        c.visit = it == order.end() ? 0 : it->second;
        c.role = !s.hit                 ? CellRole::Missed
                 : c.visit == 0         ? CellRole::Dropped
                 : parents.count(s.key) ? CellRole::VisitedInternal
                                        : CellRole::VisitedLeaf;
        cells.push_back(c);
    }
    return cells;
}

// The octree's leaf cells (empty ones too) whose box the plane w = at cuts.
std::vector<PlaneCell> leafGrid(const Octree& tree, const AxisPlane& p) {
    std::vector<PlaneCell> grid;
    for (const OctreeNode& n : tree.nodes) {
        const NodeType t = n.nodeType();
        if (t != NodeType::Leaf && t != NodeType::EmptyLeaf) continue;
        if (!(n.box.lo[p.w] <= p.at && p.at <= n.box.hi[p.w])) continue;
        PlaneCell c;
        c.key = n.key;
        c.depth = n.depth;
        projectBox(n.box, p, c.u0, c.v0, c.u1, c.v1);
        grid.push_back(c);
    }
    return grid;
}

PlaneMapping mappingOf(const Aabb& root, const AxisPlane& p) {
    PlaneMapping m;
    const double u0 = root.lo[p.u], u1 = root.hi[p.u], v0 = root.lo[p.v], v1 = root.hi[p.v];
    const double side = std::max(u1 - u0, v1 - v0), pad = kMargin * side;
    m.viewU0 = u0 - pad;
    m.viewV0 = v0 - pad;
    m.viewU1 = m.viewU0 + side + 2 * pad;
    m.viewV1 = m.viewV0 + side + 2 * pad;
    m.left = kLeft;
    m.top = kTop;
    m.scale = kArea / (side + 2 * pad);
    return m;
}

// The part t in [t0, t1] of the ray's projection that lies in the view (Liang and Barsky's
// clip of a parametric line against a rectangle).
PlaneSegment clipToView(const Ray& ray, double t0, double t1, const AxisPlane& p,
                        const PlaneMapping& m, bool endsAtHit) {
    PlaneSegment s;
    const double o[2] = {ray.org[p.u], ray.org[p.v]}, d[2] = {ray.dir[p.u], ray.dir[p.v]};
    const double lo[2] = {m.viewU0, m.viewV0}, hi[2] = {m.viewU1, m.viewV1};
    if (d[0] == 0 && d[1] == 0) {
        // Seen end-on: the ray runs along w and projects to its origin's point.
        s.endOn = true;
        s.drawn = o[0] >= lo[0] && o[0] <= hi[0] && o[1] >= lo[1] && o[1] <= hi[1];
        s.u0 = s.u1 = o[0];
        s.v0 = s.v1 = o[1];
        return s;
    }
    for (int a = 0; a < 2; ++a) {
        if (d[a] == 0) {
            if (o[a] < lo[a] || o[a] > hi[a]) return s;
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return s;
    s.drawn = true;
    s.endsAtHit = endsAtHit && std::isfinite(t1);
    s.u0 = o[0] + t0 * d[0];
    s.v0 = o[1] + t0 * d[1];
    s.u1 = o[0] + t1 * d[0];
    s.v1 = o[1] + t1 * d[1];
    return s;
}

PlaneSegment segmentOf(const RayTrace& r, const AxisPlane& p, const PlaneMapping& m) {
    const bool hit = r.hit.prim >= 0;
    const double end = hit ? double(r.hit.t) : double(r.ray.tmax);
    PlaneSegment s = clipToView(r.ray, r.ray.tmin, end, p, m, hit);
    // A hit inside the view ends the line there; clipped before it, the line does not.
    s.endsAtHit = s.endsAtHit && s.drawn;
    return s;
}

std::vector<PlanePrim> testedPrims(const RayTrace& r, const Scene& scene, const AxisPlane& p) {
    std::vector<PlanePrim> prims;
    std::set<uint32_t> seen;
    for (const ExplainStep& s : r.steps) {
        if (s.event != StepEvent::Prim || !seen.insert(s.prim).second) continue;
        PlanePrim q;
        q.id = s.prim;
        q.hit = int32_t(s.prim) == r.hit.prim;
        if (scene.kind == PrimKind::Triangles) {
            const Triangle& t = scene.triangles[s.prim];
            const Vec3 v[3] = {t.v0, t.v1, t.v2};
            for (int k = 0; k < 3; ++k) {
                q.uv[2 * k] = v[k][p.u];
                q.uv[2 * k + 1] = v[k][p.v];
            }
        } else {
            const Sphere& sp = scene.spheres[s.prim];
            q.sphere = true;
            q.uv[0] = sp.center[p.u];
            q.uv[1] = sp.center[p.v];
            q.radius = sp.radius;
        }
        prims.push_back(q);
    }
    return prims;
}

}  // namespace

PlaneFigure planeFigure(const Explanation& e, const Scene& scene, const Octree* tree,
                        const AxisPlane& plane) {
    PlaneFigure f;
    f.plane = plane;
    f.rayInPlane = e.primary.ray.dir[plane.w] == 0.0f && e.primary.ray.org[plane.w] == plane.at;
    f.map = mappingOf(e.root, plane);
    f.cells = testedCells(e.primary.steps, plane);
    for (const PlaneCell& c : f.cells) f.visited = std::max(f.visited, c.visit);
    if (tree) f.grid = leafGrid(*tree, plane);
    f.prims = testedPrims(e.primary, scene, plane);
    f.primary = segmentOf(e.primary, plane, f.map);
    if (e.shadow) f.shadow = segmentOf(*e.shadow, plane, f.map);
    f.hit = e.primary.hit.prim >= 0;
    if (f.hit) {
        // Named members, not h[i]: Vec3::operator[] indexes past &x, and clang's WebAssembly
        // build (the explain page) read the wrong coordinates of this temporary through it.
        const Vec3 h = e.primary.ray.org + e.primary.ray.dir * e.primary.hit.t;
        const float axes[3] = {h.x, h.y, h.z};
        f.hitU = axes[plane.u];
        f.hitV = axes[plane.v];
    }
    return f;
}

namespace {

const char* roleClass(CellRole r) {
    switch (r) {
        case CellRole::VisitedLeaf:
            return "visited-leaf";
        case CellRole::VisitedInternal:
            return "visited-internal";
        case CellRole::Dropped:
            return "dropped";
        case CellRole::Missed:
            return "missed";
    }
    return "missed";
}

// Visit k of n on viridis: the first visits dark, the last bright.
Rgb8 visitColour(int visit, int n) {
    return mapColour(ColourMap::Viridis, n > 1 ? double(visit - 1) / double(n - 1) : 0.0);
}

std::string cellStyle(const PlaneCell& c, int visited) {
    const std::string colour = svgColour(visitColour(c.visit, visited));
    switch (c.role) {
        case CellRole::VisitedLeaf:
            return " fill=\"" + colour + "\" fill-opacity=\"0.22\" stroke=\"" + colour +
                   "\" stroke-width=\"2\"";
        case CellRole::VisitedInternal:
            return " fill=\"" + colour + "\" fill-opacity=\"0.08\" stroke=\"" + colour +
                   "\" stroke-width=\"1.5\" stroke-dasharray=\"7 3\"";
        case CellRole::Dropped:
            return " fill=\"none\" stroke=\"#6e6e6e\" stroke-width=\"1.2\" stroke-dasharray=\"3 "
                   "3\"";
        case CellRole::Missed:
            return " fill=\"none\" stroke=\"#a8a8a8\" stroke-width=\"1\"";
    }
    return "";
}

void drawCell(SvgWriter& svg, const PlaneMapping& m, const PlaneCell& c, int visited) {
    const double x = m.x(c.u0), y = m.y(c.v1);
    svg.rect(x, y, m.x(c.u1) - x, m.y(c.v0) - y,
             " class=\"cell " + std::string(roleClass(c.role)) + "\" data-key=\"" +
                 keyOctal(c.key) + "\" data-visit=\"" + std::to_string(c.visit) + "\"" +
                 cellStyle(c, visited));
}

void drawVisitNumber(SvgWriter& svg, const PlaneMapping& m, const PlaneCell& c) {
    const double w = (c.u1 - c.u0) * m.scale, h = (c.v1 - c.v0) * m.scale;
    const double size = std::clamp(0.3 * std::min(w, h), 9.0, 18.0);
    svg.text(m.x(0.5 * (c.u0 + c.u1)), m.y(0.5 * (c.v0 + c.v1)) + 0.35 * size,
             std::to_string(c.visit),
             " class=\"visit-number\" data-key=\"" + keyOctal(c.key) +
                 "\" text-anchor=\"middle\" font-size=\"" + svgNum(size) +
                 "\" font-weight=\"bold\" fill=\"#202020\" stroke=\"#ffffff\" "
                 "stroke-width=\"3\" paint-order=\"stroke\"");
}

void drawPrim(SvgWriter& svg, const PlaneMapping& m, const PlanePrim& p) {
    const std::string style =
        p.hit ? std::string(" fill=\"") + kHitPrimColour +
                    "\" fill-opacity=\"0.55\" stroke=\"#a05000\" stroke-width=\"1.5\""
              : std::string(" fill=\"none\" stroke=\"#505050\" stroke-width=\"1\"");
    const std::string attrs = " class=\"prim" + std::string(p.hit ? " hit" : "") +
                              "\" data-prim=\"" + std::to_string(p.id) + "\"" + style;
    if (p.sphere) {
        svg.circle(m.x(p.uv[0]), m.y(p.uv[1]), p.radius * m.scale, attrs);
        return;
    }
    double xy[6];
    for (int k = 0; k < 3; ++k) {
        xy[2 * k] = m.x(p.uv[2 * k]);
        xy[2 * k + 1] = m.y(p.uv[2 * k + 1]);
    }
    svg.polygon(xy, 3, attrs);
}

std::string arrowMarker(const char* id, const char* colour) {
    return std::string("<marker id=\"") + id +
           "\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" "
           "markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" "
           "fill=\"" +
           colour + "\"/></marker>";
}

void drawSegment(SvgWriter& svg, const PlaneMapping& m, const PlaneSegment& s, const char* cls,
                 const char* colour, const char* marker) {
    if (!s.drawn) return;
    if (s.endOn) {
        svg.circle(m.x(s.u0), m.y(s.v0), 5,
                   std::string(" class=\"") + cls + " end-on\" fill=\"none\" stroke=\"" + colour +
                       "\" stroke-width=\"2\"");
        return;
    }
    svg.line(m.x(s.u0), m.y(s.v0), m.x(s.u1), m.y(s.v1),
             std::string(" class=\"") + cls + "\" stroke=\"" + colour +
                 "\" stroke-width=\"2.2\" marker-end=\"url(#" + marker + ")\"");
}

void drawHit(SvgWriter& svg, const PlaneMapping& m, double u, double v) {
    const double x = m.x(u), y = m.y(v);
    svg.circle(x, y, 6,
               " class=\"hit-point\" fill=\"#ffffff\" stroke=\"#000000\" "
               "stroke-width=\"1.5\"");
    svg.line(x - 4, y, x + 4, y, " stroke=\"#000000\" stroke-width=\"1.5\"");
    svg.line(x, y - 4, x, y + 4, " stroke=\"#000000\" stroke-width=\"1.5\"");
}

}  // namespace

std::string explainFigureTitle(const Explanation& e) {
    return "octrace explain: " + e.scene + " (" + std::to_string(e.primitives) + " " +
           primKindName(e.kind) + "), layout " + e.layout;
}

std::string explainFigureQuery(const Explanation& e) {
    if (e.pixelMode)
        return "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + ") of " +
               std::to_string(e.width) + "x" + std::to_string(e.height) +
               ": the camera ray through its centre";
    return "ray from " + vecText(e.primary.ray.org) + " along " + vecText(e.primary.ray.dir);
}

namespace {

std::string planeLine(const PlaneFigure& f) {
    const std::string w = axisName(f.plane.w);
    std::string s = "plane " + f.plane.name() + " at " + w + " = " + shortNum(f.plane.at);
    s +=
        f.rayInPlane ? ": the ray lies in it" : ": cells, primitives and rays projected along " + w;
    return s;
}

// One legend row: a small sample drawn by `sample` at (x, y), then its label.
struct LegendRows {
    SvgWriter& svg;
    double y;
    void label(const std::string& text, double size = 12) {
        svg.text(kLegendX + 34, y + 4, text,
                 " font-size=\"" + svgNum(size) + "\" fill=\"#202020\"");
        y += 20;
    }
    void note(const std::string& text) {
        svg.text(kLegendX, y + 4, text, " font-size=\"11\" fill=\"#505050\"");
        y += 16;
    }
};

void drawLegend(SvgWriter& svg, const PlaneFigure& f, const Explanation& e) {
    LegendRows rows{svg, kTop + 8};
    svg.text(kLegendX, rows.y, "Legend", " font-size=\"14\" font-weight=\"bold\"");
    rows.y += 22;
    // The visit order's ramp, first visit to last.
    const int n = std::max(f.visited, 1);
    for (int i = 0; i < 10; ++i)
        svg.rect(kLegendX + i * 9, rows.y - 6, 9, 10,
                 " fill=\"" + svgColour(visitColour(1 + (n - 1) * i / 9, n)) + "\"");
    svg.text(kLegendX + 96, rows.y + 4, "visit order 1 .. " + std::to_string(f.visited),
             " font-size=\"12\"");
    rows.y += 22;
    PlaneCell sample;
    sample.visit = 1;
    auto cellSample = [&](CellRole role, const std::string& text) {
        sample.role = role;
        svg.rect(kLegendX, rows.y - 7, 26, 14, cellStyle(sample, 1));
        rows.label(text);
    };
    cellSample(CellRole::VisitedLeaf, "leaf visited: its primitives tested");
    cellSample(CellRole::VisitedInternal, "internal cell visited: children tested");
    cellSample(CellRole::Dropped, "met, not visited (beyond the hit, or culled)");
    cellSample(CellRole::Missed, "box tested and missed");
    svg.rect(kLegendX, rows.y - 7, 26, 14,
             " fill=\"none\" stroke=\"#dadada\" stroke-width=\"0.6\"");
    rows.label("octree leaf cells the plane cuts");
    auto triangleSample = [&](const std::string& style, const std::string& text) {
        const double tri[6] = {kLegendX + 2, rows.y + 6,    kLegendX + 24,
                               rows.y + 6,   kLegendX + 13, rows.y - 7};
        svg.polygon(tri, 3, style);
        rows.label(text);
    };
    triangleSample(" fill=\"none\" stroke=\"#505050\" stroke-width=\"1\"", "primitive tested");
    triangleSample(std::string(" fill=\"") + kHitPrimColour +
                       "\" fill-opacity=\"0.55\" stroke=\"#a05000\" stroke-width=\"1.5\"",
                   "primitive hit");
    drawSegment(svg, PlaneMapping{kLegendX, rows.y, 1, 0, 0, 0, 0},
                PlaneSegment{true, false, false, 0, 0, 26, 0}, "legend", kPrimaryColour,
                "arrow-primary");
    rows.label("primary ray");
    const bool occluded = e.shadowState == kOccluded;
    drawSegment(svg, PlaneMapping{kLegendX, rows.y, 1, 0, 0, 0, 0},
                PlaneSegment{true, false, false, 0, 0, 26, 0}, "legend",
                occluded ? kOccludedColour : kShadowColour,
                occluded ? "arrow-occluded" : "arrow-shadow");
    rows.label(e.shadow ? (occluded ? "shadow ray: occluded" : "shadow ray: lit")
                        : "shadow ray: none cast");
    drawHit(svg, PlaneMapping{kLegendX + 13, rows.y, 1, 0, 0, 0, 0}, 0, 0);
    rows.label(f.hit ? "hit point" : "hit point: the ray hits nothing");
    rows.y += 8;
    const StepTotals& t = e.primary.totals;
    rows.note("primary ray: " + std::to_string(t.boxTests) + " boxes tested, " +
              std::to_string(t.entered) + " nodes entered,");
    rows.note(std::to_string(t.primTests) + " primitives tested" +
              (f.hit ? ", hit primitive " + std::to_string(e.primary.hit.prim) : ", no hit"));
    if (f.grid.size() > kMaxGridCells)
        rows.note("octree grid omitted: " + std::to_string(f.grid.size()) + " leaf cells");
    rows.note("keys (tooltips): Morton, octal; 1 is the root");
    if (!f.primary.drawn) rows.note("the primary ray does not cross the view");
}

}  // namespace

std::string planeFigureSvg(const PlaneFigure& f, const Explanation& e) {
    SvgWriter svg(kWidth, kHeight, explainFigureTitle(e));
    svg.raw("<defs>" + arrowMarker("arrow-primary", kPrimaryColour) +
            arrowMarker("arrow-shadow", kShadowColour) +
            arrowMarker("arrow-occluded", kOccludedColour) + "</defs>\n");
    svg.text(kLeft, 26, explainFigureTitle(e), " font-size=\"16\" font-weight=\"bold\"");
    svg.text(kLeft, 46, explainFigureQuery(e), " font-size=\"13\"");
    svg.text(kLeft, 64, planeLine(f), " font-size=\"13\" fill=\"#404040\"");
    const PlaneMapping& m = f.map;
    // The view, then the octree's leaf grid behind everything.
    svg.rect(m.left, m.top, kArea, kArea, " fill=\"#fbfbfb\" stroke=\"#d0d0d0\"");
    if (f.grid.size() <= kMaxGridCells)
        for (const PlaneCell& c : f.grid) {
            const double x = m.x(c.u0), y = m.y(c.v1);
            svg.rect(x, y, m.x(c.u1) - x, m.y(c.v0) - y,
                     " class=\"grid\" fill=\"none\" stroke=\"#dadada\" stroke-width=\"0.6\"");
        }
    // Cells not entered first, then the visited ones shallow to deep, so nested cells show.
    std::vector<const PlaneCell*> order;
    for (const PlaneCell& c : f.cells) order.push_back(&c);
    std::stable_sort(order.begin(), order.end(), [](const PlaneCell* a, const PlaneCell* b) {
        const bool va = a->visit > 0, vb = b->visit > 0;
        if (va != vb) return !va;
        return a->depth < b->depth;
    });
    for (const PlaneCell* c : order) drawCell(svg, m, *c, f.visited);
    for (const PlanePrim& p : f.prims) drawPrim(svg, m, p);
    const bool occluded = e.shadowState == kOccluded;
    drawSegment(svg, m, f.shadow, "shadow-ray", occluded ? kOccludedColour : kShadowColour,
                occluded ? "arrow-occluded" : "arrow-shadow");
    drawSegment(svg, m, f.primary, "primary-ray", kPrimaryColour, "arrow-primary");
    if (f.hit) drawHit(svg, m, f.hitU, f.hitV);
    // Visit numbers last, in visit order, so none is hidden under a later cell.
    std::vector<const PlaneCell*> visits;
    for (const PlaneCell& c : f.cells)
        if (c.visit > 0) visits.push_back(&c);
    std::sort(visits.begin(), visits.end(),
              [](const PlaneCell* a, const PlaneCell* b) { return a->visit < b->visit; });
    for (const PlaneCell* c : visits) drawVisitNumber(svg, m, *c);
    drawLegend(svg, f, e);
    return svg.finish();
}

std::string explainSvg(const Explanation& e, const Scene& scene, const Octree* tree,
                       const std::string& planeOption) {
    AxisPlane plane = planeOfRay(e.primary.ray);
    if (!planeOption.empty()) {
        plane = parseAxisPlane(planeOption);
        plane.at = e.primary.ray.org[plane.w];
    }
    return planeFigureSvg(planeFigure(e, scene, tree, plane), e);
}

}  // namespace oct
