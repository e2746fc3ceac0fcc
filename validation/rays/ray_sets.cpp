#include "validation/rays/ray_sets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>

#include "core/geometry/vec3t.h"
#include "core/io/ray_file.h"
#include "core/octree/built_scene.h"
#include "core/octree/octree.h"
#include "core/scene/mesh_topology.h"
#include "core/scene/slivers.h"
#include "core/system/resources.h"
#include "validation/policy/double_tracer.h"
#include "validation/policy/film_compare.h"

namespace oct {
namespace {

// Radius, relative to the scene's extent, of the disc a sealed target must be covered on. It is
// checked on the stored ray, whose float origin may lie far off the point aimed at (0.25 at
// y = 4e6): a tracer's own error is relative to the ray's local geometry (vertex - origin, exact
// for nearby floats), some 1e-7 of the ray's few triangle sides, far inside this disc.
constexpr double kSealMargin = 1e-5;
constexpr double kEdgeMinCos = 0.1, kVertexMinCos = 0.05;
constexpr int kAttemptsPerRay = 200;
// The slivers set: |cos(ray, normal)| = u^2, u in [kSliversMinSqrtCos, 1]; origins this far.
constexpr double kSliversMinSqrtCos = 0.1;
constexpr double kSliversNear = 0.25, kSliversFar = 2.0;

uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

}  // namespace

struct RaySetRng {
    std::mt19937_64 engine;
    double u01() { return double(engine() >> 11) * 0x1p-53; }  // [0, 1)
    double range(double lo, double hi) { return lo + (hi - lo) * u01(); }
    uint64_t below(uint64_t n) { return engine() % n; }
};

struct RaySetContext {
    RaySetContext(const Scene& s, const CameraOptions& cam, const TraceBatch& ref)
        : scene(s), camera(cam), reference(ref) {}
    const Scene& scene;
    const CameraOptions& camera;  // the camera and shadow sets
    const TraceBatch& reference;  // the shadow set's camera hits
    Aabb bounds{}, root{};
    Vec3 centre{};
    float radius = 0.0f;
    double margin = 0.0;                      // kSealMargin x extent
    std::shared_ptr<const MeshTargets> mesh;  // edges and vertices sets (prepareTopology)
    std::vector<double> cumulativeArea;       // slivers: running sum of the triangles' areas
    const DoubleTracer* truth = nullptr;      // the seal's double-precision check
    std::unique_ptr<DoubleTracer> ownTruth;   // when the spec gave none
    double tTolerance = 0.0;                  // world units: the default t tolerance
};
namespace {

using Rng = RaySetRng;
using Context = RaySetContext;

Rng streamFor(uint64_t seed, const RaySetDesc& k) {
    return Rng{std::mt19937_64(splitmix64(seed + 0x9E3779B97F4A7C15ull * (uint64_t(k.id) + 1)))};
}

// Uniform on the sphere by rejection from the cube: no sin/cos, so the same bits everywhere.
Vec3 unitVector(Rng& rng) {
    for (;;) {
        double x = 2.0 * rng.u01() - 1.0, y = 2.0 * rng.u01() - 1.0, z = 2.0 * rng.u01() - 1.0;
        double r2 = x * x + y * y + z * z;
        if (r2 > 1e-6 && r2 <= 1.0) {
            double s = 1.0 / std::sqrt(r2);
            return {float(x * s), float(y * s), float(z * s)};
        }
    }
}

Vec3 pointIn(Rng& rng, const Aabb& b) {
    return {float(rng.range(b.lo.x, b.hi.x)), float(rng.range(b.lo.y, b.hi.y)),
            float(rng.range(b.lo.z, b.hi.z))};
}

// Boundary coordinates of the nodes of depth `depth` along one axis: the same float midpoints
// childBox() takes, so the planes are exactly the node faces of the canonical octree.
std::vector<float> boundaryPlanes(float lo, float hi, int depth) {
    std::vector<float> cuts = {lo, hi};
    for (int d = 0; d < depth; ++d) {
        std::vector<float> next;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) {
            next.push_back(cuts[i]);
            next.push_back((cuts[i] + cuts[i + 1]) * 0.5f);
        }
        next.push_back(cuts.back());
        cuts = std::move(next);
    }
    return cuts;
}

// Double precision (DVec3) is for the acceptance tests, never for the stored floats.
DVec3 triangleNormal(const Triangle& t) {
    return cross(toDouble(t.v1) - toDouble(t.v0), toDouble(t.v2) - toDouble(t.v0));
}

double absCos(DVec3 n, DVec3 d) { return std::fabs(dot(n, d)) / (length(n) * length(d)); }

// Points seen along a direction: 2-D coordinates in a plane perpendicular to it.
struct Projection {
    DVec3 u, w;
    explicit Projection(DVec3 d) {
        DVec3 a = std::fabs(d.x) < 0.6 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
        u = cross(d, a);
        u = u * (1.0 / length(u));
        w = cross(d, u);
        w = w * (1.0 / length(w));
    }
    void operator()(DVec3 p, double& x, double& y) const {
        x = dot(p, u);
        y = dot(p, w);
    }
};

struct P2 {
    double x, y;
};
double side(P2 a, P2 b, P2 p) { return (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y); }
double segmentDistance(P2 p, P2 a, P2 b) {
    double ux = b.x - a.x, uy = b.y - a.y, l2 = ux * ux + uy * uy;
    double s = l2 > 0 ? ((p.x - a.x) * ux + (p.y - a.y) * uy) / l2 : 0.0;
    s = s < 0 ? 0 : (s > 1 ? 1 : s);
    double dx = p.x - (a.x + s * ux), dy = p.y - (a.y + s * uy);
    return std::sqrt(dx * dx + dy * dy);
}

// Winding number of a closed polygon around p (Sunday's crossing rule: signs only).
int windingNumber(const std::vector<P2>& poly, P2 p) {
    int w = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        P2 a = poly[i], b = poly[(i + 1) % poly.size()];
        if (a.y <= p.y) {
            if (b.y > p.y && side(a, b, p) > 0) ++w;
        } else if (b.y <= p.y && side(a, b, p) < 0) {
            --w;
        }
    }
    return w;
}

