#include "validation/regression/regression_files.h"

#include <stdexcept>

#include "validation/report/report_util.h"

namespace oct {

using nlohmann::json;
using report_detail::fmt;

std::string RegressionReport::failureText() const {
    std::string s;
    if (golden && !golden->passes())
        s += fmt(", %llu golden image comparisons off", (unsigned long long)golden->failures());
    if (cost && !cost->passes())
        s += fmt(", %llu cost baselines exceeded or missing", (unsigned long long)cost->failures());
    return s;
}

RegressionReport runRegressionFiles(const std::string& goldenDir, const std::string& costFile,
                                    bool update, const std::string& root) {
    if (update && goldenDir.empty() && costFile.empty())
        throw std::runtime_error("--update needs --golden DIR or --cost-baseline FILE to rewrite");
    RegressionReport r;
    if (!goldenDir.empty())
        r.golden = update ? updateGolden(goldenDir, root) : checkGolden(goldenDir, root);
    if (!costFile.empty())
        r.cost = update ? updateCostBaselines(costFile, root) : checkCostBaselines(costFile, root);
    return r;
}

void addToJson(json& report, const RegressionReport& r) {
    report["golden"] = r.golden ? toJson(*r.golden) : json(nullptr);
    report["cost_baseline"] = r.cost ? toJson(*r.cost) : json(nullptr);
    report["pass"] = report.value("pass", true) && r.passes();
}

std::string humanSummary(const RegressionReport& r) {
    return (r.golden ? humanSummary(*r.golden) : std::string()) +
           (r.cost ? humanSummary(*r.cost) : std::string());
}

}  // namespace oct
