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

// now / baseline - 1; +inf when a zero baseline became positive.
double change(uint64_t baseline, uint64_t now) {
    if (baseline == 0) return now == 0 ? 0.0 : INFINITY;
    return double(now) / double(baseline) - 1.0;
}

}  // namespace

CostTotals frameCost(const Film& film) {
    CostTotals t;
    t.pixels = film.pixelCount();
    for (size_t i = 0; i < film.pixelCount(); ++i) {
        t.nodes += film.nodes[i];
        t.prims += film.primsTested[i];
    }
    return t;
}

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

json totalsJson(const std::optional<CostTotals>& t) {
    if (!t) return nullptr;
    return {{"boxes_tested", t->nodes},
            {"prims_tested", t->prims},
            {"boxes_per_pixel", t->nodesPerPixel()},
            {"prims_per_pixel", t->primsPerPixel()}};
}

std::string pct(double v) { return std::isfinite(v) ? fmt("%+.2f%%", 100.0 * v) : "+inf"; }

}  // namespace

json toJson(const CostReport& r) {
    json rows = json::array();
    for (const CostRow& x : r.rows)
        rows.push_back({{"scene", x.scene},
                        {"entry", x.entry},
                        {"view", x.view},
                        {"render", toJson(x.render)},
                        {"layout", x.layout},
                        {"backend", x.backend},
                        {"verdict", costVerdictName(x.verdict)},
                        {"pass", x.passes()},
                        {"baseline", totalsJson(x.baseline)},
                        {"now", totalsJson(x.now)},
                        {"boxes_change", num(x.nodesChange)},
                        {"prims_change", num(x.primsChange)}});
    return {{"pass", r.passes()},
            {"manifest", r.manifest},
            {"updated", r.updated},
            {"baseline_octrace", r.baselineVersion},
            {"tolerance", r.tolerance},
            {"failures", r.failures()},
            {"rows", rows},
            {"seconds", r.seconds}};
}

std::string humanSummary(const CostReport& r) {
    std::map<CostVerdict, int> counts;
    for (const CostRow& x : r.rows) ++counts[x.verdict];
    std::string s = fmt("cost     %s: %zu frame x layout baselines%s", r.manifest.c_str(),
                        r.rows.size(), r.updated ? ", rewritten:" : ":");
    for (const auto& [v, n] : counts) s += fmt(" %d %s", n, costVerdictName(v));
    if (!r.updated)
        s += fmt("; rule: fail above %+.0f%%: %s", 100.0 * r.tolerance,
                 r.passes() ? "PASS" : "FAIL");
    s += fmt(" (%.2f s)\n", r.seconds);
    for (const CostRow& x : r.rows) {
        if (x.verdict == CostVerdict::Same) continue;
        const std::string frame =
            (x.entry.empty() ? x.scene : x.entry) + (x.view == "default" ? "" : " " + x.view);
        std::string line = fmt("  %-28s %-10s %-7s %-9s", frame.c_str(), x.layout.c_str(),
                               x.backend.c_str(), costVerdictName(x.verdict));
        if (r.updated && x.verdict == CostVerdict::Missing && x.now)
            line = fmt("  %-28s %-10s new       boxes/px %.3f, prims/px %.3f", frame.c_str(),
                       x.layout.c_str(), x.now->nodesPerPixel(), x.now->primsPerPixel());
        else if (x.baseline && x.now && x.baseline->pixels == x.now->pixels)
            line += fmt(" boxes/px %.3f -> %.3f (%s), prims/px %.3f -> %.3f (%s)",
                        x.baseline->nodesPerPixel(), x.now->nodesPerPixel(),
                        pct(x.nodesChange).c_str(), x.baseline->primsPerPixel(),
                        x.now->primsPerPixel(), pct(x.primsChange).c_str());
        else if (x.verdict == CostVerdict::Missing)
            line += " no baseline for this layout at this size: rerun with --update";
        else if (x.verdict == CostVerdict::Stale)
            line += " this build has no such layout, or the scene no longer lists it";
        s += line + "\n";
    }
    return s;
}

}  // namespace oct
