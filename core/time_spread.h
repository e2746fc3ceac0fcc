// Median, minimum and maximum of repeated timings: one rule for every backend, so CPU and CUDA
// frame times compare like for like (octrace bench, renderCuda); and the one wall-clock
// interval every timing takes. Host code only.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace oct {

// Seconds of the steady clock since t0.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct TimeSpread {
    double median = 0, min = 0, max = 0;
};

// The median of an even count is the mean of the middle two. An empty list gives zeros.
inline TimeSpread timeSpread(std::vector<double> v) {
    TimeSpread s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    s.min = v.front();
    s.max = v.back();
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    return s;
}

}  // namespace oct
