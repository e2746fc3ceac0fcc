// --size, --eye, --target, --up, --fov, --light: the camera of render and explain, spelled once
// so that `octrace explain --pixel X,Y` with the same options traces the pixel render drew.
#include <optional>

#include "apps/cli.h"

namespace oct {
namespace {

std::optional<Vec3> optionalVec3(const char* option, const std::string& text) {
    if (text.empty()) return std::nullopt;
    return parseVec3(option, text);
}

}  // namespace

void addCameraOptions(CLI::App& cmd, CameraChoice& o) {
    cmd.add_option("--size", o.size, "Image size WxH")->capture_default_str();
    cmd.add_option("--eye", o.eye, "Camera position x,y,z (default: framed from the bounds)");
    cmd.add_option("--target", o.target, "Point looked at x,y,z (default: the bounds' centre)");
    cmd.add_option("--up", o.up, "Up vector x,y,z (default 0,1,0)");
    // makeFrame refuses 0 and 180 and what lies beyond (before anything is loaded).
    cmd.add_option("--fov", o.fov, "Vertical field of view, degrees (0 to 180, open)")
        ->capture_default_str()
        ->check(finiteNumber());
    cmd.add_option("--light", o.light, "Point light x,y,z (default: above and right of the eye)");
}

CameraOptions cameraOptions(const CameraChoice& o) {
    CameraOptions c;
    parseImageSize(o.size, c.width, c.height);
    c.eye = optionalVec3("--eye", o.eye);
    c.target = optionalVec3("--target", o.target);
    c.up = optionalVec3("--up", o.up);
    c.light = optionalVec3("--light", o.light);
    c.fovDegrees = o.fov;
    // Checked here as well as in makeFrame so the error comes before loading anything.
    makeFrame({{-1, -1, -1}, {1, 1, 1}}, c);
    return c;
}

}  // namespace oct
