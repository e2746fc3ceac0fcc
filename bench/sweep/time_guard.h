// The sweep's time guard: frame times measured so far, per (primitive kind, layout, backend),
// estimate the next larger case before it runs, so a sweep never starts a case that would take
// hours. Exhaustive time grows as N (every ray tests every primitive); octrees and Embree's BVH
// grow far slower, and sqrt(N) is a safe upper model (the paper reports a doubling per 16x,
// i.e. N^0.25).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace oct {

struct Sample {
    double prims, pixels, frameSeconds;
    std::string scene;
};

struct Estimate {
    double frameSeconds;
    std::string how;  // what the estimate was scaled from, for the row's reason
};

class TimeGuard {
public:
    void record(const std::string& key, const Sample& s) { history_[key].push_back(s); }

    // From the largest measured case not above `prims` (else the smallest above it), scaled
    // by N (linearInN) or sqrt(N) and by the pixel count. None without history.
    std::optional<Estimate> estimate(const std::string& key, bool linearInN, double prims,
                                     double pixels) const;

private:
    std::map<std::string, std::vector<Sample>> history_;
};

}  // namespace oct