void push(RaySet& out, Vec3 o, Vec3 d, float tmin, float tmax) {
    const float r[8] = {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax};
    out.rays.insert(out.rays.end(), r, r + 8);
}

// Would `octrace trace` take this row (the reader's own rule)?
bool traceable(Vec3 o, Vec3 d, float tmin, float tmax) {
    const float r[8] = {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax};
    return rayRowProblem(r).empty();
}

std::string plural(uint64_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

void around(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    for (uint64_t i = 0; i < n; ++i) {
        Vec3 o = c.centre + unitVector(rng) * (1.5f * c.radius);
        Vec3 d = pointIn(rng, c.bounds) - o;
        if (!(length(d) > 0.0f)) d = c.centre - o;
        push(out, o, normalize(d), 0.0f, INFINITY);
    }
}

void inside(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    for (uint64_t i = 0; i < n; ++i) {
        Vec3 o = pointIn(rng, c.root);
        Vec3 d = unitVector(rng);
        float tmax = rng.below(4) == 0 ? float(rng.u01() * c.radius) : INFINITY;
        push(out, o, d, 0.0f, tmax);
    }
}

void axis(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    std::vector<float> planes[3][4];  // [axis][depth]
    for (int a = 0; a < 3; ++a)
        for (int d = 1; d <= 3; ++d) planes[a][d] = boundaryPlanes(c.root.lo[a], c.root.hi[a], d);
    for (uint64_t i = 0; i < n; ++i) {
        Vec3 o = pointIn(rng, c.root);
        int ax = int(rng.below(3));
        Vec3 d = {0.0f, 0.0f, 0.0f};
        d[ax] = rng.below(2) ? 1.0f : -1.0f;
        if (i % 2 == 1) {  // into a node face: move one other coordinate onto a split plane
            int other = (ax + 1 + int(rng.below(2))) % 3;
            const std::vector<float>& p = planes[other][1 + rng.below(3)];
            o[other] = p[rng.below(p.size())];
        }
        push(out, o, d, 0.0f, INFINITY);
    }
}

// The ray from `from` towards the float point p, as stored: origin, unit direction, and the
// ray parameter nearest to p (double, on the stored float ray).
void aimAt(Vec3 p, Vec3 from, Vec3& o, Vec3& dir, double& t) {
    o = from;
    dir = normalize(p - o);
    DVec3 dd = toDouble(dir);
    t = dot(toDouble(p) - toDouble(o), dd) / dot(dd, dd);
}

// Is the edge target sealed for the stored ray (origin o, direction dir): seen along it, the two
// triangles lie on both sides of the edge and cover a disc of radius `margin` around the point
// where the ray passes (the origin's projection), each at |cos| >= kEdgeMinCos.
bool edgeSealed(const Context& c, const MeshEdge& e, Vec3 o, Vec3 dir) {
    const DVec3 d = toDouble(dir);
    const Projection proj(d);
    auto at = [&](Vec3 v) {
        P2 q;
        proj(toDouble(v), q.x, q.y);
        return q;
    };
    const MeshTopology& t = c.mesh->topology;
    P2 a = at(t.vertices[e.a]), b = at(t.vertices[e.b]), q = at(o);
    P2 opp[2];
    for (int k = 0; k < 2; ++k) {
        const Triangle& tri = c.scene.triangles[e.tri[k]];
        if (absCos(triangleNormal(tri), d) < kEdgeMinCos) return false;
        const auto& cs = t.corners[e.tri[k]];
        uint32_t o =
            cs[0] != e.a && cs[0] != e.b ? cs[0] : (cs[1] != e.a && cs[1] != e.b ? cs[1] : cs[2]);
        opp[k] = at(t.vertices[o]);
    }
    double s0 = side(a, b, opp[0]), s1 = side(a, b, opp[1]);
    if (!((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0))) return false;    // a fold seen edge-on
    if (windingNumber({a, opp[0], b, opp[1]}, q) == 0) return false;  // the ray passes outside
    for (int k = 0; k < 2; ++k)
        if (segmentDistance(q, a, opp[k]) < c.margin || segmentDistance(q, opp[k], b) < c.margin)
            return false;
    return true;
}

bool vertexSealed(const Context& c, uint32_t v, const std::vector<uint32_t>& link, Vec3 o,
                  Vec3 dir) {
    const DVec3 d = toDouble(dir);
    const MeshTopology& t = c.mesh->topology;
    for (uint32_t k = t.vertexStart[v]; k < t.vertexStart[v + 1]; ++k)
        if (absCos(triangleNormal(c.scene.triangles[t.vertexTriangles[k]]), d) < kVertexMinCos)
            return false;
    const Projection proj(d);
    P2 q;  // where the stored ray passes
    proj(toDouble(o), q.x, q.y);
    std::vector<P2> poly(link.size());
    for (size_t i = 0; i < link.size(); ++i)
        proj(toDouble(t.vertices[link[i]]), poly[i].x, poly[i].y);
    for (size_t i = 0; i < poly.size(); ++i)
        if (segmentDistance(q, poly[i], poly[(i + 1) % poly.size()]) < c.margin) return false;
    return windingNumber(poly, q) != 0;
}

double longestSide(const Triangle& t) {
    return std::max({length(toDouble(t.v1) - toDouble(t.v0)),
                     length(toDouble(t.v2) - toDouble(t.v1)),
                     length(toDouble(t.v0) - toDouble(t.v2))});
}

[[noreturn]] void notPlaced(const Context& c, const char* set, uint64_t placed, uint64_t n) {
    throw std::invalid_argument("ray set '" + std::string(set) + "': placed only " +
                                std::to_string(placed) + " of " + std::to_string(n) +
                                " rays that octrace trace accepts on '" + c.scene.name + "' in " +
                                std::to_string(kAttemptsPerRay) + " tries each");
}

void prepareTopology(Context& c) {
    if (!c.mesh) c.mesh = meshTargets(c.scene);
    if (!c.truth) {
        c.ownTruth = std::make_unique<DoubleTracer>(c.scene, TouchTolerance{0.0, 0.0});
        c.truth = c.ownTruth.get();
    }
}

// The seal's second half: the double-precision truth, on the stored float ray, hits one of the
// target's own triangles (ascending ids) within the default t tolerance of its t.
bool truthHitsTarget(const Context& c, Vec3 o, Vec3 dir, double t,
                     const std::vector<uint32_t>& own) {
    // Only a hit up to the target (and its tolerance) can decide: the query stops there.
    DoubleRay r = toDoubleRay(Ray{o, dir, 0.0f, INFINITY});
    const double tol = c.tTolerance / length(r.dir);
    r.tmax = (t + tol) * (1.0 + 1e-9);
    const Hit h = c.truth->closest(r);
    return h.prim >= 0 && std::binary_search(own.begin(), own.end(), uint32_t(h.prim)) &&
           std::fabs(double(h.t) - t) <= tol;
}

// One target ray of the edges or vertices set: up to kAttemptsPerRay draws (each `draw` aims one
// ray and says whether it is sealed); the first sealed one is kept, else the last whose row trace
// accepts, marked unsealed. Returns false when no draw gave such a row.
struct TargetDraw {
    Vec3 o, dir;
    RayTarget target;
};
struct TargetCounts {
    uint64_t unsealed = 0, untraceable = 0;
};
bool placeTarget(const std::function<bool(TargetDraw&)>& draw, RaySet& out, TargetCounts& n) {
    std::optional<TargetDraw> kept;
    for (int attempt = 0; attempt < kAttemptsPerRay; ++attempt) {
        TargetDraw d;
        const bool sealed = draw(d);
        if (!traceable(d.o, d.dir, 0.0f, INFINITY)) {
            ++n.untraceable;
            continue;
        }
        d.target.sealed = sealed;
        kept = d;
        if (sealed) break;
    }
    if (!kept) return false;
    n.unsealed += !kept->target.sealed;
    kept->target.row = out.count();
    out.targets.push_back(kept->target);
    push(out, kept->o, kept->dir, 0.0f, INFINITY);
    return true;
}

void noteTargets(const char* set, uint64_t n, const TargetCounts& k, RaySet& out) {
    if (k.unsealed > 0)
        out.notes.push_back(std::string(set) + ": " + std::to_string(k.unsealed) + " of " +
                            plural(n, "target", "targets") + " could not be sealed in " +
                            std::to_string(kAttemptsPerRay) +
                            " draws (kept, marked unsealed: not counted as checked for leaks)");
    if (k.untraceable > 0)
        out.notes.push_back(std::string(set) + ": " +
                            plural(k.untraceable, "draw was a row", "draws were rows") +
                            " octrace trace refuses, drawn again");
}

void edges(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    prepareTopology(c);
    if (n > 0 && c.mesh->interiorEdges.empty())
        throw std::invalid_argument("ray set 'edges': '" + c.scene.name +
                                    "' has no edge shared by exactly two triangles");
    const MeshTopology& t = c.mesh->topology;
    TargetCounts counts;
    for (uint64_t i = 0; i < n; ++i) {
        auto draw = [&](TargetDraw& d) {
            const MeshEdge& e =
                t.edges[c.mesh->interiorEdges[rng.below(c.mesh->interiorEdges.size())]];
            const Vec3 va = t.vertices[e.a], vb = t.vertices[e.b];
            const Vec3 p = va + (vb - va) * float(rng.range(0.2, 0.8));  // float, as a hit point
            const Triangle &ta = c.scene.triangles[e.tri[0]], &tb = c.scene.triangles[e.tri[1]];
            DVec3 front = triangleNormal(ta) * (1.0 / length(triangleNormal(ta))) +
                          triangleNormal(tb) * (1.0 / length(triangleNormal(tb)));
            Vec3 dir = unitVector(rng);
            if (dot(toDouble(dir), front) > 0) dir = -dir;  // coming from the front side
            const double r = std::max(longestSide(ta), longestSide(tb)) * rng.range(1.0, 3.0);
            double tt;
            aimAt(p, p - dir * float(r), d.o, d.dir, tt);
            d.target = {0,
                        tt,
                        e.a,
                        e.b,
                        va,
                        vb,
                        {std::min(e.tri[0], e.tri[1]), std::max(e.tri[0], e.tri[1])}};
            return edgeSealed(c, e, d.o, d.dir) &&
                   truthHitsTarget(c, d.o, d.dir, tt, d.target.triangles);
        };
        if (!placeTarget(draw, out, counts)) notPlaced(c, "edges", i, n);
    }
    noteTargets("edges", n, counts, out);
}

void vertices(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    prepareTopology(c);
    if (n > 0 && c.mesh->fanVertices.empty())
        throw std::invalid_argument("ray set 'vertices': '" + c.scene.name +
                                    "' has no vertex whose triangles close a fan around it");
    const MeshTopology& t = c.mesh->topology;
    TargetCounts counts;
    for (uint64_t i = 0; i < n; ++i) {
        auto draw = [&](TargetDraw& d) {
            const size_t pick = rng.below(c.mesh->fanVertices.size());
            const uint32_t v = c.mesh->fanVertices[pick];
            DVec3 front = {0, 0, 0};
            double r = 0.0;
            std::vector<uint32_t> fan;
            for (uint32_t k = t.vertexStart[v]; k < t.vertexStart[v + 1]; ++k) {
                const Triangle& tri = c.scene.triangles[t.vertexTriangles[k]];
                front = front + triangleNormal(tri);
                r = std::max(r, longestSide(tri));
                fan.push_back(t.vertexTriangles[k]);
            }
            std::sort(fan.begin(), fan.end());
            Vec3 dir = unitVector(rng);
            if (dot(toDouble(dir), front) > 0) dir = -dir;
            r *= rng.range(1.0, 3.0);
            const Vec3 p = t.vertices[v];
            double tt;
            aimAt(p, p - dir * float(r), d.o, d.dir, tt);
            d.target = {0, tt, v, v, p, p, std::move(fan)};
            return vertexSealed(c, v, c.mesh->links[pick], d.o, d.dir) &&
                   truthHitsTarget(c, d.o, d.dir, tt, d.target.triangles);
        };
        if (!placeTarget(draw, out, counts)) notPlaced(c, "vertices", i, n);
    }
    noteTargets("vertices", n, counts, out);
}

// A point inside triangle tri (uniform, computed in float as a tracer would).
Vec3 pointOn(Rng& rng, const Triangle& tri) {
    double u = rng.u01(), v = rng.u01();
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    return tri.v0 + (tri.v1 - tri.v0) * float(u) + (tri.v2 - tri.v0) * float(v);
}

void grazing(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    static const double kCos[5] = {3e-2, 1e-3, 1e-4, 1e-5, 1e-6};
    const std::vector<Triangle>& tris = c.scene.triangles;
    for (uint64_t i = 0; i < n; ++i) {
        const Triangle& tri = tris[rng.below(tris.size())];
        const Vec3 p = pointOn(rng, tri);
        DVec3 nrm = triangleNormal(tri);
        nrm = nrm * (1.0 / length(nrm));
        DVec3 g;
        do {  // a direction in the plane
            DVec3 r = toDouble(unitVector(rng));
            g = r - nrm * dot(r, nrm);
        } while (!(length(g) > 1e-3));
        g = g * (1.0 / length(g));
        // Three draws, one statement each: the operands of one expression may be evaluated in
        // any order, so a product of draws gave compiler-chosen rays. This is the order GCC 12
        // took, so the bytes (and the pinned checksum) are unchanged.
        const double cosine = kCos[rng.below(5)];
        const double scale = rng.range(0.5, 1.0);
        const double sign = rng.below(2) ? 1.0 : -1.0;
        double s = cosine * scale * sign;
        DVec3 dd = g * std::sqrt(1.0 - s * s) + nrm * s;
        const Vec3 d = {float(dd.x), float(dd.y), float(dd.z)};
        const float r = float(longestSide(tri) * rng.range(1.0, 2.0));
        push(out, p - d * r, normalize(d), 0.0f, INFINITY);
    }
}

void tminTmax(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    const std::vector<Triangle>& tris = c.scene.triangles;
    uint64_t untraceable = 0;
    for (uint64_t i = 0; i < n; ++i) {
        bool placed = false;
        // Drawn again while the row is one trace refuses: where the origin rounds onto the point
        // (triangles a float spacing wide) the direction is NaN, or the plane's distance inf.
        for (int attempt = 0; attempt < kAttemptsPerRay && !placed; ++attempt) {
            const Triangle& tri = tris[rng.below(tris.size())];
            const Vec3 p = pointOn(rng, tri);
            const DVec3 nrm = triangleNormal(tri);
            Vec3 d;
            do d = unitVector(rng);
            while (absCos(nrm, toDouble(d)) < 0.2);
            const float r = float(longestSide(tri) * rng.range(0.5, 1.5));
            Vec3 o = p, dir = d;
            float tmin = 0.0f, tmax = INFINITY;  // i % 4 == 0: starts on the surface
            if (i % 4 != 0) {
                o = p - d * r;
                dir = normalize(p - o);
                // The ray parameter where the stored float ray meets the triangle's plane.
                const double th =
                    dot(nrm, toDouble(tri.v0) - toDouble(o)) / dot(nrm, toDouble(dir));
                const float tf = float(th);
                if (i % 4 == 1) tmax = tf;                        // ends exactly at the surface
                if (i % 4 == 2) tmin = tf;                        // starts exactly there
                if (i % 4 == 3) tmax = std::nextafter(tf, 0.0f);  // ends one ulp short
            }
            placed = traceable(o, dir, tmin, tmax);
            if (placed)
                push(out, o, dir, tmin, tmax);
            else
                ++untraceable;
        }
        if (!placed) notPlaced(c, "tmin-tmax", i, n);
    }
    if (untraceable > 0)
        out.notes.push_back(
            "tmin-tmax: " + plural(untraceable, "draw was a row", "draws were rows") +
            " octrace trace refuses, drawn again");
}

// The running sum of the triangles' areas areaWeighted draws from, made before the sets are
// drawn (in parallel, makeRaySet).
void prepareAreas(Context& c) {
    std::vector<double>& sum = c.cumulativeArea;
    if (!sum.empty() || c.scene.kind != PrimKind::Triangles) return;
    double total = 0.0;
    for (const Triangle& tri : c.scene.triangles)
        sum.push_back(total += length(triangleNormal(tri)));
}

// A triangle with probability proportional to its area (so that pointOn is uniform over all).
size_t areaWeighted(Context& c, Rng& rng) {
    const std::vector<double>& sum = c.cumulativeArea;
    const size_t k =
        size_t(std::upper_bound(sum.begin(), sum.end(), rng.u01() * sum.back()) - sum.begin());
    return std::min(k, sum.size() - 1);
}

// The edge (welded ids, a < b) of triangle k nearest to p, in the plane z = const.
void nearestEdge(const Context& c, size_t k, Vec3 p, uint32_t& a, uint32_t& b) {
    const std::array<uint32_t, 3>& cs = c.mesh->topology.corners[k];
    auto at = [&](uint32_t v) {
        return P2{c.mesh->topology.vertices[v].x, c.mesh->topology.vertices[v].y};
    };
    const P2 q{p.x, p.y};
    double best = INFINITY;
    for (int e = 0; e < 3; ++e) {
        const double d = segmentDistance(q, at(cs[e]), at(cs[(e + 1) % 3]));
        if (d < best) {
            best = d;
            a = std::min(cs[e], cs[(e + 1) % 3]);
            b = std::max(cs[e], cs[(e + 1) % 3]);
        }
    }
}

// Aimed at a point of a slivers square; kept when the float ray crosses the plane inside it.
void slivers(Context& c, Rng& rng, uint64_t n, RaySet& out) {
    prepareTopology(c);
    const MeshTopology& t = c.mesh->topology;
    const Aabb& square = c.bounds;  // [0,1]^2 in the plane z = 0
    for (uint64_t i = 0; i < n; ++i) {
        bool placed = false;
        for (int attempt = 0; attempt < kAttemptsPerRay && !placed; ++attempt) {
            Vec3 p;
            uint32_t a = 0, b = 0;
            if (i % 4 == 2) {  // on an interior edge
                const MeshEdge& e =
                    t.edges[c.mesh->interiorEdges[rng.below(c.mesh->interiorEdges.size())]];
                const Vec3 va = t.vertices[e.a], vb = t.vertices[e.b];
                p = va + (vb - va) * float(rng.u01());
                a = e.a;
                b = e.b;
            } else if (i % 4 == 3) {  // at an interior vertex
                a = b = c.mesh->fanVertices[rng.below(c.mesh->fanVertices.size())];
                p = t.vertices[a];
            } else {  // uniform in the square
                const size_t k = areaWeighted(c, rng);
                p = pointOn(rng, c.scene.triangles[k]);
                nearestEdge(c, k, p, a, b);
            }
            // Three draws, one statement each (the operands of one expression may be evaluated
            // in any order): the slope, the azimuth by rejection from the square, the side.
            const double root = rng.range(kSliversMinSqrtCos, 1.0);
            const double cosine = root * root;
            double gx, gy, g2;
            do {
                gx = 2.0 * rng.u01() - 1.0;
                gy = 2.0 * rng.u01() - 1.0;
                g2 = gx * gx + gy * gy;
            } while (!(g2 > 1e-6 && g2 <= 1.0));
            const double along = std::sqrt((1.0 - cosine * cosine) / g2);
            const double side = rng.below(2) ? 1.0 : -1.0;
            const Vec3 d = {float(gx * along), float(gy * along), float(side * cosine)};
            const float r = float(rng.range(kSliversNear, kSliversFar));
            const Vec3 o = p - d * r;
            const Vec3 dir = normalize(p - o);
            if (!(dir.z != 0.0f)) continue;
            const double tt = (double(square.lo.z) - double(o.z)) / double(dir.z);
            const double x = double(o.x) + tt * double(dir.x), y = double(o.y) + tt * double(dir.y);
            if (!(tt > 0.0) || x < square.lo.x + c.margin || x > square.hi.x - c.margin ||
                y < square.lo.y + c.margin || y > square.hi.y - c.margin)
                continue;
            // No own triangles: the square seals the ray, whichever of its triangles is hit.
            out.targets.push_back({out.count(), tt, a, b, t.vertices[a], t.vertices[b], {}, true});
            push(out, o, dir, 0.0f, INFINITY);
            placed = true;
        }
        if (!placed) notPlaced(c, "slivers", i, n);
    }
}

void cameraRays(const FrameParams& f, RaySet& out) {
    // Sized once: growing by doubling would hold the old and the new array at once (1.5 times
    // the rows at 16384x16384, 8.6 GB of them).
    out.rays.reserve(out.rays.size() + 8 * uint64_t(f.width) * uint64_t(f.height));
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            Ray r = primaryRay(f.camera, x, y, f.width, f.height);
            push(out, r.org, r.dir, r.tmin, r.tmax);
        }
}

