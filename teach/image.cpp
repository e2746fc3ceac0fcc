#include "teach/image.h"

#include <algorithm>
#include <cmath>

// stb_easy_font.h defines its functions `static` in the header: no implementation macro, no
// symbol to link; the ones this file does not call would warn as unused.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace oct {

RgbImage::RgbImage(int w, int h, Rgb8 fill) : width(w), height(h), rgb(size_t(w) * h * 3) {
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        rgb[3 * i] = fill.r;
        rgb[3 * i + 1] = fill.g;
        rgb[3 * i + 2] = fill.b;
    }
}

Rgb8 RgbImage::at(int x, int y) const {
    const size_t i = (size_t(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void RgbImage::set(int x, int y, Rgb8 c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const size_t i = (size_t(y) * width + x) * 3;
    rgb[i] = c.r;
    rgb[i + 1] = c.g;
    rgb[i + 2] = c.b;
}

void RgbImage::blend(int x, int y, Rgb8 c, float alpha) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const size_t i = (size_t(y) * width + x) * 3;
    const uint8_t src[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k)
        rgb[i + k] = uint8_t(std::lround(rgb[i + k] * (1.0f - alpha) + src[k] * alpha));
}

void RgbImage::fillRect(int x0, int y0, int x1, int y1, Rgb8 c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width);
    y1 = std::min(y1, height);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) set(x, y, c);
}

void RgbImage::paste(const RgbImage& src, int x, int y) {
    for (int j = 0; j < src.height; ++j)
        for (int i = 0; i < src.width; ++i) set(x + i, y + j, src.at(i, j));
}

int textWidth(const std::string& text, int scale) {
    std::string copy = text;
    return stb_easy_font_width(copy.data()) * scale;
}

int textHeight(int scale) { return 12 * scale; }

void drawText(RgbImage& img, int x, int y, const std::string& text, Rgb8 colour, int scale) {
    // stb_easy_font writes 4 vertices of 16 bytes (x, y, z floats + RGBA) per quad and uses
    // about 270 bytes a character; it truncates rather than overflow.
    struct Vertex {
        float x, y, z;
        uint8_t c[4];
    };
    std::vector<Vertex> quads(text.size() * 80 + 16);
    std::string copy = text;
    const int n = stb_easy_font_print(0, 0, copy.data(), nullptr, quads.data(),
                                      int(quads.size() * sizeof(Vertex)));
    for (int q = 0; q < n; ++q) {
        const Vertex* v = &quads[4 * q];
        const float qx0 = std::min(v[0].x, v[2].x), qx1 = std::max(v[0].x, v[2].x);
        const float qy0 = std::min(v[0].y, v[2].y), qy1 = std::max(v[0].y, v[2].y);
        img.fillRect(x + int(std::lround(qx0 * scale)), y + int(std::lround(qy0 * scale)),
                     x + int(std::lround(qx1 * scale)), y + int(std::lround(qy1 * scale)), colour);
    }
}

int fitText(std::string& text, int width, int maxScale) {
    for (int s = std::max(maxScale, 1); s >= 1; --s)
        if (textWidth(text, s) <= width) return s;
    while (text.size() > 3 && textWidth(text + "...", 1) > width) text.pop_back();
    text += "...";
    return 1;
}

}  // namespace oct
