#include "validation/regression/cost_baseline.h"

#include <chrono>
#include <cmath>
#include <map>

#include "core/io/output_file.h"
#include "core/octree/layout_registry.h"
#include "validation/rays/ray_manifest.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using regression_detail::field;
using report_detail::fmt;
using report_detail::num;

constexpr const char* kFormat = "octrace-cost-baselines";

struct SceneBaselines {
    std::string scene;
    std::map<std::string, CostTotals> layouts;  // by layout name
    std::vector<std::string> order;             // as in the file
};

struct BaselineFile {
    std::string octrace;
    RegressionRender render;
    std::vector<SceneBaselines> scenes;
};

BaselineFile readBaselines(const std::string& path) {
    json j = readRegressionJson(path, "cost baselines");
    if (field<std::string>(j, "format", path) != kFormat || field<int>(j, "version", path) != 1)
        throw IoError(path + ": not an " + kFormat + " version 1 file");
    BaselineFile b;
    b.octrace = field<std::string>(j, "octrace", path);
    b.render = regressionRenderFromJson(field<json>(j, "render", path), path);
    for (const json& s : field<json>(j, "scenes", path)) {
        SceneBaselines sb;
        sb.scene = field<std::string>(s, "scene", path);
        const uint64_t pixels = field<uint64_t>(s, "pixels", path);
        const json layoutsJson = field<json>(s, "layouts", path);
        if (!layoutsJson.is_object())
            throw IoError(path + ": scene '" + sb.scene + "': 'layouts' must be an object");
        for (auto it = layoutsJson.begin(); it != layoutsJson.end(); ++it) {
            sb.layouts[it.key()] = {pixels, field<uint64_t>(*it, "nodes", path),
                                    field<uint64_t>(*it, "prims", path)};
            sb.order.push_back(it.key());
        }
        b.scenes.push_back(std::move(sb));
    }
    if (b.scenes.empty()) throw IoError(path + ": lists no scenes; add some");
    return b;
}

json baselinesJson(const BaselineFile& b) {
    json scenes = json::array();
    for (const SceneBaselines& s : b.scenes) {
        json layoutsJson = json::object();
        uint64_t pixels = 0;
        for (const auto& [name, t] : s.layouts) {
            pixels = t.pixels;
            layoutsJson[name] = {{"nodes", t.nodes},
                                 {"prims", t.prims},
                                 {"nodes_per_pixel", t.nodesPerPixel()},
                                 {"prims_per_pixel", t.primsPerPixel()}};
        }
        scenes.push_back({{"scene", s.scene}, {"pixels", pixels}, {"layouts", layoutsJson}});
    }
    return {{"format", kFormat},
            {"version", 1},
            {"octrace", b.octrace},
            {"render", toJson(b.render)},
            {"scenes", scenes}};
}

// now / baseline - 1; +inf when a zero baseline became positive.
double change(uint64_t baseline, uint64_t now) {
    if (baseline == 0) return now == 0 ? 0.0 : INFINITY;
    return double(now) / double(baseline) - 1.0;
}

// One frame's totals: the layout and backend that rendered it.
struct Measured {
    std::string layout, backend;
    CostTotals totals;
};

// Every layout's totals for one scene on each backend, in renderRegressionFrames' order.
std::vector<Measured> measure(const std::string& scene, const std::string& root,
                              const RegressionRender& render, const std::string& file,
                              const std::vector<const BackendDesc*>& backends) {
    std::vector<Measured> out;
    for (const TracedFrame& f :
         renderRegressionFrames(scene, root, render, false, file, backends)) {
        CostTotals t;
        t.pixels = f.film.pixelCount();
        for (size_t i = 0; i < f.film.pixelCount(); ++i) {
            t.nodes += f.film.nodes[i];
            t.prims += f.film.primsTested[i];
        }
        out.push_back({f.tracer, f.backend, t});
    }
    return out;
}

