#include "bench/sweep/baseline.h"

#include <algorithm>
#include <cmath>

#include "backends/backend_list.h"
#include "core/io/input_file.h"
#include "core/io/output_file.h"

namespace oct {
namespace {

using json = nlohmann::ordered_json;

// A baseline is a few hundred cases of a few numbers: more than this is not one, refused unread.
constexpr uint64_t kMaxBaselineBytes = uint64_t(16) << 20;
const char* const kRemake = "make it with octrace bench --baseline FILE --update";

[[noreturn]] void badField(const std::string& file, const char* name, bool missing) {
    throw IoError(file + ": " + (missing ? "missing field '" : "field '") + name +
                  (missing ? "'" : "' has the wrong type") + "; restore it from git or " + kRemake);
}

template <class T>
T field(const json& j, const char* name, const std::string& file) {
    if (!j.is_object() || !j.contains(name)) badField(file, name, true);
    try {
        return j.at(name).get<T>();
    } catch (const json::exception&) {
        badField(file, name, false);
    }
}

json parseBaselineText(const std::string& path) {
    const std::string text = readSmallInput(path, "the bench baseline", kMaxBaselineBytes,
                                            std::string("give an existing one, or ") + kRemake);
    try {
        return json::parse(text);
    } catch (const json::exception& e) {
        throw IoError(path + ": not valid JSON (" + e.what() + "); restore it from git or " +
                      kRemake);
    }
}

void checkFormat(const json& j, const std::string& path) {
    const json format = j.is_object() && j.contains("format") ? j["format"] : json(nullptr);
    const json version = j.is_object() && j.contains("version") ? j["version"] : json(nullptr);
    if (format != kBaselineFormat || version != kBaselineVersion)
        throw IoError(path + ": not an " + kBaselineFormat + " version " +
                      std::to_string(kBaselineVersion) + " file (format " + format.dump() +
                      ", version " + version.dump() + "); " + kRemake);
}

BaselineCase caseFromJson(const json& c, const std::string& path) {
    BaselineCase b;
    b.scene = field<std::string>(c, "scene", path);
    b.layout = field<std::string>(c, "layout", path);
    b.backend = field<std::string>(c, "backend", path);
    b.ratioToEmbree = field<double>(c, "ratio_to_embree", path);
    b.nodesPerPixel = field<double>(c, "nodes_per_pixel", path);
    b.primsPerPixel = field<double>(c, "prims_per_pixel", path);
    if (!(b.ratioToEmbree > 0) || !std::isfinite(b.ratioToEmbree) || !(b.nodesPerPixel >= 0) ||
        !(b.primsPerPixel >= 0))
        throw IoError(path + ": case " + b.scene + " " + b.layout + " " + b.backend +
                      ": ratio_to_embree must be positive and the counts not negative; " + kRemake);
    return b;
}

bool sameCase(const BaselineCase& a, const std::string& scene, const std::string& layout,
              const std::string& backend) {
    return a.scene == scene && a.layout == layout && a.backend == backend;
}

bool tracesOurLayouts(const std::string& backend) {
    const BackendDesc* b = findBackend(backend);
    return b && b->usesLayouts;
}

// A count grew (or fell) by more than the tolerance: against stored x (1 +- tolerance), so that
// +5 % exactly is within it (now / stored - 1 may round above 0.05).
bool grew(double stored, double now, double tolerance) { return now > stored * (1.0 + tolerance); }
bool fell(double stored, double now, double tolerance) { return now < stored * (1.0 - tolerance); }

double relativeChange(double stored, double now) {
    if (stored == 0) return now == 0 ? 0.0 : INFINITY;
    return now / stored - 1.0;
}

void judgeMeasured(const BaselineRule& rule, CaseComparison& c) {
    const BaselineCase& s = *c.stored;
    const BaselineCase& n = *c.now;
    c.timeFactor = n.ratioToEmbree / s.ratioToEmbree;
    if (c.timeFactor > rule.timeFactor)
        c.time = Change::Worse;
    else if (c.timeFactor < 1.0 / rule.timeFactor)
        c.time = Change::Better;
    c.nodesChange = relativeChange(s.nodesPerPixel, n.nodesPerPixel);
    c.primsChange = relativeChange(s.primsPerPixel, n.primsPerPixel);
    const double tol = rule.countTolerance;
    if (grew(s.nodesPerPixel, n.nodesPerPixel, tol) || grew(s.primsPerPixel, n.primsPerPixel, tol))
        c.counts = Change::Worse;
    else if (fell(s.nodesPerPixel, n.nodesPerPixel, tol) ||
             fell(s.primsPerPixel, n.primsPerPixel, tol))
        c.counts = Change::Better;
}

// A stored case that was not measured: why, from what stopped it or from its row.
void judgeUnmeasured(const std::vector<Row>& rows, const NotRun& notRun, CaseComparison& c) {
    auto scene = notRun.scenes.find(c.scene);
    auto backend = notRun.backends.find(c.backend);
    if (scene != notRun.scenes.end() || backend != notRun.backends.end()) {
        c.outcome = CaseOutcome::Skipped;
        c.why = scene != notRun.scenes.end() ? scene->second : backend->second;
        return;
    }
    for (const Row& r : rows) {
        const bool itsRow = r.scene == c.scene && r.layout == c.layout && r.backend == c.backend;
        const bool sceneFailed = r.scene == c.scene && r.status == "error" && r.layout == "-";
        if (!itsRow && !sceneFailed) continue;
        c.outcome = r.status == "error" ? CaseOutcome::Error : CaseOutcome::Skipped;
        c.why = r.reason;
        return;
    }
    c.outcome = CaseOutcome::Stale;
}

std::string pct(double change) {
    if (std::isinf(change)) return "+inf";
    return fmt("%+.1f%%", 100.0 * change);
}

std::string verdictText(const CaseComparison& c) {
    switch (c.outcome) {
        case CaseOutcome::Missing:
            return "FAIL missing: not in the file (--update adds it)";
        case CaseOutcome::Stale:
            return "stale: in the file, not run";
        case CaseOutcome::Skipped:
            return "SKIPPED: " + c.why;
        case CaseOutcome::Error:
            return "FAIL error: " + c.why;
        case CaseOutcome::Compared:
            break;
    }
    std::string s;
    auto add = [&](const std::string& part) { s += (s.empty() ? "" : "; ") + part; };
    if (c.time == Change::Worse) add("FAIL time x" + fmt("%.2f", c.timeFactor));
    if (c.counts == Change::Worse)
        add("FAIL counts: nodes " + pct(c.nodesChange) + ", prims " + pct(c.primsChange));
    if (c.time == Change::Better) add("faster x" + fmt("%.2f", c.timeFactor) + " (--update?)");
    if (c.counts == Change::Better)
        add("fewer: nodes " + pct(c.nodesChange) + ", prims " + pct(c.primsChange) +
            " (--update?)");
    return s.empty() ? "ok" : s;
}

CaseComparison caseNamed(const std::string& scene, const std::string& layout,
                         const std::string& backend, CaseOutcome outcome) {
    CaseComparison c;
    c.scene = scene;
    c.layout = layout;
    c.backend = backend;
    c.outcome = outcome;
    return c;
}

// Failures first, then skipped cases, then the rest, each group in the file's order.
int rank(const CaseComparison& c) {
    if (c.fails()) return 0;
    return c.outcome == CaseOutcome::Skipped ? 1 : 2;
}

}  // namespace

const std::vector<std::string>& baselineMatchedOptions() {
    static const std::vector<std::string> keys = {
        "size",      "warmup",    "repeats",         "threads",   "seed",
        "max_depth", "max_prims", "cloud_max_prims", "hash_slots"};
    return keys;
}

BaselineFile readBaseline(const std::string& path) {
    const json j = parseBaselineText(path);
    checkFormat(j, path);
    BaselineFile b;
    b.octrace = field<std::string>(j, "octrace", path);
    b.machine = field<json>(j, "machine", path);
    b.options = field<json>(j, "options", path);
    for (const std::string& key : baselineMatchedOptions())
        if (!b.options.is_object() || !b.options.contains(key))
            throw IoError(path + ": options lack '" + key + "'; " + kRemake);
    const json cases = field<json>(j, "cases", path);
    if (!cases.is_array()) badField(path, "cases", false);
    for (const json& c : cases) b.cases.push_back(caseFromJson(c, path));
    return b;
}

json baselineJson(const BaselineFile& b) {
    json cases = json::array();
    for (const BaselineCase& c : b.cases)
        cases.push_back({{"scene", c.scene},
                         {"layout", c.layout},
                         {"backend", c.backend},
                         {"ratio_to_embree", c.ratioToEmbree},
                         {"nodes_per_pixel", c.nodesPerPixel},
                         {"prims_per_pixel", c.primsPerPixel}});
    return {{"format", kBaselineFormat}, {"version", kBaselineVersion}, {"octrace", b.octrace},
            {"machine", b.machine},      {"options", b.options},        {"cases", cases}};
}

void writeBaseline(const std::string& path, const BaselineFile& b) {
    const std::string text = baselineJson(b).dump(2) + "\n";
    writeFileAtomic(path, text.data(), text.size());
}

std::vector<BaselineCase> baselineCases(const std::vector<Row>& rows) {
    std::vector<BaselineCase> out;
    for (const Row& r : rows) {
        if (r.status != "ok" || !tracesOurLayouts(r.backend) || !r.ratioToEmbree) continue;
        out.push_back({r.scene, r.layout, r.backend, *r.ratioToEmbree,
                       r.nodesPerPixel.value_or(0.0), r.primsPerPixel.value_or(0.0)});
    }
    return out;
}

std::string optionMismatch(const json& stored, const json& run, const std::string& file) {
    auto shown = [](const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
    for (const std::string& key : baselineMatchedOptions()) {
        const json a = stored.contains(key) ? stored[key] : json(nullptr);
        const json b = run.contains(key) ? run[key] : json(nullptr);
        if (a == b) continue;
        std::string flag = "--" + key;
        std::replace(flag.begin(), flag.end(), '_', '-');
        return flag + " " + shown(b) + ", but " + file + " was made with " + flag + " " + shown(a);
    }
    return "";
}

size_t BaselineReport::count(CaseOutcome o) const {
    return size_t(std::count_if(cases.begin(), cases.end(),
                                [o](const CaseComparison& c) { return c.outcome == o; }));
}

size_t BaselineReport::slower() const {
    return size_t(std::count_if(cases.begin(), cases.end(),
                                [](const CaseComparison& c) { return c.time == Change::Worse; }));
}

size_t BaselineReport::costlier() const {
    return size_t(std::count_if(cases.begin(), cases.end(),
                                [](const CaseComparison& c) { return c.counts == Change::Worse; }));
}

bool BaselineReport::fails() const {
    return std::any_of(cases.begin(), cases.end(),
                       [](const CaseComparison& c) { return c.fails(); });
}

bool BaselineReport::incomplete() const {
    return !fails() &&
           (count(CaseOutcome::Skipped) > 0 || !notRun.scenes.empty() || !notRun.backends.empty());
}

std::string BaselineReport::failureText() const {
    std::string s;
    auto add = [&](size_t n, const std::string& what) {
        if (n) s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(slower(), "slower (time: ratio to Embree above x" + fmt("%.2f", rule.timeFactor) + ")");
    add(costlier(),
        "costlier (counts: nodes or prims per pixel above " + pct(rule.countTolerance) + ")");
    add(count(CaseOutcome::Missing), "missing from the file");
    add(count(CaseOutcome::Error), "errors");
    return s;
}

BaselineReport compareBaseline(const std::string& file, const std::vector<BaselineCase>& stored,
                               const std::vector<Row>& rows, const NotRun& notRun,
                               const BaselineRule& rule) {
    BaselineReport rep;
    rep.file = file;
    rep.rule = rule;
    rep.notRun = notRun;
    const std::vector<BaselineCase> measured = baselineCases(rows);
    for (const BaselineCase& s : stored) {
        CaseComparison c = caseNamed(s.scene, s.layout, s.backend, CaseOutcome::Compared);
        c.stored = s;
        auto it = std::find_if(measured.begin(), measured.end(), [&](const BaselineCase& m) {
            return sameCase(m, s.scene, s.layout, s.backend);
        });
        if (it != measured.end()) {
            c.now = *it;
            judgeMeasured(rule, c);
        } else {
            judgeUnmeasured(rows, notRun, c);
        }
        rep.cases.push_back(std::move(c));
    }
    for (const BaselineCase& m : measured) {
        const bool known = std::any_of(stored.begin(), stored.end(), [&](const BaselineCase& s) {
            return sameCase(s, m.scene, m.layout, m.backend);
        });
        if (known) continue;
        CaseComparison c = caseNamed(m.scene, m.layout, m.backend, CaseOutcome::Missing);
        c.now = m;
        rep.cases.push_back(std::move(c));
    }
    // A row of ours that failed and that the file does not know fails too.
    for (const Row& r : rows) {
        if (r.status != "error" || !tracesOurLayouts(r.backend)) continue;
        const bool known = std::any_of(stored.begin(), stored.end(), [&](const BaselineCase& s) {
            return sameCase(s, r.scene, r.layout, r.backend);
        });
        if (known) continue;
        CaseComparison c = caseNamed(r.scene, r.layout, r.backend, CaseOutcome::Error);
        c.why = r.reason;
        rep.cases.push_back(std::move(c));
    }
    std::stable_sort(
        rep.cases.begin(), rep.cases.end(),
        [](const CaseComparison& a, const CaseComparison& b) { return rank(a) < rank(b); });
    return rep;
}

std::string humanSummary(const BaselineReport& r) {
    auto num = [](const std::optional<BaselineCase>& c, double BaselineCase::*f, const char* form) {
        return c ? fmt(form, (*c).*f) : std::string("-");
    };
    std::string s = "baseline " + r.file + ": time = frame / Embree's frame (fails above x" +
                    fmt("%.2f", r.rule.timeFactor) + "), counts = boxes and prims per pixel " +
                    "(fail above " + pct(r.rule.countTolerance) + ")\n";
    char line[512];
    std::snprintf(line, sizeof line, "%-18s %-10s %-6s %7s %7s %6s %8s %8s %8s %8s  %s\n", "scene",
                  "layout", "back", "x_embr", "was", "change", "boxes/px", "was", "prims/px", "was",
                  "verdict");
    s += line;
    for (const CaseComparison& c : r.cases) {
        const std::string change =
            c.stored && c.now ? "x" + fmt("%.2f", c.timeFactor) : std::string("-");
        std::snprintf(line, sizeof line, "%-18s %-10s %-6s %7s %7s %6s %8s %8s %8s %8s  %s\n",
                      c.scene.substr(0, 18).c_str(), c.layout.c_str(), c.backend.c_str(),
                      num(c.now, &BaselineCase::ratioToEmbree, "%.3f").c_str(),
                      num(c.stored, &BaselineCase::ratioToEmbree, "%.3f").c_str(), change.c_str(),
                      num(c.now, &BaselineCase::nodesPerPixel, "%.2f").c_str(),
                      num(c.stored, &BaselineCase::nodesPerPixel, "%.2f").c_str(),
                      num(c.now, &BaselineCase::primsPerPixel, "%.2f").c_str(),
                      num(c.stored, &BaselineCase::primsPerPixel, "%.2f").c_str(),
                      verdictText(c).c_str());
        s += line;
    }
    for (const auto& [scene, why] : r.notRun.scenes) s += "not run: " + scene + ": " + why + "\n";
    for (const auto& [backend, why] : r.notRun.backends)
        s += "not run: " + backend + ": " + why + "\n";
    const size_t compared = r.count(CaseOutcome::Compared);
    s += std::to_string(r.cases.size()) + " cases: " + std::to_string(compared) + " compared (" +
         std::to_string(r.slower()) + " slower, " + std::to_string(r.costlier()) + " costlier), " +
         std::to_string(r.count(CaseOutcome::Missing)) + " missing, " +
         std::to_string(r.count(CaseOutcome::Skipped)) + " skipped, " +
         std::to_string(r.count(CaseOutcome::Stale)) + " stale, " +
         std::to_string(r.count(CaseOutcome::Error)) + " errors\n";
    return s;
}

}  // namespace oct