void shadowRays(const Scene& scene, const FrameParams& f, const TraceBatch& reference,
                RaySet& out) {
    RaySet cam;
    cameraRays(f, cam);
    const uint64_t n = cam.count();
    out.rays.reserve(out.rays.size() + 8 * n);  // at most a row per camera ray: never regrown
    std::vector<float> t(n);
    std::vector<int32_t> prim(n);
    reference({cam.rays.data(), t.data(), prim.data(), n});
    const PrimitivesView prims = primitivesView(scene);
    uint64_t untraceable = 0;
    for (uint64_t i = 0; i < n; ++i) {
        // A malformed reference hit is skipped, never indexed.
        if (prim[i] < 0 || uint32_t(prim[i]) >= prims.count || !std::isfinite(t[i])) continue;
        const ShadowQuery q = shadowQuery(f.shading, prims, cam.ray(i), {t[i], prim[i]});
        // A row trace would refuse is left out (the set is taken as given, never rebuilt).
        if (!q.cast) continue;
        if (traceable(q.ray.org, q.ray.dir, q.ray.tmin, q.ray.tmax))
            push(out, q.ray.org, q.ray.dir, q.ray.tmin, q.ray.tmax);
        else
            ++untraceable;
    }
    if (untraceable > 0)
        out.notes.push_back("shadow: " + plural(untraceable, "ray was a row", "rays were rows") +
                            " octrace trace refuses, left out");
}

