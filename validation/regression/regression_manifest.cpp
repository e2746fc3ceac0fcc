#include "validation/regression/regression_manifest.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "core/io/input_file.h"
#include "core/octree/layout_registry.h"
#include "core/scene/scene_generators.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using regression_detail::field;
using report_detail::fmt;

constexpr const char* kFormat = "octrace-regression";
// Version 2 names a frame's cost boxes_tested, prims_tested, boxes_per_pixel, prims_per_pixel
// (the words of docs/TEACHING.md, "Words"). Version 1 named them nodes, prims, nodes_per_pixel,
// prims_per_pixel; it is still read (the old keys), and --update writes version 2.
constexpr int kVersion = 2;
constexpr int kOldestVersion = 1;

// The keys of a frame's cost totals in a manifest of `version`.
const char* boxesKey(int version) { return version == 1 ? "nodes" : "boxes_tested"; }
const char* primsKey(int version) { return version == 1 ? "prims" : "prims_tested"; }

}  // namespace

bool isPlainName(const std::string& s) {
    if (s.empty() || s[0] == '.' || s.size() > 200) return false;
    for (char c : s)
        if (!(std::isalnum((unsigned char)c) || c == '.' || c == '-' || c == '_' || c == '+'))
            return false;
    return true;
}

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
    throw IoError(path + ": " + what);
}

template <class T>
std::optional<T> optionalField(const json& j, const char* name, const std::string& path) {
    if (!j.contains(name)) return std::nullopt;
    return field<T>(j, name, path);
}

// "all" or a list of layout names, each of this build's registry.
std::optional<std::vector<std::string>> readLayouts(const json& j, const std::string& path,
                                                    const std::string& where) {
    if (!j.contains("layouts")) return std::nullopt;
    const json& v = j.at("layouts");
    if (v.is_string() && v.get<std::string>() == "all") return std::vector<std::string>{};
    if (!v.is_array() || v.empty())
        refuse(path, where + ": 'layouts' must be \"all\" or a non-empty list of " + layoutNames());
    std::vector<std::string> out;
    for (const json& n : v) {
        if (!n.is_string())
            refuse(path, where + ": 'layouts' must list names (" + layoutNames() + ")");
        try {
            out.push_back(findLayout(n.get<std::string>()).name);
        } catch (const std::exception& e) {
            refuse(path, where + ": " + e.what());
        }
    }
    return out;
}

std::optional<std::vector<std::string>> readViews(const json& j, const std::string& path,
                                                  const std::string& where) {
    if (!j.contains("views")) return std::nullopt;
    std::vector<std::string> out;
    const json& v = j.at("views");
    if (!v.is_array() || v.empty())
        refuse(path, where + ": 'views' must be a non-empty list of view names");
    for (const json& n : v) {
        if (!n.is_string() || !isRegressionView(n.get<std::string>())) {
            std::string names;
            for (const std::string& s : regressionViewNames()) names += " " + s;
            refuse(path, where + ": view " + n.dump() + " is not one of" + names);
        }
        if (std::find(out.begin(), out.end(), n.get<std::string>()) != out.end())
            refuse(path, where + ": view " + n.dump() + " is listed twice");
        out.push_back(n.get<std::string>());
    }
    return out;
}

SceneSettings readSettings(const json& j, const std::string& path, const std::string& where) {
    SceneSettings s;
    s.width = optionalField<int>(j, "width", path);
    s.height = optionalField<int>(j, "height", path);
    s.maxDepth = optionalField<int>(j, "max_depth", path);
    s.maxPrims = optionalField<uint32_t>(j, "max_prims", path);
    s.radius = optionalField<float>(j, "radius", path);
    s.scale = optionalField<double>(j, "scale", path);
    if (s.scale && !(*s.scale >= 1e-6 && *s.scale <= 1e6))
        refuse(path, where + ": scale must lie in 1e-6..1e6");
    s.layouts = readLayouts(j, path, where);
    s.views = readViews(j, path, where);
    if ((s.width && (*s.width < 1 || *s.width > 4096)) ||
        (s.height && (*s.height < 1 || *s.height > 4096)))
        refuse(path, where + ": width and height must lie in 1..4096");
    if (s.maxDepth && (*s.maxDepth < 0 || *s.maxDepth > kMaxOctreeDepth))
        refuse(path, where + fmt(": max_depth must lie in 0..%d", kMaxOctreeDepth));
    if (s.maxPrims && *s.maxPrims < 1) refuse(path, where + ": max_prims must be at least 1");
    if (s.radius && !(*s.radius >= 0.0f)) refuse(path, where + ": radius must be 0 or more");
    return s;
}

