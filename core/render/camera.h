// Pinhole camera and the frame parameters every pixel of a frame shares.
#pragma once

#include "core/geometry/aabb.h"
#include "core/geometry/ray.h"

namespace oct {

// Orthonormal basis scaled for ray generation: the ray through pixel (x, y) points along
// forward + sx * right + sy * up, with sx, sy in [-1, 1] across the image.
struct Camera {
    Vec3 eye;
    Vec3 forward;  // unit, towards the target
    Vec3 right;    // unit, scaled by tan(fov/2) * aspect
    Vec3 up;       // unit, scaled by tan(fov/2)
};

// Phong shading of the paper's renderer (ambient + diffuse + specular, one point light with a
// shadow ray); fixed material so that images of different tracers are comparable.
struct ShadingParams {
    Vec3 light;          // point light position
    Vec3 surfaceColour;  // diffuse albedo
    Vec3 background;     // colour of a miss
    float ambient;       // ka
    float diffuse;       // kd
    float specular;      // ks; exponent fixed at 32 (see kernel.h)
    float shadowBias;    // offset along the normal for the shadow ray origin, world units
};

struct FrameParams {
    int width;
    int height;
    Camera camera;
    ShadingParams shading;
    // A band of the image: rows [bandBegin, bandBegin + bandRows) are rendered, into a Film of
    // bandRows rows (MPI ranks split a frame so, dist/). 0 rows: the whole image. A pixel's rays
    // depend on (x, y, width, height) only, so a band's pixels equal the whole frame's.
    int bandBegin = 0;
    int bandRows = 0;
};

// The rows a frame renders (its band's, or the image's).
OCT_HD inline int frameRows(const FrameParams& p) { return p.bandRows > 0 ? p.bandRows : p.height; }

OCT_HD inline Ray primaryRay(const Camera& c, int x, int y, int width, int height) {
    // Pixel centres; row 0 at the top of the image.
    float sx = 2.0f * (float(x) + 0.5f) / float(width) - 1.0f;
    float sy = 1.0f - 2.0f * (float(y) + 0.5f) / float(height);
    Vec3 d = c.forward + c.right * sx + c.up * sy;
    return {c.eye, normalize(d), 0.0f, INFINITY};
}

}  // namespace oct
