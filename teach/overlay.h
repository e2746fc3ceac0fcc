// The octree drawn over the shaded image: the edges of its leaf cells (or of every cell of one
// depth), projected with the frame's pinhole camera and hidden where the surface is in front.
// Each edge is sampled about twice per pixel it spans; a sample is drawn unless the Film's hit
// distance t along that pixel's primary ray is nearer than the sample's distance from the eye
// (a depth test against the frame the kernel traced, so the overlay needs no second render).
#pragma once

#include <cstdint>
#include <string>

#include "core/octree/octree.h"
#include "core/render/camera.h"
#include "core/render/film.h"
#include "teach/image.h"

namespace oct {

struct OverlaySpec {
    int depth = -1;       // -1: every leaf (empty ones fainter); d >= 0: every cell of depth d
    std::string layout;   // named in the legend
    std::string scene;    // named in the legend
    std::string details;  // a further legend line (build parameters), may be empty
};

struct OverlayStats {
    uint64_t cells = 0;          // cells whose edges were drawn
    uint64_t samplesDrawn = 0;   // edge samples inside the image and not hidden
    uint64_t samplesHidden = 0;  // edge samples inside the image behind the surface
};

// Where a world point lands on the image: pixel (x, y) and its distance from the eye; false
// behind the camera. The inverse of primaryRay() (camera.h) up to rounding.
bool projectToPixel(const FrameParams& frame, Vec3 p, double& x, double& y, double& distance);

// The Film's shaded image with the cells' edges, coloured by depth (viridis), and a legend.
// Throws TeachError when spec.depth exceeds the octree's depth.
RgbImage overlayImage(const Film& film, const FrameParams& frame, const Octree& tree,
                      const OverlaySpec& spec, OverlayStats* stats = nullptr);

}  // namespace oct
