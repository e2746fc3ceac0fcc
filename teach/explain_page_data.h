// What the explain page shows of one explained pixel (or ray), as the JSON object its viewer
// reads: the cells the traversal touched, the rays, the primitives tested, the step lines, a
// first view and the summary. `octrace explain --html` writes it for the pixel it traced; the
// page's own kernel (teach/wasm/page_kernel.cpp, the same code compiled to WebAssembly) makes
// the same object for every pixel a reader clicks, so the two can never describe a pixel
// differently.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/octree/built_scene.h"
#include "core/render/camera.h"
#include "core/scene/scene.h"
#include "teach/explain.h"

namespace oct {

// Primitives drawn as tested (beyond that, exhaustive tracing: only the hit ones).
constexpr uint32_t kPageMaxTestedPrims = 4000;

// The object's fields: "root" (the root cube, 6 floats), "light", "cells" (each tested or
// skipped cell: ray, key in octal, depth, box, visited, and order and colour when visited),
// "rays" (role, from, to, hit, colour), "prims" (id, hit, and a triangle's 9 floats "v" or a
// sphere's "c" and "r"), "prims_note", "lines" (explainLines: ray, step, text, key, prim; and
// headings), "view" (the first camera: target, eye, up), "pixel" ([x, y] or null), "title" and
// "summary". `cells` and `lines` count what it holds.
struct PixelPageCounts {
    uint64_t cells = 0;  // cells on the page
    uint64_t lines = 0;  // entries of the step list (headings excluded)
};
nlohmann::ordered_json pixelPageData(const Explanation& e, const Scene& scene,
                                     PixelPageCounts* counts = nullptr);

// Adds "svg", the 2D view of `octrace explain --svg` for `e` (svg_view.h, the plane of the ray),
// or "svg_error" when that figure cannot be drawn (its message).
void addPlaneView(nlohmann::ordered_json& data, const Explanation& e, const Scene& scene,
                  const Octree* tree);

// FNV-1a (64-bit) over the bytes of every array of the layout's View (forEachArray, in its
// order), then over the scene's primitives: the page's kernel rebuilds the layout from the
// embedded scene and refuses to trace unless its fingerprint equals the one octrace wrote.
uint64_t layoutFingerprint(const BuiltScene& bs);

// What the page's kernel needs to rebuild exactly the traced structure and frame: the scene's
// name, kind, domain and grid depth, the layout and its build options, the frame's camera and
// shading as float32 values (JSON numbers that round-trip a float), and the fingerprint. The
// primitives travel beside it as bytes: with `fromModel`, the page's model mesh (pageMesh,
// undecimated: vertices shared only where bit-identical, so its triangles are the scene's
// exactly); otherwise "data", the scene's Triangle or Sphere array in base64.
nlohmann::ordered_json kernelSpec(const BuiltScene& bs, const LayoutOptions& options,
                                  const FrameParams& frame, bool fromModel);
// The scene of a spec: its triangles from `positions` (x y z floats) and `indices` (3 per
// triangle), or, with no indices, `positions` is the Triangle or Sphere array itself. Throws
// TeachError naming the field or the size when they do not fit.
Scene kernelSpecScene(const nlohmann::json& spec, const std::string& positions,
                      const std::string& indices);
// Throws TeachError naming the field when `spec` is not a kernel spec.
LayoutOptions kernelSpecOptions(const nlohmann::json& spec);
FrameParams kernelSpecFrame(const nlohmann::json& spec);

std::string base64Encode(const void* data, size_t bytes);
// Throws TeachError on a character outside the alphabet or a length not a multiple of 4.
std::string base64Decode(const std::string& text);

}  // namespace oct
