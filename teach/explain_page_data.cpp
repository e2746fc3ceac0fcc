#include "teach/explain_page_data.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "core/octree/morton.h"
#include "core/render/film.h"
#include "teach/colour_map.h"
#include "teach/svg_view.h"
#include "teach/teach_error.h"

namespace oct {

using json = nlohmann::ordered_json;

namespace {

constexpr const char* kAlphabet =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

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

constexpr const char* kRayColour[2] = {"#ff00ff", "#00e5ff"};  // primary magenta, shadow cyan
constexpr const char* kOccludedColour = "#ff9500";

// Cells of one ray: every box tested or child skipped, visited ones numbered in visit order.
void addCells(json& cells, const Explanation& e, int rayIndex) {
    const RayTrace& r = rayIndex == 0 ? e.primary : *e.shadow;
    const std::map<uint64_t, int> order = visitOrder(r.steps);  // 1..n
    const int n = int(order.size());
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
        auto it = order.find(s.key);
        c["visited"] = it != order.end();
        if (it != order.end()) {
            char hex[8];
            hexColour(mapColour(ColourMap::Viridis, n > 1 ? double(it->second - 1) / (n - 1) : 1.0),
                      hex);
            c["order"] = it->second;
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
        note =
            std::to_string(tested.size()) + " primitives were tested; only the ones hit are drawn.";
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

json raysJson(const Explanation& e) {
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
    return rays;
}

json linesJson(const Explanation& e, uint64_t& count) {
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
            ++count;
        }
    }
    return lines;
}

// The first view: from the side of the ray, so the ray crosses the picture instead of
// pointing at the viewer, at a distance that shows the whole root box.
json firstView(const Explanation& e) {
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
    return {{"target", v3(target)},
            {"eye", v3(target + offset * (1.6f * length(e.root.extent())))},
            {"up", v3(up)}};
}

std::string summaryText(const Explanation& e) {
    const uint64_t boxes = e.primary.totals.boxTests + (e.shadow ? e.shadow->totals.boxTests : 0);
    const uint64_t prims = e.primary.totals.primTests + (e.shadow ? e.shadow->totals.primTests : 0);
    const uint64_t probes = e.primary.totals.probes + (e.shadow ? e.shadow->totals.probes : 0);
    return std::string(e.primary.hit.prim >= 0
                           ? "hit primitive " + std::to_string(e.primary.hit.prim)
                           : std::string("no hit")) +
           (e.shadowState == kOccluded ? ", in shadow"
            : e.shadowState == kLit    ? ", lit"
                                       : "") +
           ". Cost: " + std::to_string(boxes) + " boxes tested, " + std::to_string(prims) +
           " primitives tested" +
           (probes ? ", " + std::to_string(probes) + " hash probes" : std::string()) +
           " (primary + shadow ray).";
}

void fnv(uint64_t& h, const void* data, uint64_t bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (uint64_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
}

// The spec as read back (nlohmann::json, not the ordered json the page writes: a conversion
// between the two would copy, and a reference into the copy would dangle).
using SpecJson = nlohmann::json;

const SpecJson& field(const SpecJson& j, const char* name) {
    if (!j.is_object() || !j.contains(name))
        throw TeachError(std::string("page kernel: the scene description has no '") + name +
                         "' (a page written by another octrace version?)");
    return j.at(name);
}

std::vector<float> floatsOf(const SpecJson& j, const char* name, size_t n) {
    const SpecJson& a = field(j, name);
    if (!a.is_array() || a.size() != n)
        throw TeachError(std::string("page kernel: '") + name + "' is not " + std::to_string(n) +
                         " numbers");
    std::vector<float> out;
    for (const SpecJson& v : a) out.push_back(v.get<float>());
    return out;
}

Vec3 vec3At(const std::vector<float>& f, size_t i) { return {f[i], f[i + 1], f[i + 2]}; }

}  // namespace

std::string base64Encode(const void* data, size_t bytes) {
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

std::string base64Decode(const std::string& text) {
    if (text.size() % 4 != 0)
        throw TeachError("page kernel: base64 text of " + std::to_string(text.size()) +
                         " characters (not a multiple of 4)");
    int value[256];
    std::fill(value, value + 256, -1);
    for (int i = 0; i < 64; ++i) value[uint8_t(kAlphabet[i])] = i;
    std::string out;
    out.reserve(text.size() / 4 * 3);
    for (size_t i = 0; i < text.size(); i += 4) {
        uint32_t n = 0;
        int pad = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = text[i + k];
            const bool tail = c == '=' && i + 4 == text.size() && k >= 2;
            if (!tail && value[uint8_t(c)] < 0)
                throw TeachError("page kernel: '" + std::string(1, c) + "' at " +
                                 std::to_string(i + k) + " is not base64");
            pad += tail;
            n = n << 6 | uint32_t(tail ? 0 : value[uint8_t(c)]);
        }
        out += char(n >> 16 & 255);
        if (pad < 2) out += char(n >> 8 & 255);
        if (pad < 1) out += char(n & 255);
    }
    return out;
}

json pixelPageData(const Explanation& e, const Scene& scene, PixelPageCounts* countsOut) {
    PixelPageCounts counts;
    json d;
    d["root"] = box6(e.root);
    d["light"] = v3(e.light);
    json cells = json::array();
    addCells(cells, e, 0);
    if (e.shadow) addCells(cells, e, 1);
    counts.cells = cells.size();
    d["cells"] = std::move(cells);
    d["rays"] = raysJson(e);
    std::string primsNote;
    d["prims"] = primsJson(e, scene, primsNote);
    d["prims_note"] = primsNote;
    d["lines"] = linesJson(e, counts.lines);
    d["view"] = firstView(e);
    const std::string where =
        e.pixelMode ? "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + ") of " +
                          std::to_string(e.width) + "x" + std::to_string(e.height)
                    : std::string("a ray given by --ray");
    d["pixel"] = e.pixelMode ? json::array({e.x, e.y}) : json(nullptr);
    d["title"] = "octrace explain: " + where + ", layout " + e.layout;
    d["summary"] = summaryText(e);
    if (countsOut) *countsOut = counts;
    return d;
}

void addPlaneView(json& data, const Explanation& e, const Scene& scene, const Octree* tree) {
    try {
        data["svg"] = explainSvg(e, scene, tree, "");
    } catch (const std::exception& ex) {
        data["svg"] = nullptr;
        data["svg_error"] = ex.what();
    }
}

uint64_t layoutFingerprint(const BuiltScene& bs) {
    uint64_t h = 0xcbf29ce484222325ull;
    bs.visit([&](const auto& view) {
        using View = std::decay_t<decltype(view)>;
        View::forEachArray(view, [&](const char*, const auto& span) {
            if (span.data) fnv(h, span.data, span.bytes());
        });
    });
    const Scene& s = *bs.scene;
    if (s.kind == PrimKind::Triangles)
        fnv(h, s.triangles.data(), s.triangles.size() * sizeof(Triangle));
    else
        fnv(h, s.spheres.data(), s.spheres.size() * sizeof(Sphere));
    return h;
}

// The spec names every field of these structs: one added there must be added here.
static_assert(sizeof(Camera) == 12 * sizeof(float), "kernelSpec writes Camera's 12 floats");
static_assert(sizeof(ShadingParams) == 13 * sizeof(float),
              "kernelSpec writes ShadingParams' 13 floats");

json kernelSpec(const BuiltScene& bs, const LayoutOptions& o, const FrameParams& f,
                bool fromModel) {
    const Scene& s = *bs.scene;
    json scene;
    scene["name"] = s.name;
    scene["kind"] = primKindName(s.kind);
    scene["from_model"] = fromModel;
    if (!fromModel)
        scene["data"] =
            s.kind == PrimKind::Triangles
                ? base64Encode(s.triangles.data(), s.triangles.size() * sizeof(Triangle))
                : base64Encode(s.spheres.data(), s.spheres.size() * sizeof(Sphere));
    scene["domain"] = s.domain ? box6(*s.domain) : json(nullptr);
    scene["grid_depth"] = s.gridDepth;
    json spec;
    spec["scene"] = std::move(scene);
    spec["layout"] = bs.layout->name;
    spec["build"] = {{"max_depth", o.build.maxDepth},
                     {"max_prims", o.build.maxPrims},
                     {"max_references", o.build.maxReferences},
                     {"max_nodes", o.build.maxNodes}};
    spec["buckets"] = {{"bucket_slots", o.hash.bucketSlots}, {"budget_bytes", o.hash.budgetBytes}};
    spec["linear_budget"] = o.linearBudget;
    const Camera& c = f.camera;
    const ShadingParams& sh = f.shading;
    spec["frame"] = {{"width", f.width},
                     {"height", f.height},
                     {"camera",
                      {c.eye.x, c.eye.y, c.eye.z, c.forward.x, c.forward.y, c.forward.z, c.right.x,
                       c.right.y, c.right.z, c.up.x, c.up.y, c.up.z}},
                     {"shading",
                      {sh.light.x, sh.light.y, sh.light.z, sh.surfaceColour.x, sh.surfaceColour.y,
                       sh.surfaceColour.z, sh.background.x, sh.background.y, sh.background.z,
                       sh.ambient, sh.diffuse, sh.specular, sh.shadowBias}}};
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)layoutFingerprint(bs));
    spec["fingerprint"] = hex;
    return spec;
}

