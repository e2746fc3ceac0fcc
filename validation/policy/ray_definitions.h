// The kernel's three ray constructions written again from their definitions (docs/VALIDATION.md,
// "The kernel's rays against their definitions"), in double, sharing no code with core/render:
// the pinhole camera of makeFrame and primaryRay, the shadow ray of shadowQuery, and trace's
// power-of-two scaling (scaledRay, unscaledT). Every other check feeds the reference tracer the
// kernel's own rays, so a fault in this code is made on both sides and agrees with itself;
// validate's camera, shadow-ray and ray-scaling checks (validation/checks/) compare the kernel's
// rays with these instead.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/aabb.h"
#include "core/geometry/vec3t.h"
#include "core/render/frame.h"
#include "core/scene/scene.h"
#include "validation/policy/double_tracer.h"

namespace oct {

// The unit roundoff of float (2^-24): every tolerance below is a multiple of it.
constexpr double kFloatUnitRoundoff = 0x1p-24;

// A frame by its definition (makeFrame's comment in core/render/frame.h): the eye, the unit
// basis, the image plane's half extents, the light and the shadow ray's lift.
struct ReferenceFrame {
    int width = 0, height = 0;
    DVec3 eye, target;
    // How far the float target the kernel can hold lies from this one (per component): the
    // default target, the box's centre, is rounded to float; a given one is a float already.
    double targetError = 0.0;
    DVec3 forward, right, up;  // unit; right = forward x up hint, up = right x forward
    double tanHalf = 0.0;      // tan(fov / 2): the image plane's half height at distance 1
    double aspect = 0.0;       // width / height: its half width is tanHalf * aspect
    DVec3 light;
    double radius = 0.0;      // of the scene box's bounding sphere (1 for a point-sized box)
    double shadowBias = 0.0;  // 1e-5 of the scene box's diagonal
    // The largest magnitude the frame's float arithmetic handles (eye, target, light, the view
    // distance, the radius): positions derived from it are rounded by u times this, no more.
    double scale = 0.0;
};

// Throws FrameError for options makeFrame refuses (the checks only pass options it accepted).
ReferenceFrame referenceFrame(const Aabb& sceneBounds, const CameraOptions& o);

// The ray through the centre of pixel (x, y), row 0 at the top: from the eye along
// forward + sx * tanHalf * aspect * right + sy * tanHalf * up, unit, over [0, +inf), where
// sx = 2 (x + 1/2) / width - 1 and sy = 1 - 2 (y + 1/2) / height.
DoubleRay referencePrimaryRay(const ReferenceFrame& f, int x, int y);

// The shadow ray of a primary hit by its definition (docs/ARCHITECTURE.md, "The kernel"): from
// the hit point o + t d of the primary ray as traced, lifted by the frame's bias along the
// primitive's unit geometric normal turned to face the primary ray, towards the light, unit,
// over [0, distance to the light]; cast only when the lifted normal faces the light.
struct ReferenceShadowRay {
    DoubleRay ray;
    DVec3 normal;           // unit, facing the primary ray
    double viewCos = 0.0;   // cos(geometric normal, primary direction) before turning it
    double lightCos = 0.0;  // dot(normal, ray.dir): cast when > 0
    // How far the float normal of this primitive at this point may turn by rounding (radians):
    // a triangle's cross product of two float edges, a sphere's hit point minus its centre.
    double normalError = 0.0;
};
ReferenceShadowRay referenceShadowRay(const ReferenceFrame& f, const Scene& scene,
                                      const DoubleRay& primary, double t, uint32_t prim);

// trace's scaling of one ray row (ox oy oz dx dy dz tmin tmax) by its definition
// (core/render/kernel.h, above powerOfTwo): e is frexp's exponent of the direction's largest
// |component| (so that it lies in [0.5, 1) after scaling), the direction multiplied by 2^-e,
// tmin and tmax by 2^e, each rounded once to float (std::ldexp in double is exact).
struct ReferenceScaling {
    int e = 0;
    float dir[3] = {0, 0, 0};
    float tmin = 0.0f, tmax = 0.0f;
};
// The row's direction must have a finite, non-zero largest component.
ReferenceScaling referenceScaledRow(const float* row);
// A t on the scaled ray back in the row's units: t * 2^-e rounded once to float.
float referenceUnscaledT(float t, int e);
// v rounded to the nearest float (ties to even), +-inf past the largest float's half ulp: the
// conversion written out, so that an out-of-range double is not undefined behaviour.
float roundToFloat(double v);

// One comparison of the kernel's rays with their definitions, the typed result of validate's
// camera, shadow-ray and ray-scaling checks.
struct RayDefinitionReport {
    std::string scope;      // what was compared, for the summary ("4 frames: 256x256, ...")
    uint64_t compared = 0;  // rays (or decisions) held to the definition
    // Left to rounding by the definition itself (a surface edge-on to the ray or to the light, a
    // normal that rounding may turn by more than a quarter of the lift): counted, not judged.
    uint64_t unjudged = 0;
    uint64_t failures = 0;
    double worstRatio = 0.0;          // the largest error / tolerance over compared rays
    std::vector<std::string> errors;  // the first failures, one line each
    double seconds = 0.0;

    bool passes() const { return failures == 0; }
    // Counts a comparison whose error / tolerance is `ratio`: a failure when above 1 (or NaN),
    // then named by describe() while fewer than kMaxErrors are listed.
    template <class Describe>
    void judge(double ratio, Describe&& describe) {
        ++compared;
        if (!(ratio <= worstRatio)) worstRatio = ratio == ratio ? ratio : INFINITY;
        if (ratio <= 1.0) return;
        ++failures;
        if (errors.size() < kMaxErrors) errors.push_back(describe());
    }
    static constexpr size_t kMaxErrors = 16;
};

// A float primary ray of pixel (x, y) against the definition: its error over the tolerance (> 1:
// off), the largest of the eye's, the direction's angle and its unit length; +inf when the ray
// does not start at `eye` exactly or is not over [0, +inf). `def` is the frame by its options,
// `seen` the same frame from the float eye the rays start at (so that the direction is judged
// apart from the eye's rounding, which the eye's own term holds): validate's camera check and
// certify's camera set judge each ray with it.
struct PrimaryRayJudge {
    PrimaryRayJudge(const Aabb& sceneBounds, const CameraOptions& options, Vec3 eye);
    // The ray alone (the eye is judged once, by eyeRatio), and the ray with its eye.
    double rayRatio(const Ray& k, int x, int y) const;
    double ratio(const Ray& k, int x, int y) const { return std::max(eyeRatio, rayRatio(k, x, y)); }
    ReferenceFrame def, seen;
    Vec3 eye;
    double eyeTolerance = 0.0, dirTolerance = 0.0, unitTolerance = 0.0;
    double eyeRatio = 0.0;  // the eye's error / its tolerance (part of every ray's ratio)
};

// The rows of a camera set (ox oy oz dx dy dz tmin tmax, row i = pixel (i % width, i / width))
// against the definition of the frame of `options`: what octrace rays wrote for the camera set
// must be the pinhole camera, whatever code made it (certify reads these rows as given).
RayDefinitionReport checkCameraRows(const Aabb& sceneBounds, const CameraOptions& options,
                                    const float* rows, uint64_t count);

// The angle between two directions in radians, as its sine (exact to first order for the small
// angles the checks judge); 2 for an angle beyond a right one.
double angleBetween(DVec3 a, DVec3 b);
// | |v| - 1 |, to first order, without a square root.
inline double unitError(DVec3 v) { return 0.5 * std::fabs(dot(v, v) - 1.0); }

}  // namespace oct
