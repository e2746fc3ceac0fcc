// One check's outcome in the forms its report takes: the verdict, a block of the human summary,
// fields of the JSON report and a clause of the failure message. validate's checks
// (validation/checks/check.h) and the regression files give one each; the reports and the
// failure message only iterate them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace oct {

struct CheckResult {
    bool ran = true;  // false: left out by the options or the inputs (its fields are null)
    bool pass = true;
    bool complete = true;  // false: work a recheck cap left unverified (nothing wrong in it)
    std::string summary;   // its block of the human summary
    nlohmann::json json = nlohmann::json::object();  // its fields of the JSON report object
    std::string failureText;  // ", 3 replication false negatives" when it fails, else ""
    std::string verdict;      // its words in the summary's closing line, e.g. ", replication ok"
};

// A check left out: it passes, says nothing, and its JSON field `field` is null.
inline CheckResult notRun(const char* field) {
    CheckResult r;
    r.ran = false;
    r.json = {{field, nullptr}};
    return r;
}

}  // namespace oct
