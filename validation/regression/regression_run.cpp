#include "validation/regression/regression_run.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "backends/backend_list.h"
#include "core/io/output_file.h"
#include "core/octree/layout_registry.h"
#include "validation/rays/ray_manifest.h"
#include "validation/report/report_util.h"

namespace oct {

using nlohmann::json;
using report_detail::fmt;

namespace {

// A regression outcome: `key` is its JSON field, null when it was not run.
template <class Report>
CheckResult resultOf(const std::optional<Report>& r, const char* key, const char* failure) {
    if (!r) return notRun(key);
    CheckResult c;
    c.json = {{key, toJson(*r)}};
    c.pass = r->passes();
    c.summary = humanSummary(*r);
    if (!c.pass) c.failureText = fmt(failure, (unsigned long long)r->failures());
    return c;
}

// The backends to check: the list asked for, or the manifest's names; each of our kernel's
// (Embree is the reference), split into those that run here and those skipped.
std::vector<const BackendDesc*> presentBackends(const RegressionManifest& m,
                                                const std::vector<const BackendDesc*>& asked,
                                                std::vector<SkippedBackend>& skipped) {
    std::vector<const BackendDesc*> list = asked;
    if (list.empty())
        for (const std::string& name : m.backends) {
            const BackendDesc* b = findBackend(name);
            if (b)
                list.push_back(b);
            else
                skipped.push_back({name, "this build has no such backend (" + backendNames() +
                                             "), named by " + m.path});
        }
    std::vector<const BackendDesc*> present;
    for (const BackendDesc* b : list) {
        if (!b->usesLayouts)
            throw std::runtime_error(std::string("--backend ") + b->name +
                                     ": the regression set checks our kernel; " + b->name +
                                     " traces its own structure (it is the golden check's "
                                     "reference)");
        std::string why;
        if (b->available(why))
            present.push_back(b);
        else
            skipped.push_back({b->name, why});
    }
    return present;
}

const RegressionFrame* findFrame(const RegressionScene& s, const std::string& view) {
    for (const RegressionFrame& f : s.frames)
        if (f.view == view) return &f;
    return nullptr;
}

// What one scene's rendering is judged by: the manifest and the frames it rendered.
struct SceneRun {
    const RegressionManifest& m;
    const RegressionScene& s;
    std::string name;  // regressionEntryName
    RegressionRender render;
    std::vector<std::string> layouts, views;
    std::vector<TracedFrame> frames;
};

// One cost row of the scene's frame from `view`: `now` measured by `backend` (none: a baseline
// nothing measured, a layout or view the scene no longer lists, stale) against `baseline`.
void addCostRow(const SceneRun& run, const std::string& view, const std::string& layout,
                const std::string& backend, std::optional<CostTotals> baseline,
                std::optional<CostTotals> now, CostReport& cost) {
    cost.rows.push_back(judgeCost(run.s.scene, layout, baseline, now, cost.tolerance));
    cost.rows.back().view = view;
    cost.rows.back().entry = run.name;
    cost.rows.back().backend = backend;
    cost.rows.back().render = run.render;
}

// Check: each frame against the view's golden image (read once) and, for our kernel's frames,
// the view's cost baselines; then the stale baselines (a layout or view not rendered).
void checkScene(const SceneRun& run, GoldenReport& golden, CostReport& cost) {
    const std::string dir = run.m.dir();
    for (const RegressionFrame& f : run.s.frames)
        if (std::find(run.views.begin(), run.views.end(), f.view) == run.views.end())
            for (const auto& [layout, totals] : f.cost)
                addCostRow(run, f.view, layout, "", totals, std::nullopt, cost);
    for (const std::string& view : run.views) {
        const RegressionFrame* pinned = findFrame(run.s, view);
        std::vector<uint8_t> image;
        int w = 0, h = 0;
        if (pinned) image = readPngRgb((std::filesystem::path(dir) / pinned->image).string(), w, h);
        std::vector<std::string> rendered;
        for (const TracedFrame& f : run.frames) {
            if (f.view != view) continue;
            GoldenRow row;
            row.scene = run.s.scene;
            row.view = view;
            row.file = pinned ? pinned->image : regressionImageName(run.name, view);
            row.tracer = f.tracer;
            row.backend = f.backend;
            row.render = run.render;
            row.tolerance = run.m.goldenTolerance(f.backend);
            if (pinned) {
                golden.rows.push_back(judgeImage(std::move(row), f.film, w, h, image));
            } else {
                row.missing = true;
                row.diff.pixels = f.film.pixelCount();
                golden.rows.push_back(std::move(row));
            }
            if (!f.usesLayouts) continue;
            std::optional<CostTotals> base;
            if (pinned && pinned->cost.count(f.tracer)) base = pinned->cost.at(f.tracer);
            addCostRow(run, view, f.tracer, f.backend, base, frameCost(f.film), cost);
            rendered.push_back(f.tracer);
        }
        if (!pinned) continue;
        for (const auto& [layout, totals] : pinned->cost)
            if (std::find(rendered.begin(), rendered.end(), layout) == rendered.end())
                addCostRow(run, view, layout, "", totals, std::nullopt, cost);
    }
}

// Update / Add: the new frames of one scene, checked (every layout the same image; Embree
// within its rule against it), compared with what the manifest had, staged, and recorded.
std::vector<RegressionFrame> rewriteScene(const SceneRun& run, GoldenReport& golden,
                                          CostReport& cost, OutputSet& out) {
    const std::string dir = run.m.dir();
    std::vector<RegressionFrame> frames;
    for (const std::string& view : run.views) {
        const TracedFrame* first = nullptr;
        RegressionFrame nf;
        nf.view = view;
        const RegressionFrame* old = findFrame(run.s, view);
        nf.image = old ? old->image : regressionImageName(run.name, view);
        for (const TracedFrame& f : run.frames) {
            if (f.view != view) continue;
            if (!first) first = &f;
            // One comparison serves both rules: `differing` counts d > 0 whatever the channel.
            const GoldenTolerance rule = run.m.goldenTolerance(f.backend);
            const ImageDiff d = compareImages(first->film.width, first->film.height,
                                              first->film.rgb, f.film.rgb, rule.channel);
            if (f.usesLayouts && d.differing > 0)
                throw std::runtime_error(
                    fmt("%s, view %s: layouts %s and %s render different images (%llu pixels); "
                        "nothing was written: find out why before pinning an image",
                        run.s.scene.c_str(), view.c_str(), first->tracer.c_str(), f.tracer.c_str(),
                        (unsigned long long)d.differing));
            if (!f.usesLayouts && !rule.passes(d))
                throw std::runtime_error(fmt(
                    "%s, view %s: Embree's frame differs from the new image by more than its "
                    "rule (%llu pixels over %d/255); nothing was written: run octrace validate "
                    "on the scene to find the wrong pixels before pinning an image",
                    run.s.scene.c_str(), view.c_str(), (unsigned long long)d.over, rule.channel));
            if (!f.usesLayouts) continue;
            const CostTotals now = frameCost(f.film);
            nf.pixels = now.pixels;
            std::optional<CostTotals> before;
            if (old && old->cost.count(f.tracer)) before = old->cost.at(f.tracer);
            addCostRow(run, view, f.tracer, f.backend, before, now, cost);
            nf.cost[f.tracer] = now;
        }
        const std::string path = (std::filesystem::path(dir) / nf.image).string();
        GoldenRow row;
        row.scene = run.s.scene;
        row.view = view;
        row.file = nf.image;
        row.tracer = "all layouts";
        row.backend = first->backend;
        row.render = run.render;
        row.tolerance = run.m.goldenTolerance(first->backend);
        row.pass = true;
        std::error_code ec;
        if (old && std::filesystem::exists(path, ec)) {
            int w = 0, h = 0;
            const std::vector<uint8_t> before = readPngRgb(path, w, h);
            row.diff = compareImages(w, h, before, first->film.rgb, row.tolerance.channel);
            if (w != first->film.width || h != first->film.height) row.diff.sizeMismatch = true;
        } else {
            row.diff.sizeMismatch = true;  // no old image: everything is new
            row.diff.pixels = first->film.pixelCount();
        }
        golden.rows.push_back(std::move(row));
        out.stage(path, encodePng(path, first->film.width, first->film.height, first->film.rgb));
        frames.push_back(std::move(nf));
    }
    return frames;
}

// A new scene's entry: refused when listed already or when its settings name what does not
// exist; the scene is appended with no frames (rewriteScene fills them).
void appendScene(RegressionManifest& m, const RegressionAddition& add) {
    if (std::filesystem::path(add.scene).is_absolute())
        throw std::runtime_error("--regression-add " + add.scene +
                                 ": give the scene relative to the repository root, where "
                                 "validate --regression runs (the manifest is committed and "
                                 "read on other machines)");
    const std::string name = regressionEntryName(add.scene, add.name);
    if (!isPlainName(name))
        throw std::runtime_error("--regression-add " + add.scene + ": the entry's name '" + name +
                                 "' names its images, so it takes letters, digits, '.', '-', "
                                 "'_' and '+' only; give one with --regression-name");
    if (m.find(name))
        throw std::runtime_error("--regression-add " + add.scene + ": " + m.path + " lists " +
                                 name +
                                 " already; rerun with --update to re-render it, or add "
                                 "it under another --regression-name");
    for (const RegressionScene& s : m.scenes)
        for (const std::string& v : add.settings.views.value_or(*m.defaults.views))
            for (const RegressionFrame& f : s.frames)
                if (f.image == regressionImageName(name, v))
                    throw std::runtime_error("--regression-add " + add.scene + ": its image " +
                                             f.image + " is scene " + s.scene +
                                             "'s; add it under another --regression-name");
    m.scenes.push_back({add.scene, add.name, add.settings, {}});
}

}  // namespace

std::vector<CheckResult> RegressionReport::results() const {
    return {resultOf(golden, "golden", ", %llu golden image comparisons off"),
            resultOf(cost, "cost_baseline", ", %llu cost baselines exceeded or missing")};
}

std::string RegressionReport::failureText() const {
    std::string s;
    for (const CheckResult& c : results()) s += c.failureText;
    return s;
}

RegressionReport runRegression(const std::string& manifest, RegressionMode mode,
                               const std::string& root,
                               const std::vector<const BackendDesc*>& backends,
                               const RegressionAddition* addition) {
    const auto start = std::chrono::steady_clock::now();
    RegressionManifest m = readRegressionManifest(manifest);
    if (mode == RegressionMode::Add) {
        if (!addition) throw std::runtime_error("--regression-add needs a scene");
        appendScene(m, *addition);
    }
    RegressionReport r;
    const bool check = mode == RegressionMode::Check;
    std::vector<const BackendDesc*> present;
    if (check) {
        present = presentBackends(m, backends, r.skipped);
        if (present.empty()) return r;  // nothing can run: all skipped
    }
    GoldenReport golden;
    golden.manifest = manifest;
    golden.goldenVersion = check ? m.octrace : octraceVersion();
    golden.updated = !check;
    CostReport cost;
    cost.manifest = manifest;
    cost.baselineVersion = golden.goldenVersion;
    cost.tolerance = m.costTolerance;
    cost.updated = !check;
    OutputSet out;
    for (RegressionScene& s : m.scenes) {
        if (mode == RegressionMode::Add && &s != &m.scenes.back()) continue;
        SceneRun run{m,          s, regressionEntryName(s.scene, s.name), m.render(s), m.layouts(s),
                     m.views(s), {}};
        const Scene scene = loadRegressionScene(s.scene, root, run.render, manifest);
        run.frames =
            renderRegressionFrames(scene, run.render, run.views, run.layouts, true, present);
        if (check)
            checkScene(run, golden, cost);
        else
            s.frames = rewriteScene(run, golden, cost, out);
    }
    if (!check) {
        m.octrace = octraceVersion();
        const std::string text = toJson(m).dump(2) + "\n";
        out.stage(manifest, text.data(), text.size());
        out.commit();
    }
    golden.seconds = cost.seconds = secondsSince(start);
    r.golden = std::move(golden);
    r.cost = std::move(cost);
    return r;
}

void addToJson(json& report, const RegressionReport& r) {
    for (const CheckResult& c : r.results()) report.update(c.json);
    json skipped = json::array();
    for (const SkippedBackend& b : r.skipped)
        skipped.push_back({{"backend", b.name}, {"why", b.why}});
    report["skipped_backends"] = skipped;
    report["pass"] = report.value("pass", true) && r.passes() && r.skipped.empty();
}

std::string humanSummary(const RegressionReport& r) {
    std::string s;
    for (const CheckResult& c : r.results()) s += c.summary;
    for (const SkippedBackend& b : r.skipped)
        s += fmt("skipped  backend %s: %s (not run, so not a pass)\n", b.name.c_str(),
                 b.why.c_str());
    return s;
}

}  // namespace oct
