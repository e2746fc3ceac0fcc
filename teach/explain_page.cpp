#include "teach/explain_page.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <unordered_map>

#include "core/io/markup.h"
#include "core/octree/morton.h"
#include "core/render/film.h"
#include "teach/colour_map.h"
#include "teach/page_kernel_script.h"
#include "teach/teach_error.h"
#include "teach/viewer_script.h"

namespace oct {
namespace {

using json = nlohmann::ordered_json;

struct VertexKey {
    uint32_t x, y, z;
    bool operator==(const VertexKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct VertexKeyHash {
    size_t operator()(const VertexKey& k) const {
        return size_t(k.x) * 73856093u ^ size_t(k.y) * 19349663u ^ size_t(k.z) * 83492791u;
    }
};

VertexKey bitsOf(Vec3 v) {
    VertexKey k;
    std::memcpy(&k.x, &v.x, 4);
    std::memcpy(&k.y, &v.y, 4);
    std::memcpy(&k.z, &v.z, 4);
    return k;
}

// Vertex clustering on a g^3 grid over `bounds`: each vertex moves to the mean of its cell's
// vertices, triangles whose corners share a cell vanish.
IndexedMesh cluster(const Scene& scene, const Aabb& bounds, int g) {
    IndexedMesh m;
    m.decimated = true;
    std::unordered_map<uint64_t, uint32_t> cellIndex;
    std::vector<double> sums;
    std::vector<uint32_t> counts;
    const Vec3 ext = bounds.extent();
    auto cellOf = [&](Vec3 v) {
        auto axis = [&](float p, float lo, float e) {
            const double u = e > 0 ? double(p - lo) / e : 0.0;
            return uint64_t(std::clamp(int(u * g), 0, g - 1));
        };
        return axis(v.x, bounds.lo.x, ext.x) | axis(v.y, bounds.lo.y, ext.y) << 21 |
               axis(v.z, bounds.lo.z, ext.z) << 42;
    };
    for (const Triangle& t : scene.triangles) {
        uint32_t ids[3];
        const Vec3 vs[3] = {t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            const uint64_t c = cellOf(vs[k]);
            auto [it, fresh] = cellIndex.emplace(c, uint32_t(counts.size()));
            if (fresh) {
                sums.insert(sums.end(), {0.0, 0.0, 0.0});
                counts.push_back(0);
            }
            ids[k] = it->second;
        }
        if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) continue;
        for (int k = 0; k < 3; ++k) {
            sums[3 * ids[k]] += vs[k].x;
            sums[3 * ids[k] + 1] += vs[k].y;
            sums[3 * ids[k] + 2] += vs[k].z;
            ++counts[ids[k]];
        }
        m.indices.insert(m.indices.end(), ids, ids + 3);
    }
    m.positions.resize(sums.size());
    for (size_t i = 0; i < counts.size(); ++i)
        for (int k = 0; k < 3; ++k)
            m.positions[3 * i + k] = counts[i] ? float(sums[3 * i + k] / counts[i]) : 0.0f;
    return m;
}

}  // namespace

IndexedMesh pageMesh(const Scene& scene, uint32_t maxTriangles) {
    if (scene.triangles.size() > maxTriangles) {
        // The finest grid that brings the mesh within budget, from 1024 cells a side down.
        const Aabb bounds = scene.bounds();
        for (double g = 1024; g >= 4; g /= 1.25) {
            IndexedMesh m = cluster(scene, bounds, int(g));
            if (m.indices.size() / 3 <= maxTriangles) return m;
        }
        return cluster(scene, bounds, 4);
    }
    IndexedMesh m;
    std::unordered_map<VertexKey, uint32_t, VertexKeyHash> index;
    for (const Triangle& t : scene.triangles)
        for (Vec3 v : {t.v0, t.v1, t.v2}) {
            auto [it, fresh] = index.emplace(bitsOf(v), uint32_t(m.positions.size() / 3));
            if (fresh) m.positions.insert(m.positions.end(), {v.x, v.y, v.z});
            m.indices.push_back(it->second);
        }
    return m;
}

namespace {

json modelJson(const Scene& scene, PageStats& stats, std::string& note) {
    json j;
    if (scene.kind == PrimKind::Triangles) {
        const IndexedMesh m = pageMesh(scene, kPageMaxTriangles);
        j["kind"] = "triangles";
        j["positions"] = base64Encode(m.positions.data(), m.positions.size() * 4);
        j["indices"] = base64Encode(m.indices.data(), m.indices.size() * 4);
        stats.modelPrimitives = m.indices.size() / 3;
        stats.reduced = m.decimated;
        if (m.decimated)
            note = "Model shown decimated by vertex clustering: " +
                   std::to_string(stats.modelPrimitives) + " of " +
                   std::to_string(scene.triangles.size()) +
                   " triangles. The primitives the ray tested are drawn exactly.";
    } else {
        const size_t n = scene.spheres.size();
        const size_t stride = (n + kPageMaxPoints - 1) / kPageMaxPoints;
        std::vector<float> pos;
        double radius = 0;
        for (size_t i = 0; i < n; i += std::max<size_t>(stride, 1)) {
            const Sphere& s = scene.spheres[i];
            pos.insert(pos.end(), {s.center.x, s.center.y, s.center.z});
            radius = std::max(radius, double(s.radius));
        }
        j["kind"] = "points";
        j["positions"] = base64Encode(pos.data(), pos.size() * 4);
        j["radius"] = radius;
        stats.modelPrimitives = pos.size() / 3;
        stats.reduced = stride > 1;
        note = "Spheres shown as points";
        if (stride > 1)
            note += ", one in " + std::to_string(stride) + " of " + std::to_string(n) + " drawn";
        note += ". The spheres the ray tested are drawn exactly.";
    }
    return j;
}

// The page's frame; @TITLE@, @SUMMARY@, @NOTE@, @LEGEND@, @DATA@, @KERNEL@, @SCRIPT@,
// @VERSIONS@ are replaced. The first script collects errors before the viewer runs, so a test
// (and a reader) sees any failure in the page itself.
const char* kTemplate = R"html(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
html, body { margin: 0; height: 100%; background: #15171f; color: #e8e8ec;
  font: 13px/1.35 system-ui, sans-serif; }
#app { display: flex; height: 100%; }
#view { flex: 1 1 55%; position: relative; min-width: 0; }
#plane-view { position: absolute; inset: 8px; background: #fff; border-radius: 4px;
  overflow: auto; display: none; }
#plane-view svg { width: 100%; height: auto; max-height: 100%; }
#panel { flex: 0 1 45%; max-width: 640px; min-width: 320px; display: flex;
  flex-direction: column; border-left: 1px solid #30333d; overflow: hidden; }
#head { padding: 8px 10px; border-bottom: 1px solid #30333d; overflow-y: auto; max-height: 62%; }
#head h1 { font-size: 15px; margin: 0 0 4px; }
#head p { margin: 2px 0; color: #b4b7c2; }
.bar { height: 10px; border-radius: 2px; margin: 4px 0 2px; background: @LEGEND@; }
.ends { display: flex; justify-content: space-between; color: #b4b7c2; font-size: 11px; }
#image-box { display: flex; gap: 8px; align-items: flex-start; margin: 6px 0; }
#image { image-rendering: pixelated; cursor: crosshair; border: 1px solid #30333d;
  width: 192px; height: auto; }
#image-info { font-size: 12px; color: #b4b7c2; }
#controls button { font: 12px system-ui, sans-serif; margin-right: 2px; }
#kernel-state { color: #ffd479; }
#steps { list-style: none; margin: 0; padding: 4px 0; overflow: auto; flex: 1;
  font: 11px/1.4 ui-monospace, monospace; white-space: pre-wrap; overflow-wrap: anywhere; }
#steps li { padding: 0 10px 0 22px; text-indent: -12px; cursor: default; }
#steps li.heading { color: #fff; font-weight: bold; padding-top: 6px; }
#steps li.names { cursor: pointer; }
#steps li.names:hover { background: #3a3520; }
#steps li.pinned { background: #5a4d10; }
#octrace-errors { color: #ff6b6b; margin: 0; padding: 0 10px; white-space: pre-wrap; }
label { color: #b4b7c2; margin-right: 10px; }
</style>
</head>
<body data-octrace="loading">
<div id="app">
<div id="view"><div id="plane-view"></div></div>
<div id="panel">
<div id="head">
<h1 id="title">@TITLE@</h1>
<p id="scene-line">@SCENE@</p>
<p id="summary">@SUMMARY@</p>
<div class="bar"></div>
<div class="ends"><span>cells: first visited</span><span>last visited</span></div>
<p id="note">@NOTE@</p>
<p id="kernel-state"></p>
<div id="image-box"><canvas id="image" width="1" height="1"></canvas>
<div id="image-info"><label><input type="checkbox" id="show-cost"> colour by cost
(boxes tested)</label><br><span id="cost-scale"></span><br><span id="pixel-info"></span></div></div>
<p id="controls"><button id="first" title="first step (Home)">|&#x25C0;</button><button
id="prev" title="previous step (&#x2190;)">&#x25C0;</button><button id="play"
title="play / pause (space)">&#x25B6;</button><button id="next"
title="next step (&#x2192;)">&#x25B6;&#x258F;</button>
<label>speed <select id="speed"><option value="1">1</option><option value="3" selected>3</option>
<option value="10">10</option><option value="30">30</option></select> steps/s</label>
<label><input type="checkbox" id="follow" checked> camera follows</label></p>
<p><label>tree depth <input type="range" id="depth" min="-1" max="0" value="-1">
<span id="depth-value">off</span></label></p>
<p><label><input type="checkbox" id="show-model" checked> model</label>
<label><input type="checkbox" id="show-missed"> boxes missed, skipped or dropped</label>
<label><input type="checkbox" id="show-plane"> 2D view</label></p>
<p>Click a pixel of the image to explain it. Step with the buttons or the arrow keys; hover a
step to highlight its cell or primitive, click to keep it (the address then names it: #step=N,
#shadow=N, with #pixel=X,Y). Drag to orbit, scroll to zoom.</p>
<pre id="octrace-errors"></pre>
</div>
<ol id="steps"></ol>
</div>
</div>
<script>
(function () {
  function report(text) {
    document.body.dataset.octrace = 'error';
    document.getElementById('octrace-errors').textContent += text + '\n';
  }
  window.addEventListener('error', function (ev) { report('error: ' + ev.message); });
  window.addEventListener('unhandledrejection', function (ev) {
    report('unhandled rejection: ' + ev.reason);
  });
  var consoleError = console.error;
  console.error = function () {
    report('console.error: ' + Array.prototype.join.call(arguments, ' '));
    consoleError.apply(console, arguments);
  };
})();
</script>
<script id="octrace-data" type="application/json">@DATA@</script>
<script>
/* The page's kernel (@KERNELVERSION@): octrace's kernel, octree builder and explain compiled to
   WebAssembly by emscripten (teach/wasm/page_kernel.cpp). */
@KERNEL@
</script>
<script>
/* three.js and the octrace viewer (@VERSIONS@), bundled by esbuild. three.js: MIT licence,
   Copyright 2010-2025 three.js authors (https://threejs.org). */
@SCRIPT@
</script>
</body>
</html>
)html";

void replaceFirst(std::string& s, const std::string& from, const std::string& to) {
    size_t pos = s.find(from);
    if (pos == std::string::npos) return;
    s.replace(pos, from.size(), to);
}

// JSON inside a <script> element: "</" would end it; JSON allows "\/" for "/".
std::string scriptSafe(std::string text) {
    for (size_t p = text.find("</"); p != std::string::npos; p = text.find("</", p + 3))
        text.replace(p, 2, "<\\/");
    return text;
}

}  // namespace

std::string explainPage(const Explanation& e, const BuiltScene& bs, const LayoutOptions& options,
                        const FrameParams& frame, PageStats* statsOut) {
    if (!viewerAvailable())
        throw TeachError(
            "--html: this octrace was built without the page's viewer (configured with "
            "-DOCT_VIEWER=OFF); run scripts/setup, which installs three.js with npm ci, and "
            "rebuild");
    const Scene& scene = *bs.scene;
    PageStats stats;
    std::string note;
    PixelPageCounts counts;
    json d = pixelPageData(e, scene, &counts);
    stats.cells = counts.cells;
    stats.lines = counts.lines;
    addPlaneView(d, e, scene, bs.tree.get());
    d["mesh"] = modelJson(scene, stats, note);
    d["model_note"] = note;
    // The page traces pixels itself when this build has the kernel and the frame is a camera's
    // (a --ray explanation has no image to click).
    if (pageKernelAvailable() && e.pixelMode) {
        // The bunny's triangles travel once: the kernel rebuilds them from the model mesh
        // unless that was decimated.
        const bool fromModel = scene.kind == PrimKind::Triangles && !stats.reduced;
        d["kernel"] = kernelSpec(bs, options, frame, fromModel);
        stats.kernel = true;
    } else {
        d["kernel"] = nullptr;
        d["kernel_missing"] =
            !e.pixelMode ? "this page explains a ray given by --ray, not a pixel of an image"
                         : "this octrace was built without emscripten (the page's kernel is "
                           "WebAssembly: scripts/setup installs Debian's emscripten)";
    }
    const std::string dataText = scriptSafe(d.dump());

    std::string legend = "linear-gradient(to right";
    for (int i = 0; i <= 8; ++i) {
        char hex[8];
        hexColour(mapColour(ColourMap::Viridis, i / 8.0), hex);
        legend += std::string(", ") + hex;
    }
    legend += ")";
    const std::string sceneLine = e.scene + ": " + std::to_string(e.primitives) +
                                  (e.kind == PrimKind::Triangles ? " triangles" : " spheres");
    const std::string notes = note + (d["prims_note"].get<std::string>().empty() ? "" : " ") +
                              d["prims_note"].get<std::string>();

    std::string page = kTemplate;
    const std::string title = d["title"].get<std::string>();
    replaceFirst(page, "@TITLE@", xmlEscape(title));
    replaceFirst(page, "@TITLE@", xmlEscape(title));
    replaceFirst(page, "@SCENE@", xmlEscape(sceneLine));
    replaceFirst(page, "@SUMMARY@", xmlEscape(d["summary"].get<std::string>()));
    replaceFirst(page, "@LEGEND@", legend);
    replaceFirst(page, "@NOTE@", xmlEscape(notes));
    replaceFirst(page, "@VERSIONS@", viewerVersions());
    replaceFirst(page, "@KERNELVERSION@", pageKernelVersion());
    // Data and scripts last: nothing is searched for inside them.
    const size_t dataAt = page.find("@DATA@");
    page.replace(dataAt, 6, dataText);
    const std::string& kernel = pageKernelScript();
    const size_t kernelAt = page.find("@KERNEL@", dataAt + dataText.size());
    page.replace(kernelAt, 8, stats.kernel ? kernel : std::string());
    const size_t scriptAt = page.find("@SCRIPT@", kernelAt + (stats.kernel ? kernel.size() : 0));
    page.replace(scriptAt, 8, viewerScript());
    stats.kernelBytes = stats.kernel ? kernel.size() : 0;
    stats.bytes = page.size();
    if (statsOut) *statsOut = stats;
    return page;
}

}  // namespace oct
