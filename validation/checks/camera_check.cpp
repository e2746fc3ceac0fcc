// validate's camera check: the kernel's primary rays against the pinhole camera's definition in
// double (policy/ray_definitions.h, docs/VALIDATION.md "The kernel's rays against their
// definitions"). Every other check renders its reference through the same camera code, so a
// fault there (a width/height slip, a pixel centre off by half a pixel, a sign) agrees with
// itself everywhere else. The rays are the kernel's own: tracePixel run through a probe
// (checks/kernel_probe.h), for every pixel of validate's frames and of two frames of this
// check's own that are not square (a width/height slip is invisible in a square one): a wide one
// framed by default, a tall one with an oblique eye, target, up and field of view. Those two are
// also rendered by the OpenMP launcher with a probe that tags each ray: the film must hold
// pixel (x, y)'s ray at y * width + x (row-major, row 0 at the top).
#include <chrono>
#include <cmath>

#include "core/octree/layout.h"
#include "cpu_ref/render_cpu.h"
#include "validation/checks/check.h"
#include "validation/checks/definition_result.h"
#include "validation/checks/kernel_probe.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using report_detail::fmt;
using report_detail::num;

struct ProbedFrame {
    std::string name;
    FrameParams params;  // the kernel's frame (makeFrame)
    CameraOptions options;
};