// The frame of the camera sets, made once for both.
const FrameParams& frameOf(const Context& c, RaySet& out) {
    if (!out.frame) out.frame = makeFrame(c.scene.bounds(), c.camera);
    return *out.frame;
}

void camera(Context& c, Rng&, uint64_t, RaySet& out) { cameraRays(frameOf(c, out), out); }

void shadow(Context& c, Rng&, uint64_t, RaySet& out) {
    shadowRays(c.scene, frameOf(c, out), c.reference, out);
}

}  // namespace

const std::vector<RaySetDesc>& standardRaySets() {
    // id, name, seeded, needs triangles, needs slivers, needs a reference, adversarial,
    // generator, any-hit, slack on the ambiguous count
    static const std::vector<RaySetDesc> table = {
        {0, "camera", false, false, false, false, false, camera},
        {1, "shadow", false, false, false, true, false, shadow, true},
        {2, "around", true, false, false, false, false, around},
        {3, "inside", true, false, false, false, false, inside},
        {4, "axis", true, false, false, false, false, axis},
        {5, "edges", true, true, false, false, true, edges},
        {6, "vertices", true, true, false, false, true, vertices},
        {7, "grazing", true, true, false, false, true, grazing, false, 1.0},
        {8, "tmin-tmax", true, true, false, false, true, tminTmax},
        {9, "slivers", true, true, true, false, true, slivers},
    };
    return table;
}

