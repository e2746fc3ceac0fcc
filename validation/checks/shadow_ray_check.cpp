// validate's shadow-ray check: the kernel's shadow rays against their definition in double
// (policy/ray_definitions.h, docs/VALIDATION.md "The kernel's rays against their definitions").
// The per-pixel check compares shadow outcomes of rays that both tracers, and the recheck,
// build with the kernel's shadowQuery, so a fault in it (the lift's sign or size, the light's
// place, tmax) agrees with itself there. Here tracePixel runs through a probe
// (checks/kernel_probe.h) that answers each pixel of validate's frames with Embree's hit of the
// reference film and keeps the shadow ray the kernel then casts; that ray, and whether it is cast
// at all, are held to the definition's. Also the frame's light and lift themselves.
#include <chrono>
#include <cmath>

#include "core/octree/layout.h"
#include "validation/checks/check.h"
#include "validation/checks/definition_result.h"
#include "validation/checks/kernel_probe.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using report_detail::fmt;

constexpr double u = kFloatUnitRoundoff;

double maxAbs(DVec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

std::string rayText(const Ray& r) {
    return fmt("org %.9g,%.9g,%.9g dir %.9g,%.9g,%.9g [%g, %.9g]", r.org.x, r.org.y, r.org.z,
               r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
}

std::string rayText(const DoubleRay& r) {
    return fmt("org %.9g,%.9g,%.9g dir %.9g,%.9g,%.9g [%g, %.9g]", r.org.x, r.org.y, r.org.z,
               r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
}

struct View {
    const char* name;
    const FrameParams& frame;
    CameraOptions options;
    const Film& reference;  // Embree's hits through the kernel: the hit points to lift
};

// The frame's light and lift: the definition's, seen from the kernel's eye (the camera check
// holds that eye to the definition's).
void checkLight(const View& v, const ReferenceFrame& def, RayDefinitionReport& rep) {
    const DVec3 light = toDouble(v.frame.shading.light);
    const double lightTol = 16.0 * u * def.scale;
    rep.judge(maxAbs(light - def.light) / lightTol, [&] {
        return fmt(
            "shadow ray: %s view: the light %.9g,%.9g,%.9g is %.3g from the "
            "definition's %.9g,%.9g,%.9g (tolerance %.3g)",
            v.name, light.x, light.y, light.z, maxAbs(light - def.light), def.light.x, def.light.y,
            def.light.z, lightTol);
    });
    const double bias = v.frame.shading.shadowBias;
    rep.judge(std::fabs(bias - def.shadowBias) / (8.0 * u * def.shadowBias), [&] {
        return fmt(
            "shadow ray: %s view: the lift %.9g is not 1e-5 of the scene's diagonal "
            "(%.9g)",
            v.name, bias, def.shadowBias);
    });
}

// Every pixel where the reference hit: the kernel's shadow ray from that hit.
void checkRays(const Scene& scene, const View& v, const ReferenceFrame& def,
               RayDefinitionReport& rep) {
    const PrimitivesView prims = primitivesView(scene);
    const double lightTol = 16.0 * u * def.scale;
    ProbeLog log;
    const RayProbe probe{&log};
    NoObserver none;
    for (int y = 0; y < v.frame.height; ++y)
        for (int x = 0; x < v.frame.width; ++x) {
            const size_t i = size_t(y) * size_t(v.frame.width) + size_t(x);
            const Hit hit = {v.reference.t[i], v.reference.prim[i]};
            if (hit.prim < 0 || uint32_t(hit.prim) >= prims.count || !std::isfinite(hit.t))
                continue;
            log.answer = hit;
            log.anyHitCalls = 0;
            const PixelSample s = tracePixel(x, y, v.frame, probe, prims, none, none);
            const Ray& primary = log.closest;
            const ReferenceShadowRay d =
                referenceShadowRay(def, scene, toDoubleRay(primary), hit.t, uint32_t(hit.prim));
            // The float hit point is rounded by u times the magnitudes it sums, the lift by the
            // turn rounding gives the normal; where that turn or the facing is left to rounding
            // (a surface edge-on to the ray), the definition does not decide.
            const double bias = def.shadowBias;
            const double originTol =
                8.0 * u *
                    (maxAbs(toDouble(primary.org)) + hit.t * maxAbs(toDouble(primary.dir)) + bias) +
                bias * d.normalError;
            if (std::fabs(d.viewCos) <= d.normalError + 8.0 * u || originTol > 0.25 * bias) {
                ++rep.unjudged;
                continue;
            }
            const double spread = std::sqrt(3.0) * (originTol + lightTol);
            const double dirTol = 8.0 * u + spread / d.ray.tmax;
            const double tmaxTol = 8.0 * u * d.ray.tmax + spread;
            if (std::fabs(d.lightCos) <= d.normalError + dirTol) {
                ++rep.unjudged;  // the light edge-on: cast or not is left to rounding
                continue;
            }
            const bool cast = log.anyHitCalls == 1;
            const bool castByDefinition = d.lightCos > 0.0;
            const Ray& k = cast ? log.shadow : s.shadowQuery.ray;
            const DVec3 kd = toDouble(k.dir);
            double ratio = cast == castByDefinition && log.anyHitCalls <= 1 ? 0.0 : INFINITY;
            ratio = std::max(ratio, maxAbs(toDouble(k.org) - d.ray.org) / originTol);
            ratio = std::max(ratio, angleBetween(kd, d.ray.dir) / dirTol);
            ratio = std::max(ratio, unitError(kd) / (8.0 * u));
            ratio = std::max(ratio, std::fabs(double(k.tmax) - d.ray.tmax) / tmaxTol);
            if (!(k.tmin == 0.0f)) ratio = INFINITY;
            rep.judge(ratio, [&] {
                return fmt(
                    "shadow ray: %s view pixel %d,%d (prim %d, t %.9g): %s %s; the "
                    "definition %s %s (origin tolerance %.3g)",
                    v.name, x, y, hit.prim, hit.t, cast ? "cast" : "not cast", rayText(k).c_str(),
                    castByDefinition ? "casts" : "does not cast", rayText(d.ray).c_str(),
                    originTol);
            });
        }
}

class ShadowRayCheck : public SceneCheck {
public:
    const char* name() const override { return "shadow_ray"; }

    void run(const CheckInputs& in, ValidationReport& out) const override {
        const auto start = std::chrono::steady_clock::now();
        std::vector<View> views = {{"default", in.frame, in.options.camera, in.reference}};
        if (in.options.lightInside)
            views.push_back({"inside", in.frameInside,
                             insideViewCamera(in.scene, in.options.camera), in.referenceInside});
        RayDefinitionReport rep;
        for (const View& v : views) {
            CameraOptions fromEye = v.options;
            fromEye.eye = v.frame.camera.eye;
            const ReferenceFrame def = referenceFrame(in.scene.bounds(), fromEye);
            checkLight(v, def, rep);
            checkRays(in.scene, v, def, rep);
            rep.scope += fmt("%s%s", rep.scope.empty() ? "" : " and ", v.name);
        }
        rep.scope = "the shadow rays of Embree's hits in the " + rep.scope +
                    (views.size() > 1 ? " views" : " view") + ", the lights and lifts";
        rep.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        out.shadowRays = std::move(rep);
    }

    CheckResult result(const ValidationReport& rep) const override {
        if (!rep.shadowRays) return notRun("shadow_ray");
        return definitionResult("shadow_ray", "shadow ray", "against their definition in double",
                                *rep.shadowRays);
    }
};

}  // namespace

const SceneCheck& shadowRayCheck() {
    static const ShadowRayCheck check;
    return check;
}

}  // namespace oct
