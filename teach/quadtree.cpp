#include "teach/quadtree.h"

#include <algorithm>
#include <cstdio>

#include "teach/colour_map.h"
#include "teach/teach_error.h"

namespace oct {

// --- keys ------------------------------------------------------------------------------------

int quadKeyDepth(uint64_t key) {
    int depth = 0;
    for (; key > kQuadRootKey; key >>= 2) ++depth;
    return depth;
}

std::string quadKeyBase4(uint64_t key) {
    std::string digits;
    for (; key > kQuadRootKey; key >>= 2) digits.insert(digits.begin(), char('0' + (key & 3)));
    return "1" + digits;
}

std::string quadKeyBinary(uint64_t key) {
    std::string bits;
    for (; key > 0; key >>= 1) bits.insert(bits.begin(), char('0' + (key & 1)));
    return "0b" + bits;
}

QuadCell quadChildCell(const QuadCell& c, int quadrant) {
    const double mu = 0.5 * (c.u0 + c.u1), mv = 0.5 * (c.v0 + c.v1);
    QuadCell k;
    k.u0 = quadrant & 1 ? mu : c.u0;
    k.u1 = quadrant & 1 ? c.u1 : mu;
    k.v0 = quadrant & 2 ? mv : c.v0;
    k.v1 = quadrant & 2 ? c.v1 : mv;
    return k;
}

// --- the scene's plane -----------------------------------------------------------------------

namespace {

// Every point a primitive is placed by: triangle corners, sphere centres.
template <class F>
void forEachPlacingPoint(const Scene& scene, F&& f) {
    if (scene.kind == PrimKind::Triangles) {
        for (const Triangle& t : scene.triangles)
            for (const Vec3& v : {t.v0, t.v1, t.v2}) f(v);
    } else {
        for (const Sphere& s : scene.spheres) f(s.center);
    }
}

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

AxisPlane planeDroppingAxis(int w) {
    static const char* kNames[3] = {"yz", "xz", "xy"};
    return parseAxisPlane(kNames[w]);
}

}  // namespace

std::optional<AxisPlane> flatPlaneOf(const Scene& scene) {
    if (scene.primitiveCount() == 0) return std::nullopt;
    for (int w : {2, 1, 0}) {
        bool flat = true;
        float at = 0;
        bool first = true;
        forEachPlacingPoint(scene, [&](const Vec3& p) {
            if (first) at = p[w];
            first = false;
            flat = flat && p[w] == at;
        });
        if (flat) {
            AxisPlane plane = planeDroppingAxis(w);
            plane.at = at;
            return plane;
        }
    }
    return std::nullopt;
}

AxisPlane quadtreePlane(const Scene& scene, const std::string& planeOption) {
    const std::optional<AxisPlane> flat = flatPlaneOf(scene);
    if (!flat) {
        Aabb b = emptyAabb();
        forEachPlacingPoint(scene, [&](const Vec3& p) { grow(b, p); });
        const Vec3 e = b.extent();
        throw TeachError("--quadtree: the scene '" + scene.name +
                         "' is not flat: its primitives span x " + num(e.x) + ", y " + num(e.y) +
                         ", z " + num(e.z) +
                         " (a quadtree needs every triangle corner or sphere centre in one axis "
                         "plane: give a flat mesh or point cloud, or draw this scene with --svg "
                         "alone)");
    }
    if (!planeOption.empty() && parseAxisPlane(planeOption).w != flat->w)
        throw TeachError("--svg-plane " + planeOption + ": the scene '" + scene.name +
                         "' lies in the " + flat->name() + " plane at " + axisName(flat->w) +
                         " = " + num(flat->at) + " (give --svg-plane " + flat->name() +
                         " or leave it out)");
    return *flat;
}

QuadCell quadRootOf(const Scene& scene, const AxisPlane& plane) {
    const Aabb root = rootCube(scene);
    return {root.lo[plane.u], root.lo[plane.v], root.hi[plane.u], root.hi[plane.v]};
}

// --- building --------------------------------------------------------------------------------

namespace {

struct Point2 {
    double u, v;
};

void triangleCorners(const Scene& scene, uint32_t id, const AxisPlane& p, Point2 out[3]) {
    const Triangle& t = scene.triangles[id];
    const Vec3 v[3] = {t.v0, t.v1, t.v2};
    for (int k = 0; k < 3; ++k) out[k] = {v[k][p.u], v[k][p.v]};
}

// Separating axes (the 2D form of the octree builder's triangle-box test): the cell's two
// axes and the triangle's three edge normals. Touching counts as overlapping.
bool triangleOverlapsCell(const Point2 t[3], const QuadCell& c) {
    const double minU = std::min({t[0].u, t[1].u, t[2].u}),
                 maxU = std::max({t[0].u, t[1].u, t[2].u});
    const double minV = std::min({t[0].v, t[1].v, t[2].v}),
                 maxV = std::max({t[0].v, t[1].v, t[2].v});
    if (maxU < c.u0 || minU > c.u1 || maxV < c.v0 || minV > c.v1) return false;
    const Point2 corners[4] = {{c.u0, c.v0}, {c.u1, c.v0}, {c.u0, c.v1}, {c.u1, c.v1}};
    for (int e = 0; e < 3; ++e) {
        const Point2 a = t[e], b = t[(e + 1) % 3], third = t[(e + 2) % 3];
        const double nu = -(b.v - a.v), nv = b.u - a.u;
        const double side = nu * (third.u - a.u) + nv * (third.v - a.v);
        bool allOutside = true;
        for (const Point2& q : corners) {
            const double s = nu * (q.u - a.u) + nv * (q.v - a.v);
            allOutside = allOutside && (side > 0 ? s < 0 : s > 0);
        }
        if (allOutside) return false;
    }
    return true;
}

double circleCellDistanceSq(double cu, double cv, const QuadCell& c) {
    const double du = cu < c.u0 ? c.u0 - cu : cu > c.u1 ? cu - c.u1 : 0.0;
    const double dv = cv < c.v0 ? c.v0 - cv : cv > c.v1 ? cv - c.v1 : 0.0;
    return du * du + dv * dv;
}

bool primOverlapsCell(const Scene& scene, uint32_t id, const AxisPlane& p, const QuadCell& c) {
    if (scene.kind == PrimKind::Triangles) {
        Point2 t[3];
        triangleCorners(scene, id, p, t);
        return triangleOverlapsCell(t, c);
    }
    const Sphere& s = scene.spheres[id];
    const double r = s.radius;
    return circleCellDistanceSq(s.center[p.u], s.center[p.v], c) <= r * r;
}

// buildOctree's "inseparable" rule in 2D: every sub-cell would hold all of them or none.
bool inseparable(const Scene& scene, const std::vector<uint32_t>& prims, const AxisPlane& p,
                 const QuadCell& c) {
    bool same = true, allContain = scene.kind == PrimKind::Spheres;
    for (uint32_t id : prims) {
        if (scene.kind == PrimKind::Triangles) {
            Point2 a[3], b[3];
            triangleCorners(scene, prims[0], p, a);
            triangleCorners(scene, id, p, b);
            auto key = [](Point2* t) {
                std::sort(t, t + 3, [](Point2 x, Point2 y) {
                    return x.u < y.u || (x.u == y.u && x.v < y.v);
                });
            };
            key(a);
            key(b);
            for (int k = 0; k < 3; ++k) same = same && a[k].u == b[k].u && a[k].v == b[k].v;
        } else {
            const Sphere& s = scene.spheres[id];
            const Sphere& f = scene.spheres[prims[0]];
            same = same && s.center[p.u] == f.center[p.u] && s.center[p.v] == f.center[p.v] &&
                   s.radius == f.radius;
            const double fu =
                std::max(std::fabs(c.u0 - s.center[p.u]), std::fabs(c.u1 - s.center[p.u]));
            const double fv =
                std::max(std::fabs(c.v0 - s.center[p.v]), std::fabs(c.v1 - s.center[p.v]));
            allContain = allContain && fu * fu + fv * fv <= double(s.radius) * s.radius;
        }
        if (!same && !allContain) return false;
    }
    return true;
}

bool shouldSplit(const Scene& scene, const Quadtree& q, const QuadNode& n) {
    return n.prims.size() > q.params.maxPrims && n.depth < q.params.maxDepth &&
           !inseparable(scene, n.prims, q.plane, n.cell);
}

// The children of node `index`, appended as 4 adjacent nodes in quadrant order.
void splitNode(const Scene& scene, Quadtree& q, uint32_t index) {
    const uint32_t first = uint32_t(q.nodes.size());
    for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const QuadNode& parent = q.nodes[index];
        QuadNode child;
        child.key = quadChildKey(parent.key, quadrant);
        child.depth = parent.depth + 1;
        child.cell = quadChildCell(parent.cell, quadrant);
        for (uint32_t id : parent.prims)
            if (primOverlapsCell(scene, id, q.plane, child.cell)) child.prims.push_back(id);
        q.depth = std::max(q.depth, child.depth);
        q.nodes.push_back(std::move(child));
    }
    q.nodes[index].firstChild = first;
    q.nodes[index].prims.clear();  // an internal node owns no primitives
}

}  // namespace

