#include "bench/sweep/ray_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <memory>
#include <stdexcept>

#include "bench/sweep/results.h"
#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/render/kernel.h"
#include "core/time_spread.h"

namespace oct {
namespace {

using json = nlohmann::ordered_json;

// The case as the table and the messages name it: "linear/cpu", "embree-bvh/embree".
std::string caseName(const RayBenchCase& c) { return c.structure() + "/" + c.backend->name; }

// A JSON key and a CSV column per reference: "ratio_to_" and the backend's name, '-' as '_'.
std::string ratioKey(const RayBenchCase& reference) {
    std::string key = std::string("ratio_to_") + reference.backend->name;
    for (char& ch : key)
        if (ch == '-') ch = '_';
    return key;
}

uint32_t floatBits(float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// The case every other is compared with: the first on an octree layout, as the octree
// layouts must agree exactly with each other; else the first of our layouts; else the first.
size_t comparedCase(const std::vector<RayBenchCase>& cases) {
    for (size_t i = 0; i < cases.size(); ++i)
        if (cases[i].layout && cases[i].layout->usesOctree) return i;
    for (size_t i = 0; i < cases.size(); ++i)
        if (cases[i].layout) return i;
    return 0;
}

// A build or preparation failure names its case; running out of memory stays bad_alloc, for
// the command line's advice.
template <class F>
auto namedStep(const std::string& what, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw std::runtime_error(what + ": " + e.what());
    }
}

}  // namespace

HitAgreement compareHits(const RayBenchCase& c, const RayBenchCase& with, uint64_t n) {
    HitAgreement a;
    for (uint64_t i = 0; i < n; ++i) {
        if (c.prim[i] != with.prim[i]) {
            ++a.otherPrim;
        } else if (floatBits(c.t[i]) != floatBits(with.t[i])) {
            ++a.otherT;
            const double ref = std::fabs(double(with.t[i]));
            if (ref > 0 && std::isfinite(ref))
                a.maxRelativeDt =
                    std::max(a.maxRelativeDt, std::fabs(double(c.t[i]) - double(with.t[i])) / ref);
        }
    }
    return a;
}

std::string RayBenchCase::structure() const { return layout ? layout->name : backend->structure; }

double RayBenchCase::buildSeconds() const {
    return layout ? treeSeconds + convertSeconds : prepareSeconds;
}

double RayBenchCase::uploadSeconds() const { return layout ? prepareSeconds : 0.0; }

void runRayBench(const Scene& scene, const float* rays, const RayBenchOptions& o,
                 RayBenchResult& r) {
    r.primitives = scene.primitiveCount();
    std::vector<const BackendDesc*> ours, references;
    for (const BackendDesc* b : o.backends) (b->usesLayouts ? ours : references).push_back(b);

    // The structures, which the tracers below must not outlive: one canonical octree for every
    // layout (as bench's sweep builds it), one conversion per layout, the bare scene for Embree.
    std::shared_ptr<const Octree> tree;
    bool needTree = false;
    for (const LayoutDesc* l : o.layouts) needTree = needTree || l->usesOctree;
    if (needTree && !ours.empty())
        tree = namedStep("building the octree",
                         [&] { return buildSharedOctree(scene, o.layout.build); });
    std::deque<BuiltScene> built;
    if (!ours.empty())
        for (const LayoutDesc* l : o.layouts)
            built.push_back(namedStep(std::string("converting to the ") + l->name + " layout",
                                      [&] { return convertLayout(scene, tree, *l, o.layout); }));
    const BuiltScene bare = bareScene(scene);

    // Cases: each layout on each of our backends, then each backend with its own structure.
    std::vector<std::unique_ptr<SceneTracer>> tracers;
    auto addCase = [&](const BuiltScene& bs, const LayoutDesc* layout, const BackendDesc& b) {
        RayBenchCase c;
        c.layout = layout;
        c.backend = &b;
        if (layout && layout->usesOctree) c.treeSeconds = tree->buildSeconds;
        if (layout) c.convertSeconds = bs.convertSeconds;
        c.layoutBytes = layout ? bs.layoutBytes() : 0;
        c.t.resize(r.rays);
        c.prim.resize(r.rays);
        tracers.push_back(namedStep("preparing " + caseName(c), [&] { return b.prepare(bs); }));
        c.prepareSeconds = tracers.back()->prepareSeconds();
        r.cases.push_back(std::move(c));
    };
    for (size_t i = 0; i < built.size(); ++i)
        for (const BackendDesc* b : ours) addCase(built[i], o.layouts[i], *b);
    for (const BackendDesc* b : references) {
        r.references.push_back(r.cases.size());
        addCase(bare, nullptr, *b);
    }

    // Interleaved rounds, each starting one case later than the one before, so no case is
    // always the first after a pause or the one after the slowest.
    const size_t n = r.cases.size();
    const int rounds = o.warmup + o.repeats;
    for (int round = 0; round < rounds; ++round) {
        const auto t0 = std::chrono::steady_clock::now();
        for (size_t k = 0; k < n; ++k) {
            const size_t i = (k + size_t(round)) % n;
            RayBenchCase& c = r.cases[i];
            const double s = tracers[i]->trace({rays, c.t.data(), c.prim.data(), r.rays});
            if (round >= o.warmup) c.traceSeconds.push_back(s);
        }
        if (o.progress)
            std::fprintf(stderr, "bench: round %d of %d%s: %zu cases in %.2f s\n", round + 1,
                         rounds, round < o.warmup ? " (warm-up)" : "", n, secondsSince(t0));
    }

    r.compared = comparedCase(r.cases);
    for (RayBenchCase& c : r.cases) {
        for (uint64_t i = 0; i < r.rays; ++i) c.hits += c.prim[i] >= 0;
        c.agreement = compareHits(c, r.cases[r.compared], r.rays);
    }
}

double medianTraceSeconds(const RayBenchCase& c) { return timeSpread(c.traceSeconds).median; }

double mraysPerSecond(const RayBenchResult& r, const RayBenchCase& c) {
    const double s = medianTraceSeconds(c);
    return s > 0 ? double(r.rays) / s * 1e-6 : 0.0;
}

double outsideSeconds(const RayBenchResult& r, const RayBenchCase& c) {
    return r.readSeconds + r.loadSeconds + c.buildSeconds() + c.uploadSeconds();
}

std::vector<const RayBenchCase*> disagreeingCases(const RayBenchResult& r) {
    std::vector<const RayBenchCase*> out;
    if (r.cases.empty()) return out;
    const RayBenchCase& with = r.cases[r.compared];
    for (const RayBenchCase& c : r.cases)
        if (c.layout && c.backend == with.backend && !c.agreement.exact()) out.push_back(&c);
    return out;
}

namespace {

// A ratio of medians, or null when the reference's median is 0 (a clock too coarse).
json ratioJson(const RayBenchCase& c, const RayBenchCase& reference) {
    const double ref = medianTraceSeconds(reference);
    return ref > 0 ? json(medianTraceSeconds(c) / ref) : json(nullptr);
}

json caseJson(const RayBenchResult& r, const RayBenchCase& c) {
    const TimeSpread s = timeSpread(c.traceSeconds);
    json row = {
        {"layout", c.structure()}, {"backend", c.backend->name},         {"rays", r.rays},
        {"hits", c.hits},          {"trace_s_median", s.median},         {"trace_s_min", s.min},
        {"trace_s_max", s.max},    {"mrays_per_s", mraysPerSecond(r, c)}};
    for (size_t ref : r.references) row[ratioKey(r.cases[ref])] = ratioJson(c, r.cases[ref]);
    row["tree_build_s"] = c.treeSeconds;
    row["convert_s"] = c.convertSeconds;
    row["build_s"] = c.buildSeconds();
    row["upload_s"] = c.uploadSeconds();
    row["outside_s"] = outsideSeconds(r, c);
    row["layout_bytes"] = c.layoutBytes;
    row["other_prim"] = c.agreement.otherPrim;
    row["other_t"] = c.agreement.otherT;
    row["max_relative_dt"] = c.agreement.maxRelativeDt;
    row["trace_s"] = c.traceSeconds;  // JSON only: the CSV keeps scalars
    return row;
}

// The rows' scalar fields as columns (the per-round times, an array, stay in the JSON).
std::string rayBenchCsv(const json& rows) {
    if (rows.empty()) return "";
    std::vector<std::string> keys;
    for (const auto& field : rows[0].items())
        if (!field.value().is_array()) keys.push_back(field.key());
    return csvTable(keys, rows);
}

}  // namespace

std::string rayBenchTable(const RayBenchResult& r) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-16s %-12s %10s %9s %8s", "layout", "backend", "rays",
                  "trace s", "Mrays/s");
    out += line;
    // A ratio column per reference, as wide as its heading ("x embree-fast").
    std::vector<int> widths;
    for (size_t ref : r.references) {
        const std::string heading = "x " + std::string(r.cases[ref].backend->name);
        widths.push_back(std::max(8, int(heading.size())));
        std::snprintf(line, sizeof line, " %*s", widths.back(), heading.c_str());
        out += line;
    }
    std::snprintf(line, sizeof line, " %8s %9s %10s %8s %8s\n", "build s", "outside s", "hits",
                  "other p", "other t");
    out += line;
    for (size_t i = 0; i < r.cases.size(); ++i) {
        const RayBenchCase& c = r.cases[i];
        std::snprintf(line, sizeof line, "%-16s %-12s %10llu %9.4f %8.2f", c.structure().c_str(),
                      c.backend->name, (unsigned long long)r.rays, medianTraceSeconds(c),
                      mraysPerSecond(r, c));
        out += line;
        for (size_t k = 0; k < r.references.size(); ++k) {
            const json ratio = ratioJson(c, r.cases[r.references[k]]);
            if (ratio.is_null())
                std::snprintf(line, sizeof line, " %*s", widths[k], "-");
            else
                std::snprintf(line, sizeof line, " %*.2fx", widths[k] - 1, ratio.get<double>());
            out += line;
        }
        if (i == r.compared)
            std::snprintf(line, sizeof line, " %8.3f %9.3f %10llu %17s\n", c.buildSeconds(),
                          outsideSeconds(r, c), (unsigned long long)c.hits, "(compared with)");
        else
            std::snprintf(line, sizeof line, " %8.3f %9.3f %10llu %8llu %8llu\n", c.buildSeconds(),
                          outsideSeconds(r, c), (unsigned long long)c.hits,
                          (unsigned long long)c.agreement.otherPrim,
                          (unsigned long long)c.agreement.otherT);
        out += line;
    }
    return out;
}

json rayBenchJson(const RayBenchResult& r, const json& machine, const json& config) {
    json rows = json::array();
    for (const RayBenchCase& c : r.cases) rows.push_back(caseJson(r, c));
    json compared = nullptr;
    if (!r.cases.empty())
        compared = {{"layout", r.cases[r.compared].structure()},
                    {"backend", r.cases[r.compared].backend->name}};
    return {{"format", "octrace-rays-bench/1"},
            {"machine", machine},
            {"config", config},
            {"rays", r.rays},
            {"primitives", r.primitives},
            {"read_s", r.readSeconds},
            {"load_s", r.loadSeconds},
            {"compared_with", compared},
            {"results", rows}};
}

void writeRayBench(const std::filesystem::path& dir, const RayBenchResult& r, const json& machine,
                   const json& config) {
    const json doc = rayBenchJson(r, machine, config);
    const std::string text = doc.dump(2) + "\n", csv = rayBenchCsv(doc["results"]);
    OutputSet out;  // both files or neither
    out.stage((dir / "rays-bench.json").string(), text.data(), text.size());
    out.stage((dir / "rays-bench.csv").string(), csv.data(), csv.size());
    out.commit();
}

}  // namespace oct
