// Two certify runs compared ray by ray (certify --baseline OLD_PREFIX, docs/CERTIFY.md): the
// per-ray verdicts of an earlier run (its --verdicts files) against this run's, per set, so a
// team sees what a kernel change did. A row is worse when its class or its leak state got
// worse (agree and tie < ambiguous < unverified < wrong; sealed < unverified < leak), better
// when one got better and neither worse.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "validation/certify.h"
#include "validation/rays/verdict_files.h"

namespace oct {

struct RowChange {
    uint64_t row = 0;
    uint8_t oldClass = 0, newClass = 0;  // HitClass
    uint8_t oldLeak = 0, newLeak = 0;    // LeakState
};

struct SetChange {
    std::string set;
    uint64_t rows = 0, better = 0, worse = 0;
    std::vector<RowChange> firstWorse, firstBetter;  // by row, a few of each
};

struct BaselineComparison {
    std::string prefix;
    std::vector<SetChange> sets;
    uint64_t better = 0, worse = 0;
};

BaselineComparison compareWithBaseline(const RayCertification& now, const VerdictArrays& old,
                                       const std::string& prefix, int keep = 8);

nlohmann::json toJson(const BaselineComparison& c);
std::string humanSummary(const BaselineComparison& c);

}  // namespace oct
