// The explain page's kernel, compiled to WebAssembly by emscripten (teach/teach.cmake): the
// page hands it the scene and build options octrace wrote (kernelSpec), and it rebuilds the
// layout with octrace's own builder, renders the image with renderPixel and explains any pixel
// with explainPixel: the same source files as `octrace render` and `octrace explain`, so a
// clicked pixel's explanation is the one `octrace explain --json --pixel X,Y` prints.
//
// The interface is C functions on one module-wide state (one page, one scene), called from
// teach/web/src/viewer.js through emscripten's ccall. Strings returned stay valid until the
// next call; errors are reported as {"error": "..."} and never abort the module.
#include <emscripten/emscripten.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/render/film.h"
#include "core/render/kernel.h"
#include "teach/colour_map.h"
#include "teach/explain.h"
#include "teach/explain_page_data.h"
#include "teach/svg_view.h"

namespace {

using json = nlohmann::ordered_json;
using namespace oct;

struct PageKernel {
    Scene scene;
    LayoutOptions options;
    FrameParams frame{};
    BuiltScene built;
    Film film;
    std::vector<uint8_t> rgba, costRgba;  // the image and its cost map, RGBA for a canvas
    uint32_t costScale = 0;               // the cost map's top: 99th percentile of boxes tested
    std::string explanation;              // the last explainJson
};

std::unique_ptr<PageKernel> state;

const char* answer(std::string text) {
    static std::string held;
    held = std::move(text);
    return held.c_str();
}

const char* error(const std::string& what) { return answer(json({{"error", what}}).dump()); }

// The Film's rgb as RGBA, and boxes tested per pixel as inferno up to the 99th percentile (as
// `octrace render --heatmap nodes` scales it).
void paint(PageKernel& k) {
    const size_t n = k.film.pixelCount();
    k.rgba.assign(4 * n, 255);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) k.rgba[4 * i + c] = k.film.rgb[3 * i + c];
    std::vector<uint32_t> sorted(k.film.nodes);
    std::sort(sorted.begin(), sorted.end());
    k.costScale = n ? std::max<uint32_t>(1, sorted[std::min(n - 1, size_t(0.99 * double(n)))]) : 1;
    k.costRgba.assign(4 * n, 255);
    for (size_t i = 0; i < n; ++i) {
        const Rgb8 c = mapColour(ColourMap::Inferno, double(k.film.nodes[i]) / k.costScale);
        k.costRgba[4 * i] = c.r;
        k.costRgba[4 * i + 1] = c.g;
        k.costRgba[4 * i + 2] = c.b;
    }
}

}  // namespace

extern "C" {

// Builds the scene described by `specText` (kernelSpec's JSON) and the primitive bytes beside
// it (kernelSpecScene: the model's positions and indices, or the primitives with no indices),
// and renders its frame. Returns {"width", "height", "fingerprint", "nodes", "max_depth",
// "cost_scale", "build_ms", "render_ms"} or {"error"}: refused when the rebuilt layout's
// fingerprint differs from the one octrace wrote.
EMSCRIPTEN_KEEPALIVE const char* octPageLoad(const char* specText, const char* positions,
                                             int positionBytes, const char* indices,
                                             int indexBytes) {
    try {
        const nlohmann::json spec = nlohmann::json::parse(specText);
        auto k = std::make_unique<PageKernel>();
        k->scene = kernelSpecScene(spec, std::string(positions, size_t(positionBytes)),
                                   indices ? std::string(indices, size_t(indexBytes)) : "");
        k->options = kernelSpecOptions(spec);
        k->frame = kernelSpecFrame(spec);
        const double t0 = emscripten_get_now();
        k->built =
            buildScene(k->scene, findLayout(spec.at("layout").get<std::string>()), k->options);
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)layoutFingerprint(k->built));
        const std::string wanted = spec.at("fingerprint").get<std::string>();
        if (wanted != hex)
            return error("the layout rebuilt in the page (fingerprint " + std::string(hex) +
                         ") differs from the one octrace traced (" + wanted +
                         "): the page cannot explain other pixels faithfully");
        const double t1 = emscripten_get_now();
        k->film = Film(k->frame.width, k->frame.height);
        const PrimitivesView prims = k->built.prims();
        FilmView view = k->film.view();
        k->built.visit([&](const auto& accel) {
            for (int y = 0; y < k->frame.height; ++y)
                for (int x = 0; x < k->frame.width; ++x)
                    renderPixel(x, y, k->frame, accel, prims, view);
        });
        const double t2 = emscripten_get_now();
        paint(*k);
        json out;
        out["width"] = k->frame.width;
        out["height"] = k->frame.height;
        out["fingerprint"] = hex;
        out["nodes"] = k->built.tree ? k->built.tree->nodes.size() : 0;
        out["max_depth"] = k->built.tree ? k->built.tree->depth : -1;
        out["cost_scale"] = k->costScale;
        out["build_ms"] = t1 - t0;
        out["render_ms"] = t2 - t1;
        state = std::move(k);
        return answer(out.dump());
    } catch (const std::exception& ex) {
        state.reset();
        return error(ex.what());
    }
}