// Rows for one scene: what each backend measured, layout by layout, then stale baselines.
void judgeScene(const SceneBaselines& s, const std::vector<Measured>& measured, double tolerance,
                std::vector<CostRow>& rows) {
    for (const Measured& m : measured) {
        auto it = s.layouts.find(m.layout);
        rows.push_back(
            judgeCost(s.scene, m.layout,
                      it == s.layouts.end() ? std::nullopt : std::optional<CostTotals>(it->second),
                      m.totals, tolerance));
        rows.back().backend = m.backend;
    }
    for (const std::string& name : s.order) {
        bool known = false;
        for (const Measured& m : measured) known = known || m.layout == name;
        if (!known)
            rows.push_back(judgeCost(s.scene, name, s.layouts.at(name), std::nullopt, tolerance));
    }
}

}  // namespace

const char* costVerdictName(CostVerdict v) {
    switch (v) {
        case CostVerdict::Same:
            return "same";
        case CostVerdict::Within:
            return "within";
        case CostVerdict::Dropped:
            return "dropped";
        case CostVerdict::Increased:
            return "increased";
        case CostVerdict::Missing:
            return "missing";
        case CostVerdict::Stale:
            return "stale";
    }
    return "?";
}

CostRow judgeCost(std::string scene, std::string layout, std::optional<CostTotals> baseline,
                  std::optional<CostTotals> now, double tolerance) {
    CostRow r;
    r.scene = std::move(scene);
    r.layout = std::move(layout);
    r.baseline = baseline;
    r.now = now;
    if (!now) {
        r.verdict = CostVerdict::Stale;
        return r;
    }
    if (!baseline) {
        r.verdict = CostVerdict::Missing;
        return r;
    }
    // Means over different pixel counts are not comparable: a changed size is a missing
    // baseline (the file's render options were edited without --update).
    if (baseline->pixels != now->pixels) {
        r.verdict = CostVerdict::Missing;
        return r;
    }
    r.nodesChange = change(baseline->nodes, now->nodes);
    r.primsChange = change(baseline->prims, now->prims);
    // In counts, not ratios, so that +5 % exactly is within the tolerance (1.05e6 / 1e6 - 1 is
    // 0.05000000000000004 in double).
    auto above = [&](uint64_t base, uint64_t now) {
        return now > base && double(now - base) > tolerance * double(base);
    };
    auto below = [&](uint64_t base, uint64_t now) {
        return now<base&& double(base - now)> tolerance * double(base);
    };
    if (above(baseline->nodes, now->nodes) || above(baseline->prims, now->prims))
        r.verdict = CostVerdict::Increased;
    else if (below(baseline->nodes, now->nodes) || below(baseline->prims, now->prims))
        r.verdict = CostVerdict::Dropped;
    else if (baseline->nodes != now->nodes || baseline->prims != now->prims)
        r.verdict = CostVerdict::Within;
    else
        r.verdict = CostVerdict::Same;
    return r;
}

uint64_t CostReport::failures() const {
    if (updated) return 0;
    uint64_t n = 0;
    for (const CostRow& r : rows) n += r.passes() ? 0 : 1;
    return n;
}

namespace {

// The one skeleton of checking and updating: read the baselines, measure each scene with every
// layout, judge against the file, or rewrite it with the new totals (rows then compare them
// with the old ones).
CostReport runCostBaselines(const std::string& file, const std::string& root, RegressionMode mode,
                            double tolerance, const std::vector<const BackendDesc*>& backends) {
    const auto start = std::chrono::steady_clock::now();
    const bool update = mode == RegressionMode::Update;
    BaselineFile b = readBaselines(file);
    CostReport rep;
    rep.file = file;
    rep.baselineVersion = update ? octraceVersion() : b.octrace;
    rep.render = b.render;
    rep.tolerance = tolerance;
    rep.updated = update;
    for (SceneBaselines& s : b.scenes) {
        const std::vector<Measured> measured = measure(s.scene, root, b.render, file, backends);
        judgeScene(s, measured, tolerance, rep.rows);
        if (!update) continue;
        s.layouts.clear();
        s.order.clear();
        for (const Measured& m : measured) {  // update: the host backend alone
            s.layouts[m.layout] = m.totals;
            s.order.push_back(m.layout);
        }
    }
    if (update) {
        b.octrace = octraceVersion();
        const std::string text = baselinesJson(b).dump(2) + "\n";
        writeFileAtomic(file, text.data(), text.size());
    }
    rep.seconds = secondsSince(start);
    return rep;
}

}  // namespace

