#include "validation/policy/double_tracer.h"

#include <algorithm>

namespace oct {
namespace {

double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

// Squared distance between segments p1q1 and p2q2 (Ericson, Real-Time Collision Detection,
// sec. 5.1.9), degenerate segments included.
double segmentSegmentDist2(DVec3 p1, DVec3 q1, DVec3 p2, DVec3 q2) {
    DVec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    double s, t;
    if (a <= 0.0 && e <= 0.0) return dot(r, r);
    if (a <= 0.0) {
        s = 0.0;
        t = clamp01(f / e);
    } else {
        double c = dot(d1, r);
        if (e <= 0.0) {
            t = 0.0;
            s = clamp01(-c / a);
        } else {
            double b = dot(d1, d2), denom = a * e - b * b;
            s = denom > 0.0 ? clamp01((b * f - c * e) / denom) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = clamp01(-c / a);
            } else if (t > 1.0) {
                t = 1.0;
                s = clamp01((b - c) / a);
            }
        }
    }
    DVec3 diff = (p1 + d1 * s) - (p2 + d2 * t);
    return dot(diff, diff);
}

// Distance from p to the segment a + s (b - a), s in [0, 1].
double pointSegmentDist(DVec3 p, DVec3 a, DVec3 b) {
    DVec3 ab = b - a;
    double l2 = dot(ab, ab);
    double s = l2 > 0.0 ? clamp01(dot(p - a, ab) / l2) : 0.0;
    return length(p - (a + ab * s));
}

// Distance from p to triangle abc, never below the true one beyond rounding, and accurate on
// slivers: the distance to the plane when p lies over the triangle (each edge's side decided
// from that edge's own endpoints), plus the tilt the normal's rounding can give it; else, and
// in any case at most, the distance to the nearest edge. (Ericson's closest-point formula,
// barycentrics as differences of products of dot products, put a point of a shared edge of
// slivers:2000 2.2e-5 off one of its triangles.) The normal's components carry an error of at
// most 2u (|x_j y_k| + |x_k y_j|) each (u = 2^-53; the edge vectors are exact, differences of
// floats); only its part across n tilts the plane.
double pointTriangleDist(DVec3 p, DVec3 a, DVec3 b, DVec3 c) {
    const double edges =
        std::min({pointSegmentDist(p, a, b), pointSegmentDist(p, b, c), pointSegmentDist(p, c, a)});
    const DVec3 ab = b - a, ac = c - a;
    const DVec3 n = cross(ab, ac);
    const double n2 = dot(n, n);
    if (!(n2 > 0.0)) return edges;  // a segment or a point
    if (dot(n, cross(ab, p - a)) < 0.0 || dot(n, cross(c - b, p - b)) < 0.0 ||
        dot(n, cross(a - c, p - c)) < 0.0)
        return edges;
    const double nl = std::sqrt(n2);
    const DVec3 err = DVec3{std::fabs(ab.y * ac.z) + std::fabs(ab.z * ac.y),
                            std::fabs(ab.z * ac.x) + std::fabs(ab.x * ac.z),
                            std::fabs(ab.x * ac.y) + std::fabs(ab.y * ac.x)} *
                      0x1p-52;
    // |e across n| <= sum_i |e_i| |axis i across n| = sum_i err_i sqrt(1 - n_i^2 / |n|^2).
    const double across = err.x * std::sqrt(std::max(0.0, 1.0 - n.x * n.x / n2)) +
                          err.y * std::sqrt(std::max(0.0, 1.0 - n.y * n.y / n2)) +
                          err.z * std::sqrt(std::max(0.0, 1.0 - n.z * n.z / n2));
    const double tilt = across / nl * length(p - a);
    return std::min(edges, std::fabs(dot(n, p - a)) / nl + tilt);
}

// Watertight ray/triangle test in double: the three signed volumes of the ray with each edge
// are computed from the same differences for both triangles sharing an edge (with opposite
// sign), so a ray through a shared edge hits at least one of them.
bool rayTriangle(const DoubleRay& r, DVec3 v0, DVec3 v1, DVec3 v2, double& t) {
    DVec3 a = v0 - r.org, b = v1 - r.org, c = v2 - r.org;
    double u = dot(r.dir, cross(b, c));
    double v = dot(r.dir, cross(c, a));
    double w = dot(r.dir, cross(a, b));
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    if (u + v + w == 0.0) return false;
    DVec3 n = cross(v1 - v0, v2 - v0);
    double nd = dot(n, r.dir);
    if (nd == 0.0) return false;
    t = dot(n, a) / nd;
    return t >= r.tmin && t <= r.tmax;
}

// Ray/sphere in double: the closest-approach discriminant and the stable roots.
bool raySphere(const DoubleRay& r, DVec3 c, double radius, double& tHit) {
    DVec3 f = r.org - c;
    double a = dot(r.dir, r.dir);
    double bp = -dot(f, r.dir);
    DVec3 l = f + r.dir * (bp / a);
    double r2 = radius * radius;
    double disc = r2 - dot(l, l);
    if (disc < 0.0) return false;
    double cc = dot(f, f) - r2;
    double q = bp + std::copysign(std::sqrt(a * disc), bp);
    double t0 = 0.0, t1 = 0.0;
    if (q != 0.0) {
        t0 = cc / q;
        t1 = q / a;
    }
    if (t0 > t1) std::swap(t0, t1);
    if (t0 >= r.tmin && t0 <= r.tmax) {
        tHit = t0;
        return true;
    }
    if (t1 >= r.tmin && t1 <= r.tmax) {
        tHit = t1;
        return true;
    }
    return false;
}

}  // namespace

