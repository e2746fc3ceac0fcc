// Perceptual colour maps for the teaching images: inferno for traversal cost (dark = cheap,
// bright = expensive), viridis for octree depth and visit order. Both are matplotlib's tables
// (Smith & van der Walt, 2015; CC0), sampled at 256 steps: lightness rises monotonically, so a
// grey-scale print or a colour-blind reader still sees the order.
#pragma once

#include <cstdint>

namespace oct {

enum class ColourMap : uint8_t { Inferno, Viridis };

struct Rgb8 {
    uint8_t r, g, b;
};

// The colour at u in [0, 1] (clamped; NaN gives the lowest colour), nearest of the 256 entries.
Rgb8 mapColour(ColourMap map, double u);
// "#rrggbb", for the HTML page.
void hexColour(Rgb8 c, char out[8]);

}  // namespace oct
