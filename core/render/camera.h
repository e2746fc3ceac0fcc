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
    // A band of the image, rendered into a Film of bandRows rows: blocks of bandBlock rows, the
    // first at row bandBegin, one every bandStride rows (an MPI rank's share of a frame, dealt
    // round robin: dist/ranks.h). 0 rows: the whole image. A pixel's rays depend on (x, y,
    // width, height) only, so a band's pixels equal the whole frame's.
    int bandBegin = 0;
    int bandRows = 0;
    int bandBlock = 1;
    int bandStride = 1;
};

// The rows a frame renders (its band's, or the image's).
OCT_HD inline int frameRows(const FrameParams& p) { return p.bandRows > 0 ? p.bandRows : p.height; }
// The image row of the Film's row j, and the Film's row of image row y (of the band).
OCT_HD inline int imageRowOf(const FrameParams& p, int j) {
    if (p.bandRows <= 0) return j;
    return p.bandBegin + (j / p.bandBlock) * p.bandStride + j % p.bandBlock;
}
OCT_HD inline int filmRowOf(const FrameParams& p, int y) {
    if (p.bandRows <= 0) return y;
    const int d = y - p.bandBegin;
    return (d / p.bandStride) * p.bandBlock + d % p.bandStride;
}

OCT_HD inline Ray primaryRay(const Camera& c, int x, int y, int width, int height) {
    // Pixel centres; row 0 at the top of the image.
    float sx = 2.0f * (float(x) + 0.5f) / float(width) - 1.0f;
    float sy = 1.0f - 2.0f * (float(y) + 0.5f) / float(height);
    Vec3 d = c.forward + c.right * sx + c.up * sy;
    return {c.eye, normalize(d), 0.0f, INFINITY};
}

}  // namespace oct
