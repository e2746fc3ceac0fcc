#include "bench/sweep/time_guard.h"

#include <cmath>

#include "bench/sweep/results.h"

namespace oct {

std::optional<Estimate> TimeGuard::estimate(const std::string& key, bool linearInN, double prims,
                                            double pixels) const {
    auto it = history_.find(key);
    if (it == history_.end() || it->second.empty()) return std::nullopt;
    const Sample* best = nullptr;
    for (const Sample& s : it->second)
        if (s.prims <= prims && (!best || s.prims > best->prims)) best = &s;
    if (!best)
        for (const Sample& s : it->second)
            if (!best || s.prims < best->prims) best = &s;
    double exponent = linearInN ? 1.0 : 0.5;
    double t =
        best->frameSeconds * std::pow(prims / best->prims, exponent) * (pixels / best->pixels);
    return Estimate{t, "history: " + best->scene + " at " + fmt("%.3g", best->frameSeconds) +
                           " s/frame, time ~ N" + (linearInN ? "" : "^0.5")};
}

}  // namespace oct