void writeSettings(const SceneSettings& s, json& j) {
    if (s.width) j["width"] = *s.width;
    if (s.height) j["height"] = *s.height;
    if (s.maxDepth) j["max_depth"] = *s.maxDepth;
    if (s.maxPrims) j["max_prims"] = *s.maxPrims;
    if (s.radius) j["radius"] = *s.radius;
    if (s.scale) j["scale"] = *s.scale;
    if (s.layouts) j["layouts"] = s.layouts->empty() ? json("all") : json(*s.layouts);
    if (s.views) j["views"] = *s.views;
}

// A tolerance of the file: each field at most the ceiling's (a file may tighten the rule only).
GoldenTolerance readTolerance(const json& j, const std::string& path, const std::string& name) {
    const GoldenTolerance ceiling = goldenCeiling();
    GoldenTolerance t;
    t.channel = field<int>(j, "channel", path);
    t.maxOverFraction = field<double>(j, "max_over_fraction", path);
    t.maxDiff = field<int>(j, "max_diff", path);
    if (t.channel < 0 || t.maxOverFraction < 0.0 || t.maxDiff < 0)
        refuse(path, "tolerances.golden." + name + ": negative values");
    if (t.channel > ceiling.channel || !(t.maxOverFraction <= ceiling.maxOverFraction) ||
        t.maxDiff > ceiling.maxDiff)
        refuse(path, "tolerances.golden." + name +
                         fmt(" is looser than the rule's ceiling (channel %d, "
                             "max_over_fraction %g, max_diff %d): a file may tighten the "
                             "golden rule, not loosen it (docs/VALIDATION.md, \"Golden images\")",
                             ceiling.channel, ceiling.maxOverFraction, ceiling.maxDiff));
    return t;
}

json toleranceJson(const GoldenTolerance& t) {
    return {
        {"channel", t.channel}, {"max_over_fraction", t.maxOverFraction}, {"max_diff", t.maxDiff}};
}

RegressionFrame readFrame(const json& j, const std::string& path, const std::string& where,
                          int version) {
    RegressionFrame f;
    f.view = field<std::string>(j, "view", path);
    if (!isRegressionView(f.view)) refuse(path, where + ": unknown view '" + f.view + "'");
    f.image = field<std::string>(j, "image", path);
    // Beside the manifest, by name only: a path could write outside the folder on --update.
    if (!isPlainName(f.image))
        refuse(path, where + ": image '" + f.image + "' must be a plain file name");
    f.pixels = field<uint64_t>(j, "pixels", path);
    const json cost = field<json>(j, "cost", path);
    if (!cost.is_object()) refuse(path, where + ": 'cost' must be an object by layout");
    for (auto it = cost.begin(); it != cost.end(); ++it)
        f.cost[it.key()] = {f.pixels, field<uint64_t>(*it, boxesKey(version), path),
                            field<uint64_t>(*it, primsKey(version), path)};
    return f;
}

json frameJson(const RegressionFrame& f) {
    json cost = json::object();
    for (const auto& [name, t] : f.cost)
        cost[name] = {{boxesKey(kVersion), t.nodes},
                      {primsKey(kVersion), t.prims},
                      {"boxes_per_pixel", t.nodesPerPixel()},
                      {"prims_per_pixel", t.primsPerPixel()}};
    return {{"view", f.view}, {"image", f.image}, {"pixels", f.pixels}, {"cost", cost}};
}

}  // namespace

const std::vector<std::string>& regressionViewNames() {
    // +z is the default view (the default framing looks along -z from the +z side).
    static const std::vector<std::string> names{"default", "+x", "-x", "+y", "-y", "-z", "inside"};
    return names;
}

bool isRegressionView(const std::string& view) {
    const auto& n = regressionViewNames();
    return std::find(n.begin(), n.end(), view) != n.end();
}

std::string regressionEntryName(const std::string& scene, const std::optional<std::string>& name) {
    if (name) return *name;
    std::string base =
        findSceneGenerator(scene) ? scene : std::filesystem::path(scene).filename().string();
    std::replace(base.begin(), base.end(), ':', '-');
    return base;
}

std::string regressionImageName(const std::string& base, const std::string& view) {
    if (view == "default") return base + ".png";
    std::string v = view;
    if (v[0] == '+' || v[0] == '-') v = v.substr(1) + (v[0] == '+' ? "pos" : "neg");
    return base + "-" + v + ".png";
}

RegressionRender RegressionManifest::render(const RegressionScene& s) const {
    RegressionRender r;
    r.width = s.own.width.value_or(*defaults.width);
    r.height = s.own.height.value_or(*defaults.height);
    r.build.maxDepth = s.own.maxDepth.value_or(*defaults.maxDepth);
    r.build.maxPrims = s.own.maxPrims.value_or(*defaults.maxPrims);
    r.radius = s.own.radius.value_or(*defaults.radius);
    r.scale = s.own.scale.value_or(defaults.scale.value_or(1.0));
    return r;
}

