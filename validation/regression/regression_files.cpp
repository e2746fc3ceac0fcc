#include "validation/regression/regression_files.h"

#include <stdexcept>

#include "validation/report/report_util.h"

namespace oct {

using nlohmann::json;
using report_detail::fmt;

namespace {

// A regression file's outcome: `key` is its JSON field, null when it was not run.
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

RegressionReport runRegressionFiles(const std::string& goldenDir, const std::string& costFile,
                                    bool update, const std::string& root,
                                    const std::vector<const BackendDesc*>& backends) {
    if (update && goldenDir.empty() && costFile.empty())
        throw std::runtime_error("--update needs --golden DIR or --cost-baseline FILE to rewrite");
    RegressionReport r;
    std::vector<const BackendDesc*> present;
    for (const BackendDesc* b : backends) {
        if (!b->usesLayouts)
            throw std::runtime_error(std::string("--backend ") + b->name +
                                     ": the regression files check our kernel; " + b->name +
                                     " traces its own structure (it is the golden check's "
                                     "reference)");
        std::string why;
        if (b->available(why))
            present.push_back(b);
        else
            r.skipped.push_back({b->name, why});
    }
    if (!backends.empty() && present.empty()) return r;  // nothing can run: all skipped
    if (!goldenDir.empty())
        r.golden = update ? updateGolden(goldenDir, root)
                          : checkGolden(goldenDir, root, true, GoldenTolerance{}, present);
    if (!costFile.empty())
        r.cost = update ? updateCostBaselines(costFile, root)
                        : checkCostBaselines(costFile, root, kCostTolerance, present);
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