const RaySetDesc* findRaySet(const std::string& name) {
    for (const RaySetDesc& k : standardRaySets())
        if (name == k.name) return &k;
    return nullptr;
}

std::string raySetNames() {
    std::string s;
    for (const RaySetDesc& k : standardRaySets())
        s += (s.empty() ? "" : ", ") + std::string(k.name);
    return s;
}

std::string raySetMisfit(const RaySetDesc& k, const Scene& scene) {
    if (k.needsTriangles && scene.kind != PrimKind::Triangles) return "needs a triangle mesh";
    if (k.needsSlivers && !isSliversScene(scene)) return "needs a slivers:N scene";
    return "";
}

const RaySetRange* RaySet::find(const std::string& name) const {
    for (const RaySetRange& r : sets)
        if (r.name == name) return &r;
    return nullptr;
}

std::vector<std::string> raySetsUnavailable(const Scene& scene,
                                            const std::vector<const RaySetDesc*>& sets) {
    std::vector<std::string> why(sets.size());
    std::optional<MeshTopology> topo;  // made once, when edges or vertices are asked
    for (size_t i = 0; i < sets.size(); ++i) {
        const RaySetDesc& k = *sets[i];
        const std::string misfit = raySetMisfit(k, scene);
        if (!misfit.empty()) {
            why[i] = "it " + misfit;
            continue;
        }
        if (k.generate != edges && k.generate != vertices) continue;
        if (!topo) topo = meshTopology(scene);
        if (k.generate == edges && std::none_of(topo->edges.begin(), topo->edges.end(),
                                                [](const MeshEdge& e) { return e.triangles == 2; }))
            why[i] = "'" + scene.name + "' has no edge shared by exactly two triangles";
        if (k.generate == vertices) {
            bool fan = false;
            for (uint32_t v = 0; v < topo->vertices.size() && !fan; ++v)
                fan = !vertexLink(*topo, v).empty();
            if (!fan)
                why[i] = "'" + scene.name + "' has no vertex whose triangles close a fan around it";
        }
    }
    return why;
}

