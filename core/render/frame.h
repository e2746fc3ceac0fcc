// Host-side set-up of a frame: camera from options or framed automatically, shading defaults,
// and the Film that owns the per-pixel arrays.
#pragma once

#include <optional>
#include <stdexcept>
#include <vector>

#include "core/render/camera.h"
#include "core/render/film.h"

namespace oct {

class FrameError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct CameraOptions {
    std::optional<Vec3> eye, target, up, light;
    // The side the default eye frames the scene from (a unit vector from the target towards the
    // eye), when `eye` is not given: +z by default (looking along -z). The regression set's
    // axis views (validation/regression/regression_render.h) set it.
    Vec3 from{0.0f, 0.0f, 1.0f};
    float fovDegrees = 45.0f;
    int width = 512;
    int height = 512;
};

// Largest image side accepted: 16384 (16384^2 pixels of Film take about 4.3 GiB).
constexpr int kMaxImageSide = 16384;

// Default framing rule: look at the centre of the scene's box along -z (from the +z side),
// with +y up, from the distance at which the box's bounding sphere just fits the smaller of
// the two fields of view, plus 5%. So every scene is fully visible. The light sits above and
// to the right of the eye by one bounding-sphere radius in each direction.
// Throws FrameError for a non-finite value, eye == target, up parallel to the view direction,
// fov outside (0, 180), or a size outside [1, kMaxImageSide].
FrameParams makeFrame(const Aabb& sceneBounds, const CameraOptions& opt);

}  // namespace oct
