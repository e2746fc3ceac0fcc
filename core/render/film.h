// The Film: what a frame produces per pixel, row-major (index y * width + x): the kernel-side
// view of its arrays and the host object that owns them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/platform.h"

namespace oct {

// Per-pixel shadow-ray outcome.
constexpr uint8_t kNoShadowRay = 0;  // primary ray missed, or the surface faces away from the light
constexpr uint8_t kLit = 1;          // shadow ray cast, nothing between hit and light
constexpr uint8_t kOccluded = 2;     // shadow ray cast and blocked

// Kernel-side view of a film's arrays (host or device memory).
struct FilmView {
    uint8_t* rgb;           // 3 bytes per pixel, sRGB-agnostic 8-bit colour
    float* t;               // closest hit distance along the unit primary ray, +inf on a miss
    int32_t* prim;          // primitive id of the closest hit, -1 on a miss
    uint32_t* nodes;        // boxes tested by the primary and the shadow ray
    uint32_t* primsTested;  // primitives tested by the primary and the shadow ray
    uint8_t* shadow;        // kNoShadowRay, kLit or kOccluded
    int width;
    int height;
};

// Owns the arrays a FilmView points to (host memory).
// A Film's bytes per pixel: rgb, t, prim, nodes, primsTested, shadow (for memory estimates).
constexpr uint64_t kFilmBytesPerPixel = 3 + 4 + 4 + 4 + 4 + 1;

struct Film {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
    std::vector<float> t;
    std::vector<int32_t> prim;
    std::vector<uint32_t> nodes, primsTested;
    std::vector<uint8_t> shadow;

    Film() = default;
    Film(int w, int h);
    FilmView view();
    size_t pixelCount() const { return size_t(width) * size_t(height); }
};

// The per-pixel cost as `octrace render --cost` writes it and the Python module's render()
// returns it: (H, W, 2) int32, boxes tested then primitives tested (primary + shadow ray).
std::vector<int32_t> costArray(const Film& film);

}  // namespace oct