double maxAbs(DVec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// The check's own frames: not square, one framed by default, one by explicit options. A frame
// makeFrame refuses (an eye beyond the numeric range, for a scene at its edge) is left out and
// named in `skipped`.
std::vector<ProbedFrame> ownFrames(const Scene& scene, std::string& skipped) {
    const Aabb b = scene.bounds();
    CameraOptions wide;
    wide.width = 97;
    wide.height = 61;
    CameraOptions tall;
    tall.width = 61;
    tall.height = 97;
    tall.fovDegrees = 30.0f;
    const Vec3 c = b.center();
    float r = 0.5f * length(b.extent());  // makeFrame's radius rule
    if (!(r > 0.0f)) r = 1.0f;
    tall.eye = c + Vec3{0.9f * r, 0.6f * r, 2.7f * r};
    tall.target = c + Vec3{0.1f * r, -0.1f * r, 0.05f * r};
    tall.up = Vec3{0.2f, 1.0f, -0.3f};
    std::vector<ProbedFrame> frames;
    for (const auto& [name, options] : {std::make_pair("wide", wide), std::make_pair("tall", tall)})
        try {
            frames.push_back({name, makeFrame(b, options), options});
        } catch (const FrameError& e) {
            skipped += fmt("; %s frame left out: %s", name, e.what());
        }
    return frames;
}

std::string rayText(const Ray& r) {
    return fmt("org %.9g,%.9g,%.9g dir %.9g,%.9g,%.9g [%g, %g]", r.org.x, r.org.y, r.org.z, r.dir.x,
               r.dir.y, r.dir.z, r.tmin, r.tmax);
}

std::string rayText(const DoubleRay& r) {
    return fmt("org %.9g,%.9g,%.9g dir %.9g,%.9g,%.9g [%g, %g]", r.org.x, r.org.y, r.org.z, r.dir.x,
               r.dir.y, r.dir.z, r.tmin, r.tmax);
}

// Every pixel's primary ray against the definition; returns the rays' tags for the placement.
std::vector<float> checkRays(const Scene& scene, const ProbedFrame& f, RayDefinitionReport& rep) {
    const PrimaryRayJudge judge(scene.bounds(), f.options, f.params.camera.eye);
    const ReferenceFrame& def = judge.def;
    const DVec3 eye = toDouble(f.params.camera.eye);
    rep.judge(judge.eyeRatio, [&] {
        return fmt(
            "camera: %s %dx%d: the eye %.9g,%.9g,%.9g is %.3g from the definition's "
            "%.9g,%.9g,%.9g (tolerance %.3g)",
            f.name.c_str(), def.width, def.height, eye.x, eye.y, eye.z, maxAbs(eye - def.eye),
            def.eye.x, def.eye.y, def.eye.z, judge.eyeTolerance);
    });
    const PrimitivesView prims = primitivesView(scene);
    std::vector<float> tags(size_t(f.params.width) * size_t(f.params.height));
    ProbeLog log;
    const RayProbe probe{&log};
    NoObserver none;
    for (int y = 0; y < f.params.height; ++y)
        for (int x = 0; x < f.params.width; ++x) {
            log.closestCalls = 0;
            tracePixel(x, y, f.params, probe, prims, none, none);
            const Ray& k = log.closest;  // the ray the kernel traced for the pixel
            tags[size_t(y) * size_t(f.params.width) + size_t(x)] = rayTag(k);
            // One query, from the frame's eye exactly, over [0, +inf), along the definition.
            const double ratio = log.closestCalls == 1 ? judge.rayRatio(k, x, y) : INFINITY;
            rep.judge(ratio, [&] {
                const DoubleRay d = referencePrimaryRay(judge.seen, x, y);
                const DVec3 kd = toDouble(k.dir);
                return fmt(
                    "camera: %s %dx%d pixel %d,%d: traced %s, %.3g rad from the "
                    "definition's %s (tolerance %.3g)",
                    f.name.c_str(), def.width, def.height, x, y, rayText(k).c_str(),
                    angleBetween(kd, d.dir), rayText(d).c_str(), judge.dirTolerance);
            });
        }
    return tags;
}

// The OpenMP launcher's film holds each pixel's own ray at its row-major index.
void checkPlacement(const ProbedFrame& f, const std::vector<float>& tags,
                    RayDefinitionReport& rep) {
    Film film(f.params.width, f.params.height);
    const TagProbe probe;
    const FilmView view = film.view();
    // The launcher's loops as they are, on this thread alone: inside a region of one thread its
    // parallel loop is not parallel (OpenMP's nested regions are off), so a few thousand probed
    // pixels do not wait for a second thread on a busy machine.
#pragma omp parallel num_threads(1)
    renderFrameCpu(f.params, probe, PrimitivesView{}, view);
    uint64_t misplaced = 0;
    size_t first = 0;
    for (size_t i = 0; i < tags.size(); ++i)
        if (!(film.t[i] == tags[i]) && misplaced++ == 0) first = i;
    rep.judge(misplaced ? INFINITY : 0.0, [&] {
        return fmt(
            "camera: %s %dx%d: the launcher's film holds %llu pixels' rays at another "
            "index than y * width + x (the first at pixel %zu,%zu)",
            f.name.c_str(), f.params.width, f.params.height, (unsigned long long)misplaced,
            first % size_t(f.params.width), first / size_t(f.params.width));
    });
}

class CameraCheck : public SceneCheck {
public:
    const char* name() const override { return "camera"; }

    void run(const CheckInputs& in, ValidationReport& out) const override {
        const auto start = std::chrono::steady_clock::now();
        std::vector<ProbedFrame> frames = {{"default", in.frame, in.options.camera}};
        if (in.options.lightInside)
            frames.push_back(
                {"inside", in.frameInside, insideViewCamera(in.scene, in.options.camera)});
        std::string skipped;
        for (ProbedFrame& f : ownFrames(in.scene, skipped)) frames.push_back(std::move(f));
        RayDefinitionReport rep;
        uint64_t pixels = 0;
        for (const ProbedFrame& f : frames) {
            const std::vector<float> tags = checkRays(in.scene, f, rep);
            // A width/height slip in the launcher shows in a frame that is not square only.
            if (f.params.width != f.params.height) checkPlacement(f, tags, rep);
            pixels += uint64_t(f.params.width) * uint64_t(f.params.height);
            rep.scope += fmt("%s%s %dx%d", rep.scope.empty() ? "" : ", ", f.name.c_str(),
                             f.params.width, f.params.height);
        }
        rep.scope = fmt("%llu primary rays of %zu frames (%s%s)", (unsigned long long)pixels,
                        frames.size(), rep.scope.c_str(), skipped.c_str());
        rep.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        out.camera = std::move(rep);
    }

    CheckResult result(const ValidationReport& rep) const override {
        if (!rep.camera) return notRun("camera");
        return definitionResult("camera", "camera",
                                "against the pinhole camera's definition in double", *rep.camera);
    }
};

}  // namespace

const SceneCheck& cameraCheck() {
    static const CameraCheck check;
    return check;
}

}  // namespace oct