const char* reasonName(int bit) {
    static const char* names[kReasonCount] = {
        "edge_or_vertex", "grazing",         "degenerate",    "tangent",     "range_end",
        "reference_off",  "terminator",      "not_rechecked", "invalid_hit", "missed_hit",
        "false_hit",      "t_outside_range", "off_surface"};
    return bit >= 0 && bit < kReasonCount ? names[bit] : "unknown";
}

std::string reasonNames(uint32_t reasons) {
    std::string s;
    for (int b = 0; b < kReasonCount; ++b)
        if (reasons & (1u << b)) {
            if (!s.empty()) s += ",";
            s += reasonName(b);
        }
    return s;
}

DoubleRay toDoubleRay(const Ray& r) {
    return {toDouble(r.org), toDouble(r.dir), double(r.tmin), double(r.tmax)};
}

namespace {

// Each primitive's box in double (exact: the float coordinates), for the BVH.
std::vector<DBox> primitiveBoxes(const Scene& scene) {
    std::vector<DBox> boxes(scene.primitiveCount());
    for (size_t i = 0; i < boxes.size(); ++i) {
        DBox& b = boxes[i];
        if (scene.kind == PrimKind::Triangles) {
            const Triangle& t = scene.triangles[i];
            const Vec3 v[3] = {t.v0, t.v1, t.v2};
            for (int a = 0; a < 3; ++a) {
                b.lo[a] = std::min({double(v[0][a]), double(v[1][a]), double(v[2][a])});
                b.hi[a] = std::max({double(v[0][a]), double(v[1][a]), double(v[2][a])});
            }
        } else {
            const Sphere& sp = scene.spheres[i];
            for (int a = 0; a < 3; ++a) {
                b.lo[a] = double(sp.center[a]) - double(sp.radius);
                b.hi[a] = double(sp.center[a]) + double(sp.radius);
            }
        }
    }
    return boxes;
}

// The BVH's growth: the touch distance (touchiness concerns primitives that close to a
// segment), and at least a relative 1e-12 of the coordinates' magnitude, so that a hit the
// double test accepts by rounding at an edge is inside its primitive's grown box.
double bvhPad(const Scene& scene, double touchDistance) {
    const Aabb b = scene.bounds();
    double m = 0.0;
    for (int a = 0; a < 3; ++a)
        m = std::max({m, std::fabs(double(b.lo[a])), std::fabs(double(b.hi[a]))});
    return std::max(touchDistance, 1e-12 * m);
}

}  // namespace

