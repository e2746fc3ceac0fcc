#include "core/render/frame.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "core/geometry/numeric_range.h"

namespace oct {
namespace {

std::string str(Vec3 v) {
    return std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z);
}

std::string shortStr(Vec3 v) {
    std::ostringstream o;
    o << v.x << "," << v.y << "," << v.z;
    return o.str();
}

// The camera's eye and target and the light are ray origins or ray ends: finite and within
// +-kMaxRayOrigin, the numeric range in which the float32 tests are correct.
void requireInRange(const char* what, const std::optional<Vec3>& v) {
    if (!v) return;
    if (!isFinite(*v))
        throw FrameError(std::string("--") + what + " " + str(*v) + " is not finite");
    const float m = std::max({std::fabs(v->x), std::fabs(v->y), std::fabs(v->z)});
    if (double(m) > kMaxRayOrigin) {
        std::ostringstream limit;
        limit << kMaxRayOrigin;
        throw FrameError(std::string("--") + what + " " + shortStr(*v) + " is beyond +-" +
                         limit.str() +
                         ", the range in which octrace's float32 ray tests are correct "
                         "(docs/ROBUSTNESS.md, numeric range); bring it closer");
    }
}

void checkOptions(const CameraOptions& o) {
    if (o.width < 1 || o.height < 1 || o.width > kMaxImageSide || o.height > kMaxImageSide)
        throw FrameError("--size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                         " is outside 1x1 .. " + std::to_string(kMaxImageSide) + "x" +
                         std::to_string(kMaxImageSide));
    if (!(o.fovDegrees > 0.0f && o.fovDegrees < 180.0f))
        throw FrameError("--fov " + std::to_string(o.fovDegrees) +
                         " must be strictly between 0 and 180 degrees");
    requireInRange("eye", o.eye);
    requireInRange("target", o.target);
    if (o.up && !isFinite(*o.up)) throw FrameError("--up " + str(*o.up) + " is not finite");
    requireInRange("light", o.light);
}

}  // namespace

FrameParams makeFrame(const Aabb& b, const CameraOptions& o) {
    checkOptions(o);
    if (!isFinite(b.lo) || !isFinite(b.hi))
        throw FrameError("the scene's bounds are not finite; cannot frame it");
    Vec3 centre = b.center();
    float radius = 0.5f * length(b.extent());
    if (radius <= 0.0f) radius = 1.0f;
    float tanHalf = std::tan(0.5f * o.fovDegrees * float(M_PI) / 180.0f);
    float aspect = float(o.width) / float(o.height);
    // The bounding sphere fits when its radius / distance <= sin of the smaller half-angle.
    float halfMin = std::atan(tanHalf * std::min(1.0f, aspect));
    float distance = 1.05f * radius / std::sin(halfMin);

    Vec3 target = o.target.value_or(centre);
    Vec3 eye = o.eye.value_or(target + o.from * distance);
    const float farthest = std::max({std::fabs(eye.x), std::fabs(eye.y), std::fabs(eye.z)});
    if (!o.eye && !(double(farthest) <= kMaxRayOrigin)) {
        std::ostringstream why;
        why << "the default eye for this scene and --fov " << o.fovDegrees << " would sit at "
            << str(eye) << ", beyond +-" << kMaxRayOrigin
            << " (docs/ROBUSTNESS.md, numeric range); give --eye or a wider --fov";
        throw FrameError(why.str());
    }
    Vec3 upHint = o.up.value_or(Vec3{0.0f, 1.0f, 0.0f});
    // Only its direction matters: scaled to a largest component of 1, so that neither --up
    // 1e30,1e30,0 (whose length overflows) nor 1e-30,0,0 (whose length underflows) reads as zero.
    const float upMax = std::max({std::fabs(upHint.x), std::fabs(upHint.y), std::fabs(upHint.z)});
    if (upMax > 0.0f) upHint = upHint * (1.0f / upMax);
    Vec3 view = target - eye;
    if (!(length(view) > 0.0f))
        throw FrameError("--eye " + str(eye) + " equals --target: the view direction is undefined");
    Vec3 forward = normalize(view);
    Vec3 right = cross(forward, upHint);
    if (!(length(right) > 1e-6f * length(upHint)))
        throw FrameError("--up " + str(o.up.value_or(Vec3{0.0f, 1.0f, 0.0f})) +
                         " is parallel to the view direction (or zero)");
    right = normalize(right);
    Vec3 up = cross(right, forward);

    FrameParams p;
    p.width = o.width;
    p.height = o.height;
    p.camera = {eye, forward, right * (tanHalf * aspect), up * tanHalf};
    ShadingParams& s = p.shading;
    s.light = o.light.value_or(eye + up * radius + right * radius);
    s.surfaceColour = {0.85f, 0.80f, 0.70f};
    s.background = {0.08f, 0.09f, 0.12f};
    s.ambient = 0.12f;
    s.diffuse = 0.75f;
    s.specular = 0.25f;
    // Lift shadow-ray origins by 1e-5 of the scene's diagonal: far above float rounding of the
    // hit point (about 6e-8 relative), far below any feature of the test scenes.
    s.shadowBias = 1e-5f * 2.0f * radius;
    return p;
}

}  // namespace oct
