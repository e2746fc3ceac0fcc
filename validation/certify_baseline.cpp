#include "validation/certify_baseline.h"

#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using report_detail::fmt;

int classRank(uint8_t c) {
    switch (HitClass(c)) {
        case HitClass::Agree:
        case HitClass::Tie:
            return 0;
        case HitClass::Ambiguous:
            return 1;
        case HitClass::Unverified:
            return 2;
        case HitClass::Wrong:
            return 3;
    }
    return 3;
}

int leakRank(uint8_t l) {
    switch (LeakState(l)) {
        case LeakState::Leak:
            return 2;
        case LeakState::Unverified:
            return 1;
        default:
            return 0;
    }
}

const char* leakName(uint8_t l) {
    switch (LeakState(l)) {
        case LeakState::Sealed:
            return "sealed";
        case LeakState::Leak:
            return "leak";
        case LeakState::NotTarget:
            return "-";
        case LeakState::Unsealed:
            return "unsealed";
        case LeakState::Unverified:
            return "unverified";
    }
    return "?";
}

json rowJson(const RowChange& r) {
    return {{"row", r.row},
            {"class", {hitClassName(HitClass(r.oldClass)), hitClassName(HitClass(r.newClass))}},
            {"leak", {leakName(r.oldLeak), leakName(r.newLeak)}}};
}

std::string rowText(const RowChange& r) {
    std::string s = fmt("%llu %s -> %s", (unsigned long long)r.row,
                        hitClassName(HitClass(r.oldClass)), hitClassName(HitClass(r.newClass)));
    if (r.oldLeak != r.newLeak)
        s += fmt(", leak %s -> %s", leakName(r.oldLeak), leakName(r.newLeak));
    return s;
}

}  // namespace

BaselineComparison compareWithBaseline(const RayCertification& now, const VerdictArrays& old,
                                       const std::string& prefix, int keep) {
    BaselineComparison out;
    out.prefix = prefix;
    for (const SetCertification& s : now.sets) {
        SetChange c;
        c.set = s.range.name;
        c.rows = s.range.count;
        for (uint64_t i = s.range.begin; i < s.range.begin + s.range.count; ++i) {
            const RowChange r{i, old.cls[i], now.rayClass[i], old.leak[i], now.rayLeak[i]};
            const int dc = classRank(r.newClass) - classRank(r.oldClass);
            const int dl = leakRank(r.newLeak) - leakRank(r.oldLeak);
            if (dc > 0 || dl > 0) {
                ++c.worse;
                if (int(c.firstWorse.size()) < keep) c.firstWorse.push_back(r);
            } else if (dc < 0 || dl < 0) {
                ++c.better;
                if (int(c.firstBetter.size()) < keep) c.firstBetter.push_back(r);
            }
        }
        out.better += c.better;
        out.worse += c.worse;
        out.sets.push_back(std::move(c));
    }
    return out;
}

json toJson(const BaselineComparison& c) {
    json sets = json::object();
    for (const SetChange& s : c.sets) {
        json worse = json::array(), better = json::array();
        for (const RowChange& r : s.firstWorse) worse.push_back(rowJson(r));
        for (const RowChange& r : s.firstBetter) better.push_back(rowJson(r));
        sets[s.set] = {{"rows", s.rows},
                       {"better", s.better},
                       {"worse", s.worse},
                       {"first_worse", worse},
                       {"first_better", better}};
    }
    return {{"prefix", c.prefix}, {"better", c.better}, {"worse", c.worse}, {"by_set", sets}};
}

std::string humanSummary(const BaselineComparison& c) {
    std::string s =
        fmt("baseline %s: %llu rays better, %llu worse than that run\n", c.prefix.c_str(),
            (unsigned long long)c.better, (unsigned long long)c.worse);
    for (const SetChange& k : c.sets) {
        if (!k.better && !k.worse) continue;
        s += fmt("  %-10s %8llu better %8llu worse", k.set.c_str(), (unsigned long long)k.better,
                 (unsigned long long)k.worse);
        if (!k.firstWorse.empty()) s += "; first worse: " + rowText(k.firstWorse.front());
        for (size_t i = 1; i < k.firstWorse.size() && i < 3; ++i)
            s += "; " + rowText(k.firstWorse[i]);
        s += "\n";
    }
    return s;
}

}  // namespace oct