DoubleTracer::DoubleTracer(const Scene& scene, TouchTolerance tol)
    : scene_(&scene),
      count_(scene.primitiveCount()),
      tol_(tol),
      pad_(bvhPad(scene, tol.distance)),
      bvh_(primitiveBoxes(scene), pad_) {
    Aabb b = scene.bounds();
    DVec3 lo = toDouble(b.lo), hi = toDouble(b.hi);
    sceneCentre_ = (lo + hi) * 0.5;
    sceneRadius_ = 0.5 * length(hi - lo);
    boundCentre_.resize(count_);
    boundRadius_.resize(count_);
    for (uint32_t i = 0; i < count_; ++i) {
        if (scene.kind == PrimKind::Triangles) {
            const Triangle& t = scene.triangles[i];
            DVec3 v[3] = {toDouble(t.v0), toDouble(t.v1), toDouble(t.v2)};
            DVec3 c = (v[0] + v[1] + v[2]) * (1.0 / 3.0);
            double r = 0.0;
            for (const DVec3& p : v) r = std::max(r, length(p - c));
            boundCentre_[i] = c;
            boundRadius_[i] = r * (1.0 + 1e-12);
            largestDiameter_ = std::max(largestDiameter_, diameter(i));
        } else {
            boundCentre_[i] = toDouble(scene.spheres[i].center);
            boundRadius_[i] = double(scene.spheres[i].radius);
            largestDiameter_ = std::max(largestDiameter_, 2.0 * boundRadius_[i]);
        }
    }
}

bool DoubleTracer::hit(uint32_t prim, const DoubleRay& r, double& t) const {
    if (prim >= count_) return false;
    if (scene_->kind == PrimKind::Triangles) {
        const Triangle& tri = scene_->triangles[prim];
        return rayTriangle(r, toDouble(tri.v0), toDouble(tri.v1), toDouble(tri.v2), t);
    }
    const Sphere& s = scene_->spheres[prim];
    return raySphere(r, toDouble(s.center), double(s.radius), t);
}

Hit DoubleTracer::closestBrute(const DoubleRay& r) const {
    double bestT = INFINITY;
    int32_t best = -1;
    for (uint32_t i = 0; i < count_; ++i) {
        double t;
        if (hit(i, r, t) && t < bestT) {
            bestT = t;
            best = int32_t(i);
        }
    }
    return {best >= 0 ? float(bestT) : INFINITY, best};
}

std::vector<std::pair<double, uint32_t>> DoubleTracer::allHitsBrute(const DoubleRay& r) const {
    std::vector<std::pair<double, uint32_t>> out;
    for (uint32_t i = 0; i < count_; ++i) {
        double t;
        if (hit(i, r, t)) out.push_back({t, i});
    }
    std::sort(out.begin(), out.end());
    return out;
}

double DoubleTracer::clipFar(const DoubleRay& r, double tol) const {
    // Nothing lies beyond the scene's bounding sphere: clip an infinite ray there so the
    // distance computations below work on a finite segment.
    double dl = length(r.dir);
    double far = (length(r.org - sceneCentre_) + sceneRadius_ + tol) / dl;
    return std::max(r.tmin, std::min(r.tmax, far));
}

