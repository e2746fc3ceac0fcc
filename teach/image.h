// A plain 8-bit RGB raster for the teaching images (heat maps, octree overlays) and the few
// drawing operations their legends need: rectangles, blended pixels and text. Text is Sean
// Barrett's stb_easy_font (Debian's libstb-dev): ASCII glyphs built from axis-aligned quads,
// which this file fills as pixel rectangles scaled by an integer factor.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "teach/colour_map.h"

namespace oct {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // row-major, 3 bytes a pixel, row 0 at the top

    RgbImage() = default;
    RgbImage(int w, int h, Rgb8 fill);
    Rgb8 at(int x, int y) const;
    void set(int x, int y, Rgb8 c);
    // c over the pixel with opacity alpha in [0, 1]; outside the image: nothing.
    void blend(int x, int y, Rgb8 c, float alpha);
    // The rectangle [x0, x1) x [y0, y1), clipped to the image.
    void fillRect(int x0, int y0, int x1, int y1, Rgb8 c);
    // Copies `src` with its top-left corner at (x, y), clipped.
    void paste(const RgbImage& src, int x, int y);
};

// Pixels a line of text takes at `scale` (stb_easy_font's glyphs are about 6 x 7 units, lines
// 12 units apart, before scaling).
int textWidth(const std::string& text, int scale);
int textHeight(int scale);
// Draws one line of ASCII text with its top-left corner at (x, y).
void drawText(RgbImage& img, int x, int y, const std::string& text, Rgb8 colour, int scale);
// The largest scale in [1, maxScale] at which `text` fits in `width` pixels; the text is cut
// and ends in "..." when it does not fit even at scale 1.
int fitText(std::string& text, int width, int maxScale);

}  // namespace oct