uint64_t raySetPeakBytes(const RaySetSpec& spec) {
    const uint64_t rowBytes = 8 * sizeof(float);
    const uint64_t pixels =
        uint64_t(std::max(spec.camera.width, 0)) * uint64_t(std::max(spec.camera.height, 0));
    // A target row also keeps its RayTarget twice (the part's, then the joined set's) and the
    // ids of its triangles (a fan of a few).
    const uint64_t targetBytes = 2 * sizeof(RayTarget) + 64;
    uint64_t parts = 0, temporaries = 0, rows = 0;
    for (const RaySetDesc* k : spec.sets) {
        if (!k) continue;
        uint64_t n = k->seeded ? seededShare(spec, *k) : pixels;
        parts = saturatingAdd(parts, saturatingMul(n, rowBytes));
        rows = saturatingAdd(rows, n);
        if (k->generate == edges || k->generate == vertices || k->generate == slivers)
            parts = saturatingAdd(parts, saturatingMul(n, targetBytes));
        // The shadow set traces a camera set of its own first: its rows and the hits' t, prim.
        if (k->needsReference)
            temporaries = saturatingAdd(
                temporaries, saturatingMul(pixels, rowBytes + sizeof(float) + sizeof(int32_t)));
    }
    // The sets are drawn at once (in parallel), then joined into one array (one set: moved).
    const uint64_t joined = spec.sets.size() > 1 ? saturatingMul(rows, rowBytes) : 0;
    return saturatingAdd(parts, std::max(temporaries, joined));
}