uint32_t DoubleTracer::triangleTouchiness(uint32_t prim, const DoubleRay& r, double tFar,
                                          double tol) const {
    const Triangle& tri = scene_->triangles[prim];
    DVec3 v[3] = {toDouble(tri.v0), toDouble(tri.v1), toDouble(tri.v2)};
    DVec3 p = r.org + r.dir * r.tmin, q = r.org + r.dir * tFar;
    double edgeDist = INFINITY;
    for (int i = 0; i < 3; ++i)
        edgeDist = std::min(edgeDist, std::sqrt(segmentSegmentDist2(p, q, v[i], v[(i + 1) % 3])));
    double endDist = pointTriangleDist(p, v[0], v[1], v[2]);
    if (std::isfinite(r.tmax) && r.tmax <= tFar)
        endDist = std::min(endDist, pointTriangleDist(q, v[0], v[1], v[2]));
    // Distance from the segment to the closed triangle: 0 when it crosses, else attained at an
    // end of the segment or on the triangle's boundary.
    DoubleRay seg = r;
    seg.tmax = tFar;
    double t;
    double dist = rayTriangle(seg, v[0], v[1], v[2], t) ? 0.0 : std::min(edgeDist, endDist);
    if (dist > tol) return 0;  // far from this triangle: nothing here can flip

    uint32_t reasons = 0;
    if (edgeDist <= tol) reasons |= kEdgeOrVertex;
    if (endDist <= tol) reasons |= kRangeEnd;
    DVec3 n = cross(v[1] - v[0], v[2] - v[0]);
    double nl = length(n);
    double maxEdge = std::max({length(v[1] - v[0]), length(v[2] - v[1]), length(v[0] - v[2])});
    // Smallest altitude = twice the area over the longest edge.
    if (!(nl > tol * maxEdge)) reasons |= kDegenerate;
    double cosine = nl > 0.0 ? std::fabs(dot(n, r.dir)) / (nl * length(r.dir)) : 0.0;
    if (cosine <= tol_.grazingCos) reasons |= kGrazing;
    return reasons;
}

uint32_t DoubleTracer::sphereTouchiness(uint32_t prim, const DoubleRay& r, double tFar,
                                        double tol) const {
    const Sphere& s = scene_->spheres[prim];
    DVec3 c = toDouble(s.center);
    double radius = double(s.radius);
    uint32_t reasons = 0;
    DVec3 p = r.org + r.dir * r.tmin, q = r.org + r.dir * tFar;
    if (std::fabs(pointSegmentDist(c, p, q) - radius) <= tol) reasons |= kTangent;
    bool endNear = std::fabs(length(p - c) - radius) <= tol;
    if (std::isfinite(r.tmax) && r.tmax <= tFar)
        endNear = endNear || std::fabs(length(q - c) - radius) <= tol;
    if (endNear) reasons |= kRangeEnd;
    return reasons;
}

uint32_t DoubleTracer::touchiness(uint32_t prim, const DoubleRay& r, double distance) const {
    if (prim >= count_) return 0;
    const double tol = touchDistance(distance);
    double tFar = clipFar(r, tol);
    return scene_->kind == PrimKind::Triangles ? triangleTouchiness(prim, r, tFar, tol)
                                               : sphereTouchiness(prim, r, tFar, tol);
}

double DoubleTracer::distanceTo(uint32_t prim, DVec3 p) const {
    if (prim >= count_) return INFINITY;
    if (scene_->kind == PrimKind::Triangles) {
        const Triangle& t = scene_->triangles[prim];
        return pointTriangleDist(p, toDouble(t.v0), toDouble(t.v1), toDouble(t.v2));
    }
    const Sphere& s = scene_->spheres[prim];
    return std::fabs(length(p - toDouble(s.center)) - double(s.radius));
}