Scene kernelSpecScene(const nlohmann::json& spec, const std::string& positions,
                      const std::string& indices) {
    const SpecJson& j = field(spec, "scene");
    Scene s;
    s.name = field(j, "name").get<std::string>();
    const std::string kind = field(j, "kind").get<std::string>();
    if (kind == "triangles" && !indices.empty()) {
        s.kind = PrimKind::Triangles;
        const size_t vertices = positions.size() / 12, n = indices.size() / 12;
        if (positions.size() % 12 || indices.size() % 12)
            throw TeachError("page kernel: a model of " + std::to_string(positions.size()) +
                             " position bytes and " + std::to_string(indices.size()) +
                             " index bytes (12 a vertex, 12 a triangle)");
        std::vector<Vec3> v(vertices);
        std::memcpy(v.data(), positions.data(), positions.size());
        std::vector<uint32_t> idx(3 * n);
        std::memcpy(idx.data(), indices.data(), indices.size());
        s.triangles.resize(n);
        for (size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k)
                if (idx[3 * i + k] >= vertices)
                    throw TeachError("page kernel: triangle " + std::to_string(i) +
                                     " names vertex " + std::to_string(idx[3 * i + k]) + " of " +
                                     std::to_string(vertices));
            s.triangles[i] = {v[idx[3 * i]], v[idx[3 * i + 1]], v[idx[3 * i + 2]]};
        }
    } else if (kind == "triangles") {
        s.kind = PrimKind::Triangles;
        if (positions.size() % sizeof(Triangle))
            throw TeachError("page kernel: triangle data of " + std::to_string(positions.size()) +
                             " bytes (not 36 a triangle)");
        s.triangles.resize(positions.size() / sizeof(Triangle));
        std::memcpy(s.triangles.data(), positions.data(), positions.size());
    } else if (kind == "spheres") {
        s.kind = PrimKind::Spheres;
        if (positions.size() % sizeof(Sphere))
            throw TeachError("page kernel: sphere data of " + std::to_string(positions.size()) +
                             " bytes (not 16 a sphere)");
        s.spheres.resize(positions.size() / sizeof(Sphere));
        std::memcpy(s.spheres.data(), positions.data(), positions.size());
    } else {
        throw TeachError("page kernel: scene kind '" + kind + "' (triangles or spheres)");
    }
    if (!field(j, "domain").is_null()) {
        const std::vector<float> d = floatsOf(j, "domain", 6);
        s.domain = Aabb{vec3At(d, 0), vec3At(d, 3)};
    }
    s.gridDepth = field(j, "grid_depth").get<int>();
    return s;
}