std::vector<std::string> RegressionManifest::layouts(const RegressionScene& s) const {
    return s.own.layouts.value_or(*defaults.layouts);
}

std::vector<std::string> RegressionManifest::views(const RegressionScene& s) const {
    return s.own.views.value_or(*defaults.views);
}

GoldenTolerance RegressionManifest::goldenTolerance(const std::string& backend) const {
    auto it = golden.find(backend);
    return it == golden.end() ? goldenCeiling() : it->second;
}

std::string RegressionManifest::dir() const {
    return std::filesystem::path(path).parent_path().string();
}

const RegressionScene* RegressionManifest::find(const std::string& name) const {
    for (const RegressionScene& s : scenes)
        if (regressionEntryName(s.scene, s.name) == name) return &s;
    return nullptr;
}

RegressionManifest readRegressionManifest(const std::string& path) {
    json j = readRegressionJson(path, "regression manifest");
    const int version = field<int>(j, "version", path);
    if (field<std::string>(j, "format", path) != kFormat || version < kOldestVersion ||
        version > kVersion)
        refuse(path, fmt("not an %s version %d to %d manifest", kFormat, kOldestVersion, kVersion));
    RegressionManifest m;
    m.path = path;
    m.octrace = field<std::string>(j, "octrace", path);
    m.backends = field<std::vector<std::string>>(j, "backends", path);
    if (m.backends.empty()) refuse(path, "'backends' lists none; give at least \"cpu\"");
    const json tol = field<json>(j, "tolerances", path);
    const json golden = field<json>(tol, "golden", path);  // named: items() does not own it
    if (!golden.is_object()) refuse(path, "tolerances.golden must be an object by backend");
    for (auto it = golden.begin(); it != golden.end(); ++it)
        m.golden[it.key()] = readTolerance(*it, path, it.key());
    m.costTolerance = field<double>(tol, "cost", path);
    if (!(m.costTolerance >= 0.0 && m.costTolerance <= kCostTolerance))
        refuse(path, fmt("tolerances.cost %g must lie in 0..%g: a file may tighten the cost rule, "
                         "not loosen it",
                         m.costTolerance, kCostTolerance));
    m.defaults = readSettings(field<json>(j, "defaults", path), path, "defaults");
    const SceneSettings& d = m.defaults;
    if (!d.width || !d.height || !d.maxDepth || !d.maxPrims || !d.radius || !d.layouts || !d.views)
        refuse(path,
               "'defaults' must set width, height, max_depth, max_prims, radius, layouts "
               "and views");
    std::set<std::string> images, scenes;
    for (const json& e : field<json>(j, "scenes", path)) {
        RegressionScene s;
        s.scene = field<std::string>(e, "scene", path);
        s.name = optionalField<std::string>(e, "name", path);
        const std::string name = regressionEntryName(s.scene, s.name);
        const std::string where = "scene '" + name + "'";
        if (!isPlainName(name))
            refuse(path, where + ": a name of letters, digits, '.', '-' and '_' only");
        if (!scenes.insert(name).second)
            refuse(path, where + " is listed twice; give one of them a \"name\"");
        s.own = readSettings(e, path, where);
        if (e.contains("frames"))
            for (const json& f : field<json>(e, "frames", path)) {
                s.frames.push_back(readFrame(f, path, where, version));
                if (!images.insert(s.frames.back().image).second)
                    refuse(path, where + ": image '" + s.frames.back().image +
                                     "' is another frame's too");
            }
        m.scenes.push_back(std::move(s));
    }
    if (m.scenes.empty()) refuse(path, "lists no scenes; add one with --regression-add SCENE");
    return m;
}

json toJson(const RegressionManifest& m) {
    json golden = json::object();
    for (const auto& [name, t] : m.golden) golden[name] = toleranceJson(t);
    json defaults = json::object();
    writeSettings(m.defaults, defaults);
    json scenes = json::array();
    for (const RegressionScene& s : m.scenes) {
        json e = {{"scene", s.scene}};
        if (s.name) e["name"] = *s.name;
        writeSettings(s.own, e);
        json frames = json::array();
        for (const RegressionFrame& f : s.frames) frames.push_back(frameJson(f));
        e["frames"] = frames;
        scenes.push_back(e);
    }
    return {{"format", kFormat},
            {"version", kVersion},
            {"octrace", m.octrace},
            {"backends", m.backends},
            {"tolerances", {{"golden", golden}, {"cost", m.costTolerance}}},
            {"defaults", defaults},
            {"scenes", scenes}};
}

}  // namespace oct