uint64_t seededShare(const RaySetSpec& spec, const RaySetDesc& k) {
    uint64_t seeded = 0, index = 0;
    bool found = false;
    for (const RaySetDesc* s : spec.sets) {
        if (!s->seeded) continue;
        if (s == &k) {
            index = seeded;
            found = true;
        }
        ++seeded;
    }
    if (!found || seeded == 0) return 0;
    return spec.count / seeded + (index < spec.count % seeded ? 1 : 0);
}

RaySet makeRaySet(const Scene& scene, const RaySetSpec& spec, const TraceBatch& reference) {
    for (size_t i = 0; i < spec.sets.size(); ++i) {
        const RaySetDesc* k = spec.sets[i];
        if (!k) throw std::invalid_argument("ray set list holds no set (a name findRaySet missed)");
        for (size_t j = 0; j < i; ++j)
            if (k == spec.sets[j])
                throw std::invalid_argument("ray set '" + std::string(k->name) +
                                            "' is named twice");
        if (k->needsTriangles && scene.kind != PrimKind::Triangles)
            throw std::invalid_argument("ray set '" + std::string(k->name) +
                                        "' needs a triangle mesh; '" + scene.name +
                                        "' is a point cloud");
        if (k->needsSlivers && !isSliversScene(scene))
            throw std::invalid_argument("ray set '" + std::string(k->name) +
                                        "' needs a generated slivers:N scene, where every ray "
                                        "must hit; '" +
                                        scene.name + "' is not one (try slivers:2000)");
        if (k->needsReference && !reference)
            throw std::invalid_argument("ray set '" + std::string(k->name) +
                                        "' needs a reference tracer for the camera hits");
    }
    Context c(scene, spec.camera, reference);
    c.bounds = scene.bounds();
    c.root = rootCube(scene);
    c.mesh = spec.mesh;
    c.truth = spec.truth;
    c.centre = c.bounds.center();
    c.radius = 0.5f * length(c.bounds.extent());
    if (!(c.radius > 0.0f)) c.radius = 0.5f * length(c.root.extent());
    c.margin = kSealMargin * sceneExtent(scene);
    c.tTolerance = kDefaultRelativeTolerance * sceneExtent(scene);

    // What several sets share is made first; then every set is drawn from its own stream into
    // its own part, the sets in parallel (each part's bytes are those of a serial run), and the
    // parts joined in the spec's order.
    for (const RaySetDesc* k : spec.sets) {
        if (k->generate == edges || k->generate == vertices || k->generate == slivers)
            prepareTopology(c);
        if (k->needsTriangles) prepareAreas(c);
    }
    std::vector<RaySet> parts(spec.sets.size());
    std::vector<std::exception_ptr> failed(spec.sets.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t i = 0; i < int64_t(spec.sets.size()); ++i) {
        const RaySetDesc* k = spec.sets[size_t(i)];
        RaySet& part = parts[size_t(i)];
        try {
            Rng rng = streamFor(spec.seed, *k);
            part.rays.reserve(8 * seededShare(spec, *k));
            k->generate(c, rng, seededShare(spec, *k), part);
            // Every row is one `octrace trace` accepts: a generator that wrote another is a bug.
            for (uint64_t r = 0; r < part.count(); ++r) {
                const std::string why = rayRowProblem(&part.rays[8 * r]);
                if (!why.empty())
                    throw std::logic_error("ray set '" + std::string(k->name) + "' made row " +
                                           std::to_string(r) + ", which octrace trace refuses (" +
                                           why + "): a bug of its generator in ray_sets.cpp");
            }
        } catch (...) {
            failed[size_t(i)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
    RaySet out;
    uint64_t rows = 0;
    for (const RaySet& part : parts) rows += part.count();
    // One part is the set as it is (moved, not copied); several are joined, each freed once
    // copied, so that the parts and the whole are not all held at once.
    const bool single = parts.size() == 1;
    if (single)
        out.rays = std::move(parts[0].rays);
    else
        out.rays.reserve(8 * rows);
    for (size_t i = 0; i < parts.size(); ++i) {
        RaySet& part = parts[i];
        const uint64_t begin = single ? 0 : out.count();
        const uint64_t partRows = single ? rows : part.count();
        if (!single) {
            out.rays.insert(out.rays.end(), part.rays.begin(), part.rays.end());
            std::vector<float>().swap(part.rays);
        }
        for (RayTarget& t : part.targets) {
            t.row += begin;
            out.targets.push_back(std::move(t));
        }
        out.notes.insert(out.notes.end(), part.notes.begin(), part.notes.end());
        if (part.frame) out.frame = part.frame;
        out.sets.push_back({spec.sets[i]->name, begin, partRows});
    }
    out.mesh = c.mesh;
    return out;
}

std::shared_ptr<const MeshTargets> meshTargets(const Scene& scene) {
    auto m = std::make_shared<MeshTargets>();
    m->topology = meshTopology(scene);
    const MeshTopology& t = m->topology;
    for (size_t i = 0; i < t.edges.size(); ++i)
        if (t.edges[i].triangles == 2) m->interiorEdges.push_back(uint32_t(i));
    // Every vertex's link on its own (in parallel), then the closed fans in vertex order.
    std::vector<std::vector<uint32_t>> links(t.vertices.size());
    const int64_t nv = int64_t(t.vertices.size());
#pragma omp parallel for schedule(dynamic, 4096)
    for (int64_t v = 0; v < nv; ++v) links[size_t(v)] = vertexLink(t, uint32_t(v));
    for (uint32_t v = 0; v < t.vertices.size(); ++v) {
        if (links[v].empty()) continue;
        m->fanVertices.push_back(v);
        m->links.push_back(std::move(links[v]));
    }
    return m;
}

RaySet makeValidationRays(const Scene& scene, uint64_t n, uint64_t seed) {
    RaySetSpec spec;
    spec.sets = {findRaySet("around"), findRaySet("inside"), findRaySet("axis")};
    spec.count = n;
    spec.seed = seed;
    return makeRaySet(scene, spec);
}

uint64_t fnv1a64(const void* data, size_t bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < bytes; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string hex64(uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)v);
    return buf;
}

}  // namespace oct