Quadtree buildQuadtree(const Scene& scene, const AxisPlane& plane, const QuadCell& root,
                       const BuildParams& params) {
    Quadtree q;
    q.plane = plane;
    q.params = params;
    QuadNode r;
    r.cell = root;
    for (uint32_t id = 0; id < scene.primitiveCount(); ++id)
        if (primOverlapsCell(scene, id, plane, root)) r.prims.push_back(id);
    q.nodes.push_back(std::move(r));
    // Breadth first: the nodes are appended level by level, so a node's index is after its
    // parent's and the loop meets every node once.
    for (uint32_t i = 0; i < q.nodes.size(); ++i) {
        if (!shouldSplit(scene, q, q.nodes[i])) continue;
        if (q.nodes.size() + 4 > kMaxQuadtreeNodes)
            throw TeachError("--quadtree: the quadtree of '" + scene.name + "' needs more than " +
                             std::to_string(kMaxQuadtreeNodes) + " cells at --max-depth " +
                             std::to_string(params.maxDepth) + " and --max-prims " +
                             std::to_string(params.maxPrims) +
                             ", too many to draw: lower --max-depth or raise --max-prims");
        splitNode(scene, q, i);
    }
    return q;
}

// --- the ray ---------------------------------------------------------------------------------

Ray2D rayInPlane(const Ray& ray, const AxisPlane& plane) {
    const double du = ray.dir[plane.u], dv = ray.dir[plane.v];
    const double len = std::sqrt(du * du + dv * dv);
    // Well below this the ray runs along the dropped axis up to rounding.
    if (!(len > 1e-6 * std::fabs(double(ray.dir[plane.w]))) || len == 0)
        throw TeachError("--quadtree: the ray runs along " + std::string(axisName(plane.w)) +
                         ", across the scene's plane " + plane.name() +
                         ": it has no direction in the plane (give --ray with a direction in the "
                         "plane, e.g. " +
                         (plane.w == 2 ? "--ray X,Y,Z,1,0.3,0" : "--ray X,Y,Z,0.3,0,1") + ")");
    Ray2D r;
    r.ou = ray.org[plane.u];
    r.ov = ray.org[plane.v];
    r.du = du / len;
    r.dv = dv / len;
    return r;
}

