#include "validation/policy/ray_definitions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace oct {
namespace {

constexpr double kPi = 3.14159265358979323846;

double maxAbs(DVec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// How far the nearest float lies from v, per component at most (0 for a float).
double floatRounding(DVec3 v) {
    auto r = [](double c) { return std::fabs(double(roundToFloat(c)) - c); };
    return std::max({r(v.x), r(v.y), r(v.z)});
}

}  // namespace

float roundToFloat(double v) {
    // The largest float, (2 - 2^-23) 2^127, plus half its ulp: from there on the nearest
    // (ties to even: the largest float's last bit is odd) is infinity.
    constexpr double kOverflow = 0x1.ffffffp127;
    if (std::fabs(v) >= kOverflow) return v > 0 ? INFINITY : -INFINITY;
    return static_cast<float>(v);
}

ReferenceFrame referenceFrame(const Aabb& b, const CameraOptions& o) {
    ReferenceFrame f;
    f.width = o.width;
    f.height = o.height;
    const DVec3 lo = toDouble(b.lo), hi = toDouble(b.hi);
    const DVec3 centre = (lo + hi) * 0.5;
    f.radius = 0.5 * length(hi - lo);
    if (!(f.radius > 0.0)) f.radius = 1.0;
    f.tanHalf = std::tan(0.5 * double(o.fovDegrees) * kPi / 180.0);
    f.aspect = double(o.width) / double(o.height);
    // The bounding sphere fits the smaller of the two fields of view, plus 5%.
    const double halfMin = std::atan(f.tanHalf * std::min(1.0, f.aspect));
    const double distance = 1.05 * f.radius / std::sin(halfMin);
    f.target = o.target ? toDouble(*o.target) : centre;
    f.targetError = o.target ? 0.0 : floatRounding(centre);
    f.eye = o.eye ? toDouble(*o.eye) : f.target + DVec3{0.0, 0.0, distance};
    const DVec3 upHint = o.up ? toDouble(*o.up) : DVec3{0.0, 1.0, 0.0};
    const DVec3 view = f.target - f.eye;
    const DVec3 side = cross(view, upHint);
    if (!(length(view) > 0.0) || !(length(side) > 0.0))
        throw FrameError(
            "reference camera: the eye equals the target or the up hint is parallel "
            "to the view; makeFrame refuses such options");
    f.forward = normalize(view);
    f.right = normalize(side);
    f.up = cross(f.right, f.forward);
    f.light = o.light ? toDouble(*o.light) : f.eye + f.up * f.radius + f.right * f.radius;
    f.shadowBias = 1e-5 * 2.0 * f.radius;
    f.scale = std::max({maxAbs(f.eye), maxAbs(f.target), maxAbs(f.light), length(view), f.radius});
    return f;
}

DoubleRay referencePrimaryRay(const ReferenceFrame& f, int x, int y) {
    const double sx = 2.0 * (double(x) + 0.5) / double(f.width) - 1.0;
    const double sy = 1.0 - 2.0 * (double(y) + 0.5) / double(f.height);
    const DVec3 d = f.forward + f.right * (sx * f.tanHalf * f.aspect) + f.up * (sy * f.tanHalf);
    return {f.eye, normalize(d), 0.0, INFINITY};
}

ReferenceShadowRay referenceShadowRay(const ReferenceFrame& f, const Scene& scene,
                                      const DoubleRay& primary, double t, uint32_t prim) {
    constexpr double u = kFloatUnitRoundoff;
    ReferenceShadowRay s;
    const DVec3 p = primary.org + primary.dir * t;
    DVec3 n;
    if (scene.kind == PrimKind::Triangles) {
        const Triangle& tri = scene.triangles[prim];
        const DVec3 e1 = toDouble(tri.v1) - toDouble(tri.v0);
        const DVec3 e2 = toDouble(tri.v2) - toDouble(tri.v0);
        n = cross(e1, e2);
        // Each float edge is the exact one rounded once (u relative); the cross product's
        // components cancel by |e1| |e2| / |e1 x e2| (1 / sin of the angle between the edges).
        s.normalError = 8.0 * u * length(e1) * length(e2) / length(n);
    } else {
        const Sphere& sp = scene.spheres[prim];
        n = p - toDouble(sp.center);
        // The float hit point is rounded by u times the magnitudes of its sum, the difference
        // with the centre once more; a normal turns by that over its length.
        s.normalError =
            8.0 * u *
            (maxAbs(primary.org) + t * maxAbs(primary.dir) + maxAbs(toDouble(sp.center))) /
            length(n);
    }
    n = normalize(n);
    s.viewCos = dot(n, primary.dir) / length(primary.dir);
    s.normal = s.viewCos > 0.0 ? -n : n;
    const DVec3 origin = p + s.normal * f.shadowBias;
    const DVec3 toLight = f.light - origin;
    const double distance = length(toLight);
    s.ray = {origin, toLight * (1.0 / distance), 0.0, distance};
    s.lightCos = dot(s.normal, s.ray.dir);
    return s;
}

ReferenceScaling referenceScaledRow(const float* row) {
    const double largest =
        std::max({std::fabs(double(row[3])), std::fabs(double(row[4])), std::fabs(double(row[5]))});
    ReferenceScaling s;
    std::frexp(largest, &s.e);  // largest = m 2^e, m in [0.5, 1)
    for (int i = 0; i < 3; ++i) s.dir[i] = roundToFloat(std::ldexp(double(row[3 + i]), -s.e));
    s.tmin = roundToFloat(std::ldexp(double(row[6]), s.e));
    s.tmax = roundToFloat(std::ldexp(double(row[7]), s.e));
    return s;
}

float referenceUnscaledT(float t, int e) { return roundToFloat(std::ldexp(double(t), -e)); }

double angleBetween(DVec3 a, DVec3 b) {
    const DVec3 c = cross(a, b);
    const double sin2 = dot(c, c) / (dot(a, a) * dot(b, b));
    // The sine is the angle to within a relative angle^2 / 6 (tolerances are a few 1e-6 rad);
    // beyond a right angle, anything above pi / 2 will do for a check.
    return dot(a, b) > 0.0 ? std::sqrt(sin2) : 2.0;
}

namespace {

double maxAbsOf(DVec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

CameraOptions fromEye(CameraOptions o, Vec3 eye) {
    o.eye = eye;
    return o;
}

}  // namespace

PrimaryRayJudge::PrimaryRayJudge(const Aabb& b, const CameraOptions& o, Vec3 e)
    : def(referenceFrame(b, o)), seen(referenceFrame(b, fromEye(o, e))), eye(e) {
    constexpr double u = kFloatUnitRoundoff;
    // The eye: rounded by the float arithmetic of the default framing, u times its magnitude.
    eyeTolerance = 16.0 * u * def.scale;
    eyeRatio = maxAbsOf(toDouble(e) - def.eye) / eyeTolerance;
    // Each direction is the definition's to a few rounding errors of the basis and the sum,
    // plus the turn that the rounding of a default target (the box's centre) gives the view.
    dirTolerance = 16.0 * u + 4.0 * def.targetError / length(seen.target - seen.eye);
    unitTolerance = 8.0 * u;
}

double PrimaryRayJudge::rayRatio(const Ray& k, int x, int y) const {
    const bool sameEye = k.org.x == eye.x && k.org.y == eye.y && k.org.z == eye.z;
    if (!sameEye || !(k.tmin == 0.0f && k.tmax == INFINITY)) return INFINITY;
    const DVec3 kd = toDouble(k.dir);
    const DoubleRay d = referencePrimaryRay(seen, x, y);
    return std::max(angleBetween(kd, d.dir) / dirTolerance, unitError(kd) / unitTolerance);
}

RayDefinitionReport checkCameraRows(const Aabb& b, const CameraOptions& o, const float* rows,
                                    uint64_t count) {
    RayDefinitionReport rep;
    const uint64_t pixels = uint64_t(o.width) * uint64_t(o.height);
    rep.scope = std::to_string(count) + " camera rows of a " + std::to_string(o.width) + "x" +
                std::to_string(o.height) + " frame";
    if (count != pixels) {
        rep.judge(INFINITY, [&] {
            return "the camera set has " + std::to_string(count) + " rows for " +
                   std::to_string(pixels) + " pixels";
        });
        return rep;
    }
    if (count == 0) return rep;
    const PrimaryRayJudge judge(b, o, {rows[0], rows[1], rows[2]});
    for (uint64_t i = 0; i < count; ++i) {
        const float* r = rows + 8 * i;
        const Ray k{{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, r[6], r[7]};
        const int x = int(i % uint64_t(o.width)), y = int(i / uint64_t(o.width));
        rep.judge(judge.ratio(k, x, y), [&] {
            const DoubleRay d = referencePrimaryRay(judge.seen, x, y);
            char line[400];
            std::snprintf(line, sizeof line,
                          "camera row %llu (pixel %d,%d): org %.9g,%.9g,%.9g dir %.9g,%.9g,%.9g "
                          "[%g, %g], the definition's dir %.9g,%.9g,%.9g from the eye "
                          "%.9g,%.9g,%.9g",
                          (unsigned long long)i, x, y, r[0], r[1], r[2], r[3], r[4], r[5], r[6],
                          r[7], d.dir.x, d.dir.y, d.dir.z, judge.def.eye.x, judge.def.eye.y,
                          judge.def.eye.z);
            return std::string(line);
        });
    }
    return rep;
}

}  // namespace oct
