#include "teach/explain_page.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <unordered_map>

#include "core/octree/morton.h"
#include "core/render/film.h"
#include "teach/colour_map.h"
#include "teach/teach_error.h"
#include "teach/viewer_script.h"

namespace oct {
namespace {

using json = nlohmann::ordered_json;

std::string base64(const void* data, size_t bytes) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* p = static_cast<const uint8_t*>(data);
    std::string out;
    out.reserve((bytes + 2) / 3 * 4);
    for (size_t i = 0; i < bytes; i += 3) {
        const uint32_t n = uint32_t(p[i]) << 16 | (i + 1 < bytes ? uint32_t(p[i + 1]) << 8 : 0) |
                           (i + 2 < bytes ? uint32_t(p[i + 2]) : 0);
        out += kAlphabet[n >> 18 & 63];
        out += kAlphabet[n >> 12 & 63];
        out += i + 1 < bytes ? kAlphabet[n >> 6 & 63] : '=';
        out += i + 2 < bytes ? kAlphabet[n & 63] : '=';
    }
    return out;
}

json v3(Vec3 v) { return json::array({v.x, v.y, v.z}); }
json box6(const Aabb& b) { return json::array({b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}); }

// The box of the cell with Morton key `key` under `root` (childBox digit by digit, as the
// builder splits), for children the traversal skipped without reporting a box.
Aabb boxOfKey(const Aabb& root, uint64_t key) {
    const int depth = keyDepth(key);
    Aabb b = root;
    for (int level = depth - 1; level >= 0; --level) b = childBox(b, int(key >> (3 * level) & 7));
    return b;
}

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

constexpr const char* kRayColour[2] = {"#ff00ff", "#00e5ff"};  // primary magenta, shadow cyan
constexpr const char* kOccludedColour = "#ff9500";

json modelJson(const Scene& scene, PageStats& stats, std::string& note) {
    json j;
    if (scene.kind == PrimKind::Triangles) {
        const IndexedMesh m = pageMesh(scene, kPageMaxTriangles);
        j["kind"] = "triangles";
        j["positions"] = base64(m.positions.data(), m.positions.size() * 4);
        j["indices"] = base64(m.indices.data(), m.indices.size() * 4);
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
        j["positions"] = base64(pos.data(), pos.size() * 4);
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

// Cells of one ray: every box tested or child skipped, visited ones numbered in visit order.
void addCells(json& cells, const Explanation& e, int rayIndex) {
    const RayTrace& r = rayIndex == 0 ? e.primary : *e.shadow;
    std::map<uint64_t, int> visitOrder;
    for (const ExplainStep& s : r.steps)
        if (s.event == StepEvent::Pop && s.hit && !visitOrder.count(s.key))
            visitOrder.emplace(s.key, int(visitOrder.size()));
    const int n = int(visitOrder.size());
    std::set<uint64_t> seen;
    for (const ExplainStep& s : r.steps) {
        if ((s.event != StepEvent::Box && s.event != StepEvent::Skip) || seen.count(s.key))
            continue;
        seen.insert(s.key);
        json c;
        c["ray"] = rayIndex;
        c["key"] = keyOctal(s.key);
        c["depth"] = keyDepth(s.key);
        c["box"] = box6(s.event == StepEvent::Box ? s.box : boxOfKey(e.root, s.key));
        auto it = visitOrder.find(s.key);
        c["visited"] = it != visitOrder.end();
        if (it != visitOrder.end()) {
            char hex[8];
            hexColour(mapColour(ColourMap::Viridis, n > 1 ? double(it->second) / (n - 1) : 1.0),
                      hex);
            c["order"] = it->second + 1;
            c["colour"] = hex;
        }
        cells.push_back(std::move(c));
    }
}

// The primitives the rays tested, drawn exactly (all of them unless exhaustive tracing tested
// more than kPageMaxTestedPrims: then the hit ones only).
json primsJson(const Explanation& e, const Scene& scene, std::string& note) {
    std::map<uint32_t, bool> tested;  // id -> hit by some ray
    for (int i = 0; i < (e.shadow ? 2 : 1); ++i)
        for (const ExplainStep& s : (i == 0 ? e.primary : *e.shadow).steps)
            if (s.event == StepEvent::Prim) tested[s.prim] = tested[s.prim] || s.hit;
    const bool all = tested.size() <= kPageMaxTestedPrims;
    if (!all)
        note += (note.empty() ? "" : " ") + std::to_string(tested.size()) +
                " primitives were tested; only the ones hit are drawn.";
    json out = json::array();
    for (auto [id, hit] : tested) {
        if (!all && !hit) continue;
        json p;
        p["id"] = id;
        p["hit"] = hit;
        if (scene.kind == PrimKind::Triangles) {
            const Triangle& t = scene.triangles[id];
            p["v"] = {t.v0.x, t.v0.y, t.v0.z, t.v1.x, t.v1.y, t.v1.z, t.v2.x, t.v2.y, t.v2.z};
        } else {
            p["c"] = v3(scene.spheres[id].center);
            p["r"] = scene.spheres[id].radius;
        }
        out.push_back(std::move(p));
    }
    return out;
}

// Where a ray is drawn to: its hit, else where it leaves the root box, else its closest
// approach to it (and as far again).
Vec3 rayEnd(const Explanation& e, const RayTrace& r) {
    if (r.hit.prim >= 0) return r.ray.org + r.ray.dir * r.hit.t;
    if (std::isfinite(r.ray.tmax)) return r.ray.org + r.ray.dir * r.ray.tmax;
    float t0, t1;
    if (intersectBox(makeRaySlabs(r.ray.org, r.ray.dir), e.root, r.ray.tmin, r.ray.tmax, t0, t1))
        return r.ray.org + r.ray.dir * t1;
    const float t = r.miss ? float(2.0 * r.miss->t) : length(e.root.extent());
    return r.ray.org + r.ray.dir * std::max(t, length(e.root.extent()));
}

json linesJson(const Explanation& e, PageStats& stats) {
    json lines = json::array();
    auto heading = [&](const std::string& text) {
        lines.push_back({{"heading", true}, {"text", text}});
    };
    for (int i = 0; i < (e.shadow ? 2 : 1); ++i) {
        heading(i == 0 ? "Primary ray (magenta)" : "Shadow ray (cyan: lit, orange: occluded)");
        for (const ExplainLine& l : explainLines(e, i)) {
            json j;
            j["ray"] = l.rayIndex;
            j["step"] = l.step;
            j["text"] = l.text;
            j["key"] = l.key ? json(keyOctal(l.key)) : json(nullptr);
            j["prim"] = l.prim;
            lines.push_back(std::move(j));
            ++stats.lines;
        }
    }
    return lines;
}

std::string escapeHtml(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

// The page's frame; @TITLE@, @SUMMARY@, @NOTE@, @LEGEND@, @DATA@, @SCRIPT@, @VERSIONS@ are
// replaced. The first script collects errors before the viewer runs, so a test (and a reader)
// sees any failure in the page itself.
const char* kTemplate = R"html(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
html, body { margin: 0; height: 100%; background: #15171f; color: #e8e8ec;
  font: 13px/1.35 system-ui, sans-serif; }
#app { display: flex; height: 100%; }
#view { flex: 1 1 62%; position: relative; min-width: 0; }
#panel { flex: 1 1 38%; max-width: 560px; display: flex; flex-direction: column;
  border-left: 1px solid #30333d; min-width: 0; }
#head { padding: 8px 10px; border-bottom: 1px solid #30333d; }
#head h1 { font-size: 15px; margin: 0 0 4px; }
#head p { margin: 2px 0; color: #b4b7c2; }
.bar { height: 10px; border-radius: 2px; margin: 4px 0 2px; background: @LEGEND@; }
.ends { display: flex; justify-content: space-between; color: #b4b7c2; font-size: 11px; }
#steps { list-style: none; margin: 0; padding: 4px 0; overflow: auto; flex: 1;
  font: 11px/1.4 ui-monospace, monospace; white-space: pre; }
#steps li { padding: 0 10px; cursor: default; }
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
<div id="view"></div>
<div id="panel">
<div id="head">
<h1>@TITLE@</h1>
@SUMMARY@
<div class="bar"></div>
<div class="ends"><span>cells: first visited</span><span>last visited</span></div>
<p>@NOTE@</p>
<p><label><input type="checkbox" id="show-model" checked> model</label>
<label><input type="checkbox" id="show-missed"> boxes missed, skipped or dropped</label></p>
<p>Hover a step to highlight its cell or primitive; click to keep it (the address then names
it: #step=N, #shadow=N). Drag to orbit, scroll to zoom.</p>
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

}  // namespace

std::string explainPage(const Explanation& e, const Scene& scene, PageStats* statsOut) {
    if (!viewerAvailable())
        throw TeachError(
            "--html: this octrace was built without the page's viewer (configured with "
            "-DOCT_VIEWER=OFF); run scripts/setup, which installs three.js with npm ci, and "
            "rebuild");
    PageStats stats;
    std::string note;
    json d;
    const std::string where =
        e.pixelMode ? "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + ") of " +
                          std::to_string(e.width) + "x" + std::to_string(e.height)
                    : std::string("a ray given by --ray");
    d["mesh"] = modelJson(scene, stats, note);
    d["root"] = box6(e.root);
    d["light"] = v3(e.light);
    json cells = json::array();
    addCells(cells, e, 0);
    if (e.shadow) addCells(cells, e, 1);
    stats.cells = cells.size();
    d["cells"] = std::move(cells);
    json rays = json::array();
    for (int i = 0; i < (e.shadow ? 2 : 1); ++i) {
        const RayTrace& r = i == 0 ? e.primary : *e.shadow;
        json jr;
        jr["role"] = r.role;
        jr["from"] = v3(r.ray.org);
        jr["to"] = v3(rayEnd(e, r));
        jr["hit"] = r.hit.prim >= 0 ? v3(r.ray.org + r.ray.dir * r.hit.t) : json(nullptr);
        jr["colour"] = i == 0                       ? kRayColour[0]
                       : e.shadowState == kOccluded ? kOccludedColour
                                                    : kRayColour[1];
        rays.push_back(std::move(jr));
    }
    d["rays"] = std::move(rays);
    d["prims"] = primsJson(e, scene, note);
    d["lines"] = linesJson(e, stats);

    // The first view: from the side of the ray, so the ray crosses the picture instead of
    // pointing at the viewer, at a distance that shows the whole root box.
    const Vec3 dir = e.primary.ray.dir;
    const Vec3 target =
        e.primary.hit.prim >= 0 ? e.primary.ray.org + dir * e.primary.hit.t : e.root.center();
    Vec3 up = {0, 1, 0};
    Vec3 side = cross(dir, up);
    if (length(side) < 1e-3f) {
        up = {0, 0, 1};
        side = cross(dir, up);
    }
    side = normalize(side);
    const Vec3 offset = normalize(side * 1.0f + up * 0.45f - dir * 0.35f);
    d["view"] = {{"target", v3(target)},
                 {"eye", v3(target + offset * (1.6f * length(e.root.extent())))},
                 {"up", v3(up)}};

    std::string dataText = d.dump();
    // "</" inside the JSON would end its script element: JSON allows "\/" for "/".
    for (size_t p = dataText.find("</"); p != std::string::npos; p = dataText.find("</", p + 3))
        dataText.replace(p, 2, "<\\/");

    const std::string title = "octrace explain: " + where + ", layout " + e.layout;
    const uint64_t nodes = e.primary.totals.boxTests + (e.shadow ? e.shadow->totals.boxTests : 0);
    const uint64_t prims = e.primary.totals.primTests + (e.shadow ? e.shadow->totals.primTests : 0);
    const uint64_t probes = e.primary.totals.probes + (e.shadow ? e.shadow->totals.probes : 0);
    std::string summary = "<p>" + escapeHtml(e.scene) + ": " + std::to_string(e.primitives) +
                          (e.kind == PrimKind::Triangles ? " triangles" : " spheres") + "</p>";
    summary +=
        "<p>" +
        std::string(e.primary.hit.prim >= 0 ? "hit primitive " + std::to_string(e.primary.hit.prim)
                                            : std::string("no hit")) +
        (e.shadowState == kOccluded ? ", in shadow"
         : e.shadowState == kLit    ? ", lit"
                                    : "") +
        ". Cost: " + std::to_string(nodes) + " node boxes tested, " + std::to_string(prims) +
        " primitives tested" +
        (probes ? ", " + std::to_string(probes) + " hash probes" : std::string()) +
        " (primary + shadow ray).</p>";
    std::string legend = "linear-gradient(to right";
    for (int i = 0; i <= 8; ++i) {
        char hex[8];
        hexColour(mapColour(ColourMap::Viridis, i / 8.0), hex);
        legend += std::string(", ") + hex;
    }
    legend += ")";

    std::string page = kTemplate;
    replaceFirst(page, "@TITLE@", escapeHtml(title));
    replaceFirst(page, "@TITLE@", escapeHtml(title));
    replaceFirst(page, "@SUMMARY@", summary);
    replaceFirst(page, "@LEGEND@", legend);
    replaceFirst(page, "@NOTE@", escapeHtml(note));
    replaceFirst(page, "@VERSIONS@", viewerVersions());
    // Data and script last: nothing is searched for inside them.
    const size_t dataAt = page.find("@DATA@");
    page.replace(dataAt, 6, dataText);
    const size_t scriptAt = page.find("@SCRIPT@", dataAt + dataText.size());
    page.replace(scriptAt, 8, viewerScript());
    stats.bytes = page.size();
    if (statsOut) *statsOut = stats;
    return page;
}

}  // namespace oct