namespace {

// A triangle in the ray's sheared frame of Woop, Benthin & Wald's watertight test (JCGT 2013),
// in double: the vertices relative to the origin, sheared so that the ray runs along +z, their
// edge functions, and the t where the ray's line crosses the triangle's plane (the mean of the
// z weighted by the edge functions). `det` 0: the ray is parallel to the plane (or d is 0).
struct ShearedTriangle {
    double x[3], y[3], z[3], pz[3];
    double e[3], det = 0.0, t = INFINITY;
};

ShearedTriangle shear(const Triangle& tri, const DoubleRay& r) {
    ShearedTriangle s;
    const double d[3] = {r.dir.x, r.dir.y, r.dir.z}, o[3] = {r.org.x, r.org.y, r.org.z};
    int kz = 0;
    for (int a = 1; a < 3; ++a)
        if (std::fabs(d[a]) > std::fabs(d[kz])) kz = a;
    const int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (d[kz] == 0.0) return s;
    const double sx = -d[kx] / d[kz], sy = -d[ky] / d[kz], sz = 1.0 / d[kz];
    const Vec3 v[3] = {tri.v0, tri.v1, tri.v2};
    for (int i = 0; i < 3; ++i) {
        const double p[3] = {double(v[i].x) - o[0], double(v[i].y) - o[1], double(v[i].z) - o[2]};
        s.pz[i] = p[kz];
        s.x[i] = p[kx] + sx * p[kz];
        s.y[i] = p[ky] + sy * p[kz];
        s.z[i] = p[kz] * sz;
    }
    s.e[0] = s.x[1] * s.y[2] - s.y[1] * s.x[2];
    s.e[1] = s.x[2] * s.y[0] - s.y[2] * s.x[0];
    s.e[2] = s.x[0] * s.y[1] - s.y[0] * s.x[1];
    s.det = s.e[0] + s.e[1] + s.e[2];
    if (s.det != 0.0) s.t = (s.e[0] * s.z[0] + s.e[1] * s.z[1] + s.e[2] * s.z[2]) / s.det;
    return s;
}

}  // namespace

double DoubleTracer::planeCrossing(uint32_t prim, const DoubleRay& r) const {
    if (prim >= count_ || scene_->kind != PrimKind::Triangles) return NAN;
    const ShearedTriangle s = shear(scene_->triangles[prim], r);
    return s.det == 0.0 ? NAN : s.t;
}