CostReport checkCostBaselines(const std::string& file, const std::string& root, double tolerance,
                              const std::vector<const BackendDesc*>& backends) {
    return runCostBaselines(file, root, RegressionMode::Check, tolerance, backends);
}

CostReport updateCostBaselines(const std::string& file, const std::string& root) {
    return runCostBaselines(file, root, RegressionMode::Update, kCostTolerance, {});
}

namespace {

json totalsJson(const std::optional<CostTotals>& t) {
    if (!t) return nullptr;
    return {{"nodes", t->nodes},
            {"prims", t->prims},
            {"nodes_per_pixel", t->nodesPerPixel()},
            {"prims_per_pixel", t->primsPerPixel()}};
}

std::string pct(double v) { return std::isfinite(v) ? fmt("%+.2f%%", 100.0 * v) : "+inf"; }

}  // namespace

json toJson(const CostReport& r) {
    json rows = json::array();
    for (const CostRow& x : r.rows)
        rows.push_back({{"scene", x.scene},
                        {"layout", x.layout},
                        {"backend", x.backend},
                        {"verdict", costVerdictName(x.verdict)},
                        {"pass", x.passes()},
                        {"baseline", totalsJson(x.baseline)},
                        {"now", totalsJson(x.now)},
                        {"nodes_change", num(x.nodesChange)},
                        {"prims_change", num(x.primsChange)}});
    return {{"pass", r.passes()},         {"file", r.file},
            {"updated", r.updated},       {"baseline_octrace", r.baselineVersion},
            {"render", toJson(r.render)}, {"tolerance", r.tolerance},
            {"failures", r.failures()},   {"rows", rows},
            {"seconds", r.seconds}};
}

std::string humanSummary(const CostReport& r) {
    std::map<CostVerdict, int> counts;
    for (const CostRow& x : r.rows) ++counts[x.verdict];
    std::string s =
        fmt("cost     %s: %zu scene x layout baselines (%dx%d)%s", r.file.c_str(), r.rows.size(),
            r.render.width, r.render.height, r.updated ? ", rewritten:" : ":");
    for (const auto& [v, n] : counts) s += fmt(" %d %s", n, costVerdictName(v));
    if (!r.updated)
        s += fmt("; rule: fail above %+.0f%%: %s", 100.0 * r.tolerance,
                 r.passes() ? "PASS" : "FAIL");
    s += fmt(" (%.2f s)\n", r.seconds);
    for (const CostRow& x : r.rows) {
        if (x.verdict == CostVerdict::Same) continue;
        std::string line = fmt("  %-28s %-10s %-7s %-9s", x.scene.c_str(), x.layout.c_str(),
                               x.backend.c_str(), costVerdictName(x.verdict));
        if (r.updated && x.verdict == CostVerdict::Missing && x.now)
            line = fmt("  %-28s %-10s new       nodes/px %.3f, prims/px %.3f", x.scene.c_str(),
                       x.layout.c_str(), x.now->nodesPerPixel(), x.now->primsPerPixel());
        else if (x.baseline && x.now && x.baseline->pixels == x.now->pixels)
            line += fmt(" nodes/px %.3f -> %.3f (%s), prims/px %.3f -> %.3f (%s)",
                        x.baseline->nodesPerPixel(), x.now->nodesPerPixel(),
                        pct(x.nodesChange).c_str(), x.baseline->primsPerPixel(),
                        x.now->primsPerPixel(), pct(x.primsChange).c_str());
        else if (x.verdict == CostVerdict::Missing)
            line += " no baseline for this layout at this size: rerun with --update";
        else if (x.verdict == CostVerdict::Stale)
            line += " this build has no such layout";
        s += line + "\n";
    }
    return s;
}

}  // namespace oct