// The image (cost = 0) or its cost map (cost = 1): width * height * 4 bytes in the module's
// memory, valid until the next octPageLoad.
EMSCRIPTEN_KEEPALIVE const uint8_t* octPageImage(int cost) {
    if (!state) return nullptr;
    return cost ? state->costRgba.data() : state->rgba.data();
}

// Pixel (x, y)'s cost and hit: {"boxes", "prims", "prim", "t"} or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* octPagePixel(int x, int y) {
    if (!state) return error("no scene loaded");
    try {
        checkPixelInImage(x, y, state->frame.width, state->frame.height);
        const size_t i = size_t(y) * state->frame.width + x;
        json out;
        out["boxes"] = state->film.nodes[i];
        out["prims"] = state->film.primsTested[i];
        out["prim"] = state->film.prim[i];
        out["t"] = std::isfinite(state->film.t[i]) ? json(state->film.t[i]) : json(nullptr);
        return answer(out.dump());
    } catch (const std::exception& ex) {
        return error(ex.what());
    }
}

// Explains pixel (x, y): the page's data for it (pixelPageData) with "ms", the time taken.
// octPageExplanation() then returns explainJson of the same explanation, byte for byte what
// `octrace explain --json` writes.
EMSCRIPTEN_KEEPALIVE const char* octPageExplain(int x, int y) {
    if (!state) return error("no scene loaded");
    try {
        const double t0 = emscripten_get_now();
        const Explanation e = explainPixel(state->built, state->frame, x, y);
        state->explanation = explainJson(e);
        json out = pixelPageData(e, state->scene);
        addPlaneView(out, e, state->scene, state->built.tree.get());
        out["ms"] = emscripten_get_now() - t0;
        return answer(out.dump());
    } catch (const std::exception& ex) {
        state->explanation.clear();
        return error(ex.what());
    }
}

EMSCRIPTEN_KEEPALIVE const char* octPageExplanation() {
    return state ? state->explanation.c_str() : "";
}

// The octree's cells at `depth` (internal nodes and leaves, empty leaves included):
// {"cells": [[lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, type], ...]} with type 0 internal, 1 leaf,
// 2 empty leaf (node.h), for the page's depth slider; {"cells": []} for exhaustive tracing.
EMSCRIPTEN_KEEPALIVE const char* octPageCells(int depth) {
    if (!state) return error("no scene loaded");
    json cells = json::array();
    if (state->built.tree)
        for (const OctreeNode& n : state->built.tree->nodes)
            if (n.depth == depth)
                cells.push_back({n.box.lo.x, n.box.lo.y, n.box.lo.z, n.box.hi.x, n.box.hi.y,
                                 n.box.hi.z, int(n.type)});
    return answer(json({{"cells", std::move(cells)}}).dump());
}

}  // extern "C"
