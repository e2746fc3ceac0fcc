// Stand-in accelerators through which validate's camera, shadow-ray and ray-scaling checks run
// the kernel's own code (tracePixel, renderPixel and traceRayAt in core/render/kernel.h, the
// OpenMP launcher): their queries answer what the check chose and keep the ray they were given,
// so a check sees exactly the rays a frame or a ray batch traces, built by the functions that
// build them, with no traversal in between.
#pragma once

#include <cstdint>
#include <cstring>

#include "core/render/kernel.h"

namespace oct {

// What one probed query was asked and answers. One thread: the checks probe pixel by pixel.
struct ProbeLog {
    Hit answer = {INFINITY, -1};  // closestHit's answer
    Ray closest{}, shadow{};      // the last rays closestHit and anyHit were given
    int closestCalls = 0, anyHitCalls = 0;
};

struct RayProbe {
    ProbeLog* log;
};

inline Hit closestHit(const RayProbe& p, const Ray& r, TraceCost&) {
    p.log->closest = r;
    ++p.log->closestCalls;
    return p.log->answer;
}
template <class Obs>
Hit closestHit(const RayProbe& p, const Ray& r, TraceCost& cost, Obs&) {
    return closestHit(p, r, cost);
}
inline bool anyHit(const RayProbe& p, const Ray& r, TraceCost&) {
    p.log->shadow = r;
    ++p.log->anyHitCalls;
    return false;
}
template <class Obs>
bool anyHit(const RayProbe& p, const Ray& r, TraceCost& cost, Obs&) {
    return anyHit(p, r, cost);
}

// A tag of a ray's bits, in [1, 2^24] and exact as a float: different rays get different tags
// but for a collision of the hash (1 in 2^24 a pair).
inline float rayTag(const Ray& r) {
    uint32_t w[8];
    std::memcpy(w, &r, sizeof w);
    uint64_t h = 1469598103934665603ull;  // FNV-1a over the ray's 32 bytes
    for (uint32_t v : w) h = (h ^ v) * 1099511628211ull;
    return float((h >> 40) + 1);
}

// For a whole frame rendered by a launcher, in parallel: a miss whose t is the ray's tag, so the
// film shows at each index which pixel's ray was traced there.
struct TagProbe {};

inline Hit closestHit(const TagProbe&, const Ray& r, TraceCost&) { return {rayTag(r), -1}; }
template <class Obs>
Hit closestHit(const TagProbe& p, const Ray& r, TraceCost& cost, Obs&) {
    return closestHit(p, r, cost);
}
inline bool anyHit(const TagProbe&, const Ray&, TraceCost&) { return false; }
template <class Obs>
bool anyHit(const TagProbe&, const Ray&, TraceCost&, Obs&) {
    return false;
}

}  // namespace oct