LayoutOptions kernelSpecOptions(const nlohmann::json& spec) {
    LayoutOptions o;
    const SpecJson& b = field(spec, "build");
    o.build.maxDepth = field(b, "max_depth").get<int>();
    o.build.maxPrims = field(b, "max_prims").get<uint32_t>();
    o.build.maxReferences = field(b, "max_references").get<uint64_t>();
    o.build.maxNodes = field(b, "max_nodes").get<uint64_t>();
    const SpecJson& h = field(spec, "buckets");
    o.hash.bucketSlots = field(h, "bucket_slots").get<uint32_t>();
    o.hash.budgetBytes = field(h, "budget_bytes").get<uint64_t>();
    o.linearBudget = field(spec, "linear_budget").get<uint64_t>();
    return o;
}

FrameParams kernelSpecFrame(const nlohmann::json& spec) {
    const SpecJson& f = field(spec, "frame");
    FrameParams p;
    p.width = field(f, "width").get<int>();
    p.height = field(f, "height").get<int>();
    const std::vector<float> c = floatsOf(f, "camera", 12);
    p.camera = {vec3At(c, 0), vec3At(c, 3), vec3At(c, 6), vec3At(c, 9)};
    const std::vector<float> s = floatsOf(f, "shading", 13);
    p.shading.light = vec3At(s, 0);
    p.shading.surfaceColour = vec3At(s, 3);
    p.shading.background = vec3At(s, 6);
    p.shading.ambient = s[9];
    p.shading.diffuse = s[10];
    p.shading.specular = s[11];
    p.shading.shadowBias = s[12];
    return p;
}

}  // namespace oct