double DoubleTracer::floatTError(uint32_t prim, const DoubleRay& r) const {
    if (prim >= count_ || scene_->kind != PrimKind::Triangles) return 0.0;
    const ShearedTriangle s = shear(scene_->triangles[prim], r);
    if (s.det == 0.0) return INFINITY;
    const double *x = s.x, *y = s.y, *z = s.z, *pz = s.pz, det = s.det, t = s.t;
    // PBRT's gamma(n) for single precision: n u / (1 - n u), u = 2^-24.
    auto gamma = [](int n) { return n * 0x1p-24 / (1.0 - n * 0x1p-24); };
    auto max3 = [](double a, double b, double c) {
        return std::max({std::fabs(a), std::fabs(b), std::fabs(c)});
    };
    const double maxXt = max3(x[0], x[1], x[2]), maxYt = max3(y[0], y[1], y[2]);
    const double maxZt = max3(z[0], z[1], z[2]);
    // Translation and shear round the sheared x and y by a few units of the largest unscaled z
    // as well (PBRT takes the scaled one, the same for a unit direction).
    const double maxZ = std::max(maxZt, max3(pz[0], pz[1], pz[2]));
    const double deltaX = gamma(5) * (maxXt + maxZ), deltaY = gamma(5) * (maxYt + maxZ);
    const double deltaE = 2.0 * (gamma(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    // t is the mean of the z_i weighted by the edge functions: their errors (delta_e each) move
    // it by at most 3 delta_e / |det| times the z_i's spread around t (PBRT bounds that spread by
    // max |z_i|, far too loose for a small triangle far away); the z_i themselves are off by
    // gamma_3 max |z_i|, and the sums and the division round by gamma_4 of it.
    const double spread = max3(z[0] - t, z[1] - t, z[2] - t);
    return 3.0 * deltaE * spread / std::fabs(det) + (gamma(3) + gamma(4)) * maxZt;
}

double DoubleTracer::diameter(uint32_t prim) const {
    if (prim >= count_) return 0.0;
    if (scene_->kind == PrimKind::Spheres) return 2.0 * double(scene_->spheres[prim].radius);
    const Triangle& t = scene_->triangles[prim];
    const DVec3 a = toDouble(t.v0), b = toDouble(t.v1), c = toDouble(t.v2);
    return std::max({length(b - a), length(c - b), length(a - c)});
}

int32_t DoubleTracer::nearestToBrute(DVec3 p, double& dist) const {
    int32_t best = -1;
    dist = INFINITY;
    for (uint32_t i = 0; i < count_; ++i) {
        // The bounding sphere bounds the distance from below: skip what cannot be nearer.
        double lower = length(p - boundCentre_[i]) - boundRadius_[i];
        if (lower > dist) continue;
        double d = distanceTo(i, p);
        if (d < dist) {
            dist = d;
            best = int32_t(i);
        }
    }
    return best;
}

uint32_t DoubleTracer::touchinessNearBrute(const DoubleRay& r, double distance) const {
    const double tol = touchDistance(distance);
    double tFar = clipFar(r, tol);
    DVec3 p = r.org + r.dir * r.tmin, q = r.org + r.dir * tFar;
    uint32_t reasons = 0;
    for (uint32_t i = 0; i < count_; ++i) {
        if (pointSegmentDist(boundCentre_[i], p, q) > boundRadius_[i] + tol) continue;
        reasons |= scene_->kind == PrimKind::Triangles ? triangleTouchiness(i, r, tFar, tol)
                                                       : sphereTouchiness(i, r, tFar, tol);
    }
    return reasons;
}

// --- the accelerated queries: the BVH proposes, the per-primitive tests above decide ----------

Hit DoubleTracer::closest(const DoubleRay& r) const {
    double t;
    const int32_t prim = closest(r, t);
    return {prim >= 0 ? float(t) : INFINITY, prim};
}

int32_t DoubleTracer::closest(const DoubleRay& r, double& tOut) const {
    double bestT = INFINITY;
    int32_t best = -1;
    const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
    bvh_.segment(o, d, r.tmin, r.tmax, [&](uint32_t i) {
        double t;
        if (hit(i, r, t) && (t < bestT || (t == bestT && int32_t(i) < best))) {
            bestT = t;
            best = int32_t(i);
        }
        return std::min(bestT,
                        r.tmax);  // boxes entered beyond the best hit cannot hold a nearer one
    });
    tOut = bestT;
    return best;
}

std::vector<std::pair<double, uint32_t>> DoubleTracer::allHits(const DoubleRay& r) const {
    std::vector<std::pair<double, uint32_t>> out;
    const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
    bvh_.segment(o, d, r.tmin, r.tmax, [&](uint32_t i) {
        double t;
        if (hit(i, r, t)) out.push_back({t, i});
        return r.tmax;
    });
    std::sort(out.begin(), out.end());
    return out;
}

int32_t DoubleTracer::nearestTo(DVec3 p, double& dist) const {
    int32_t best = -1;
    dist = INFINITY;
    const double q[3] = {p.x, p.y, p.z};
    bvh_.nearest(q, dist, [&](uint32_t i) {
        const double d = distanceTo(i, p);
        if (d < dist || (d == dist && int32_t(i) < best)) best = int32_t(i);
        return d;
    });
    return best;
}

uint32_t DoubleTracer::touchinessNear(const DoubleRay& r, double distance) const {
    const double tol = touchDistance(distance);
    const double tFar = clipFar(r, tol);
    const DVec3 p = r.org + r.dir * r.tmin, q = r.org + r.dir * tFar;
    uint32_t reasons = 0;
    const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
    // Boxes are grown by pad_; a larger touch distance grows them by the rest.
    bvh_.segment(
        o, d, r.tmin, tFar,
        [&](uint32_t i) {
            if (!(pointSegmentDist(boundCentre_[i], p, q) > boundRadius_[i] + tol))
                reasons |= scene_->kind == PrimKind::Triangles ? triangleTouchiness(i, r, tFar, tol)
                                                               : sphereTouchiness(i, r, tFar, tol);
            return tFar;
        },
        tol > pad_ ? tol - pad_ : 0.0);
    return reasons;
}

}  // namespace oct