// --- traversal -------------------------------------------------------------------------------

namespace {

// The 2D slab test (Kay & Kajiya) in double: the part of [t0, t1] inside the cell.
bool rayMeetsCell(const Ray2D& r, const QuadCell& c, double& t0, double& t1) {
    const double o[2] = {r.ou, r.ov}, d[2] = {r.du, r.dv};
    const double lo[2] = {c.u0, c.v0}, hi[2] = {c.u1, c.v1};
    for (int a = 0; a < 2; ++a) {
        if (d[a] == 0) {
            if (o[a] < lo[a] || o[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

// The ray and a circle: the nearer root in [tmin, tmax], else the farther (a ray starting
// inside meets its far side), as intersectSphere answers for the sphere's centre plane.
bool rayHitsCircle(const Ray2D& r, double cu, double cv, double radius, double tmax, double& t) {
    const double ou = r.ou - cu, ov = r.ov - cv;
    const double b = ou * r.du + ov * r.dv, c = ou * ou + ov * ov - radius * radius;
    const double disc = b * b - c;
    if (disc < 0) return false;
    const double s = std::sqrt(disc);
    t = -b - s;
    if (t < r.tmin) t = -b + s;
    return t >= r.tmin && t <= tmax;
}

// The ray and a triangle's region (Cyrus and Beck's clip against its three edges): where the
// ray enters it.
bool rayHitsTriangle(const Ray2D& r, const Point2 tri[3], double tmax, double& t) {
    double t0 = r.tmin, t1 = tmax;
    for (int e = 0; e < 3; ++e) {
        const Point2 a = tri[e], b = tri[(e + 1) % 3], third = tri[(e + 2) % 3];
        double nu = -(b.v - a.v), nv = b.u - a.u;
        if (nu * (third.u - a.u) + nv * (third.v - a.v) < 0) {
            nu = -nu;
            nv = -nv;
        }
        const double start = nu * (r.ou - a.u) + nv * (r.ov - a.v);  // >= 0: inside
        const double rate = nu * r.du + nv * r.dv;
        if (rate == 0) {
            if (start < 0) return false;
            continue;
        }
        const double tc = -start / rate;
        if (rate > 0)
            t0 = std::max(t0, tc);
        else
            t1 = std::min(t1, tc);
    }
    t = t0;
    return t0 <= t1;
}

bool rayHitsPrim(const Scene& scene, const Quadtree& q, const Ray2D& r, uint32_t id, double tmax,
                 double& t) {
    if (scene.kind == PrimKind::Spheres) {
        const Sphere& s = scene.spheres[id];
        return rayHitsCircle(r, s.center[q.plane.u], s.center[q.plane.v], s.radius, tmax, t);
    }
    Point2 tri[3];
    triangleCorners(scene, id, q.plane, tri);
    return rayHitsTriangle(r, tri, tmax, t);
}

struct Pending {
    uint32_t node;
    double tEnter;
};

// The octree traversal's visiting order (nearFirstOrder, traversal.h): sorted by descending
// t enter, ties in quadrant order, so the nearest is pushed last and popped first (nearest
// first; equal t, the higher quadrant first).
void sortFarToNear(std::vector<Pending>& kids) {
    for (size_t i = 1; i < kids.size(); ++i) {
        const Pending x = kids[i];
        size_t j = i;
        while (j > 0 && kids[j - 1].tEnter < x.tEnter) {
            kids[j] = kids[j - 1];
            --j;
        }
        kids[j] = x;
    }
}

void testLeaf(const Quadtree& q, const Scene& scene, const QuadNode& n, QuadTrace& tr) {
    for (uint32_t id : n.prims) {
        double t = 0;
        const bool hit = rayHitsPrim(scene, q, tr.ray, id, tr.hitT, t);
        tr.steps.push_back({QuadEvent::Prim, 0, hit, hit ? t : 0.0, id});
        // The closest hit, ties to the lower id (considerPrimitive).
        if (hit && (t < tr.hitT || (t == tr.hitT && int64_t(id) < tr.hitPrim))) {
            tr.hitT = t;
            tr.hitPrim = id;
        }
    }
}

}  // namespace

QuadTrace traceQuadtree(const Quadtree& q, const Scene& scene, const Ray2D& ray) {
    QuadTrace tr;
    tr.ray = ray;
    double t0 = ray.tmin, t1 = ray.tmax;
    const bool rootHit = rayMeetsCell(ray, q.nodes[0].cell, t0, t1);
    tr.steps.push_back({QuadEvent::Box, 0, rootHit, rootHit ? t0 : 0.0, 0});
    if (!rootHit) return tr;
    std::vector<Pending> stack = {{0, t0}};
    while (!stack.empty()) {
        const Pending e = stack.back();
        stack.pop_back();
        const QuadNode& n = q.nodes[e.node];
        const bool visit = !(e.tEnter > tr.hitT);  // a nearer hit is already known: dropped
        tr.steps.push_back({QuadEvent::Pop, e.node, visit, e.tEnter, 0});
        if (!visit) continue;
        tr.visits.push_back(e.node);
        if (n.leaf()) {
            testLeaf(q, scene, n, tr);
            continue;
        }
        std::vector<Pending> kids;
        for (uint32_t c = n.firstChild; c < n.firstChild + 4; ++c) {
            const QuadNode& k = q.nodes[c];
            if (k.leaf() && k.prims.empty()) {  // an empty leaf holds nothing to hit
                tr.steps.push_back({QuadEvent::Skip, c, false, 0, 0});
                continue;
            }
            double a = ray.tmin, b = tr.hitT;
            const bool hit = rayMeetsCell(ray, k.cell, a, b);
            tr.steps.push_back({QuadEvent::Box, c, hit, hit ? a : 0.0, 0});
            if (hit) kids.push_back({c, a});
        }
        sortFarToNear(kids);
        stack.insert(stack.end(), kids.begin(), kids.end());
    }
    return tr;
}

// --- the figure ------------------------------------------------------------------------------

namespace {

constexpr double kLeft = 20, kTop = 78, kArea = 560, kWidth = 900, kHeight = 660;
constexpr double kPanelX = 604;
constexpr double kMargin = 0.04;
constexpr size_t kListedVisits = 18;  // visit lines in the panel; more are summed up

struct Mapping {
    double u0, v1, scale;
    double x(double u) const { return kLeft + (u - u0) * scale; }
    double y(double v) const { return kTop + (v1 - v) * scale; }
};

Mapping mappingOf(const QuadCell& root) {
    const double side = std::max(root.u1 - root.u0, root.v1 - root.v0), pad = kMargin * side;
    return {root.u0 - pad, root.v0 - pad + side + 2 * pad, kArea / (side + 2 * pad)};
}

void drawCell(SvgWriter& svg, const Mapping& m, const QuadNode& n, int visit, int visits) {
    const double x = m.x(n.cell.u0), y = m.y(n.cell.v1);
    const double w = m.x(n.cell.u1) - x, h = m.y(n.cell.v0) - y;
    std::string fill = "none";
    std::string opacity;
    if (n.leaf() && visit > 0) {
        fill = svgColour(
            mapColour(ColourMap::Viridis, visits > 1 ? double(visit - 1) / (visits - 1) : 0.0));
        opacity = " fill-opacity=\"0.3\"";
    } else if (n.leaf() && n.prims.empty()) {
        fill = "#f2f2f2";
    }
    const double stroke = std::max(0.6, 2.4 - 0.45 * n.depth);
    svg.withTitle("<rect x=\"" + svgNum(x) + "\" y=\"" + svgNum(y) + "\" width=\"" + svgNum(w) +
                      "\" height=\"" + svgNum(h) + "\" class=\"qcell" +
                      (n.leaf() ? " leaf" : " internal") + "\" data-key=\"" + quadKeyBase4(n.key) +
                      "\" data-visit=\"" + std::to_string(visit) + "\" fill=\"" + fill + "\"" +
                      opacity + " stroke=\"#404040\" stroke-width=\"" + svgNum(stroke) + "\"",
                  "rect",
                  "key " + quadKeyBase4(n.key) + " (base 4) = " + quadKeyBinary(n.key) +
                      ", depth " + std::to_string(n.depth) + ", " + std::to_string(n.prims.size()) +
                      " primitives");
}

// The key in the cell, and under it the visit number when the cell was visited.
void drawLeafLabel(SvgWriter& svg, const Mapping& m, const QuadNode& n, int visit) {
    const double w = (n.cell.u1 - n.cell.u0) * m.scale;
    const std::string key = quadKeyBase4(n.key);
    const double size = std::min(15.0, 1.5 * w / double(key.size() + 1));
    if (size < 5.5) return;  // too small to read: the tooltip still names it
    const double cx = m.x(0.5 * (n.cell.u0 + n.cell.u1)), cy = m.y(0.5 * (n.cell.v0 + n.cell.v1));
    svg.text(cx, cy + (visit > 0 ? 0 : 0.35 * size), key,
             " class=\"qkey\" text-anchor=\"middle\" font-size=\"" + svgNum(size) +
                 "\" fill=\"#303030\"");
    if (visit > 0)
        svg.text(cx, cy + 1.1 * size, "#" + std::to_string(visit),
                 " class=\"qvisit\" data-key=\"" + key + "\" text-anchor=\"middle\" font-size=\"" +
                     svgNum(size) + "\" font-weight=\"bold\" fill=\"#000000\"");
}

void drawPrims(SvgWriter& svg, const Mapping& m, const Quadtree& q, const Scene& scene,
               int64_t hitPrim) {
    for (uint32_t id = 0; id < scene.primitiveCount(); ++id) {
        const bool hit = int64_t(id) == hitPrim;
        const std::string attrs =
            " class=\"prim" + std::string(hit ? " hit" : "") + "\" data-prim=\"" +
            std::to_string(id) + "\"" +
            (hit ? " fill=\"#ff9500\" fill-opacity=\"0.7\" stroke=\"#a05000\" stroke-width=\"1.5\""
                 : " fill=\"#9ab0d0\" fill-opacity=\"0.35\" stroke=\"#3b5d99\" stroke-width=\"1\"");
        if (scene.kind == PrimKind::Spheres) {
            const Sphere& s = scene.spheres[id];
            svg.circle(m.x(s.center[q.plane.u]), m.y(s.center[q.plane.v]),
                       std::max(1.5, s.radius * m.scale), attrs);
        } else {
            Point2 t[3];
            triangleCorners(scene, id, q.plane, t);
            const double xy[6] = {m.x(t[0].u), m.y(t[0].v), m.x(t[1].u),
                                  m.y(t[1].v), m.x(t[2].u), m.y(t[2].v)};
            svg.polygon(xy, 3, attrs);
        }
    }
}

void drawRay(SvgWriter& svg, const Mapping& m, const Quadtree& q, const QuadTrace& tr) {
    // From the origin (or where the ray enters the view) to the hit, or out of the view.
    const QuadCell& root = q.nodes[0].cell;
    const double pad = kMargin * (root.u1 - root.u0);
    const QuadCell view = {root.u0 - pad, root.v0 - pad, root.u1 + pad, root.v1 + pad};
    double t0 = tr.ray.tmin, t1 = std::isfinite(tr.hitT) ? tr.hitT : tr.ray.tmax;
    if (!rayMeetsCell(tr.ray, view, t0, t1)) return;
    svg.raw(
        "<defs><marker id=\"qarrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
        "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 "
        "L10,5 L0,10 z\" fill=\"#d6008f\"/></marker></defs>\n");
    svg.line(m.x(tr.ray.ou + t0 * tr.ray.du), m.y(tr.ray.ov + t0 * tr.ray.dv),
             m.x(tr.ray.ou + t1 * tr.ray.du), m.y(tr.ray.ov + t1 * tr.ray.dv),
             " class=\"ray\" stroke=\"#d6008f\" stroke-width=\"2.2\" marker-end=\"url(#qarrow)\"");
    if (tr.hitPrim >= 0) {
        const double x = m.x(tr.ray.ou + tr.hitT * tr.ray.du),
                     y = m.y(tr.ray.ov + tr.hitT * tr.ray.dv);
        svg.circle(x, y, 6,
                   " class=\"hit-point\" fill=\"#ffffff\" stroke=\"#000000\" stroke-width=\"1.5\"");
        svg.line(x - 4, y, x + 4, y, " stroke=\"#000000\" stroke-width=\"1.5\"");
        svg.line(x, y - 4, x, y + 4, " stroke=\"#000000\" stroke-width=\"1.5\"");
    }
}

void drawPanel(SvgWriter& svg, const Quadtree& q, const QuadTrace& tr) {
    double y = kTop + 8;
    auto line = [&](const std::string& text, const std::string& attrs = " font-size=\"12\"") {
        svg.text(kPanelX, y, text, attrs);
        y += 17;
    };
    size_t leaves = 0;
    for (const QuadNode& n : q.nodes) leaves += n.leaf();
    line("Quadtree (the paper's Figure 1)", " font-size=\"14\" font-weight=\"bold\"");
    line(std::to_string(q.nodes.size()) + " cells, " + std::to_string(leaves) + " leaves, depth " +
         std::to_string(q.depth));
    line("split: more than " + std::to_string(q.params.maxPrims) + " primitives, to depth " +
         std::to_string(q.params.maxDepth));
    line("keys in base 4: 1 is the root, each further");
    line("digit a quadrant u + 2v (0 lower left, 1 lower");
    line("right, 2 upper left, 3 upper right): a child's key");
    line("appends 2 bits, key(child q of k) = 4k + q");
    if (q.nodes.size() > 1) {
        const QuadNode& last = q.nodes.back();
        line("e.g. " + quadKeyBase4(last.key) + " (base 4) = " + quadKeyBinary(last.key) + " = " +
             std::to_string(last.key));
    }
    y += 6;
    line("Visit order (#n in the cells)", " font-size=\"13\" font-weight=\"bold\"");
    for (size_t i = 0; i < tr.visits.size() && i < kListedVisits; ++i) {
        const QuadNode& n = q.nodes[tr.visits[i]];
        line(std::to_string(i + 1) + ". key " + quadKeyBase4(n.key) +
             (n.leaf() ? ", leaf of " + std::to_string(n.prims.size()) +
                             (n.prims.size() == 1 ? " primitive" : " primitives")
                       : ", internal"));
    }
    if (tr.visits.size() > kListedVisits)
        line("... and " + std::to_string(tr.visits.size() - kListedVisits) + " more");
    y += 6;
    line(tr.hitPrim >= 0 ? "hit: primitive " + std::to_string(tr.hitPrim) + " at t " + num(tr.hitT)
                         : "hit: none",
         " font-size=\"12\" font-weight=\"bold\"");
}

}  // namespace

std::string quadtreeSvg(const Quadtree& q, const QuadTrace& tr, const Scene& scene,
                        const std::string& title, const std::string& query) {
    SvgWriter svg(kWidth, kHeight, title);
    svg.text(kLeft, 26, title, " font-size=\"16\" font-weight=\"bold\"");
    svg.text(kLeft, 46, query, " font-size=\"13\"");
    svg.text(kLeft, 64,
             "quadtree over the plane " + q.plane.name() + " at " + axisName(q.plane.w) + " = " +
                 num(q.plane.at) + ", the ray in that plane",
             " font-size=\"13\" fill=\"#404040\"");
    const Mapping m = mappingOf(q.nodes[0].cell);
    std::vector<int> visitOf(q.nodes.size(), 0);
    for (size_t i = 0; i < tr.visits.size(); ++i) visitOf[tr.visits[i]] = int(i + 1);
    const int visits = int(tr.visits.size());
    for (size_t i = 0; i < q.nodes.size(); ++i) drawCell(svg, m, q.nodes[i], visitOf[i], visits);
    drawPrims(svg, m, q, scene, tr.hitPrim);
    for (size_t i = 0; i < q.nodes.size(); ++i)
        if (q.nodes[i].leaf()) drawLeafLabel(svg, m, q.nodes[i], visitOf[i]);
    drawRay(svg, m, q, tr);
    drawPanel(svg, q, tr);
    return svg.finish();
}

}  // namespace oct
