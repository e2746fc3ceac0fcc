// traceRayAt (core/render/kernel.h) rescales a user's ray by a power of two before tracing and
// the hit's t back after. It builds the power of two from exponent bits instead of calling
// frexpf/ldexpf per ray; these tests pin that the rays handed to the traversal and the t
// written back are bit for bit those of the ldexpf form, across the whole exponent range the
// ray reader admits and beyond it (where the ldexpf form itself is taken), overflow and
// underflow of tmin, tmax and t included.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "core/render/kernel.h"

namespace oct {
namespace {

// An accelerator that records the ray it was asked about and answers a chosen t.
struct RecordingAccel {
    Ray* seen;
    float answer;
};
Hit closestHit(const RecordingAccel& a, const Ray& r, TraceCost&) {
    *a.seen = r;
    return {a.answer, 0};
}

uint32_t bitsOf(float f) {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

// The reference: the frexpf/ldexpf form the kernel used before.
struct Reference {
    Ray ray;
    float t;
};
Reference reference(const float* r, float answer) {
    int e = 0;
    std::frexp(std::fmax(std::fabs(r[3]), std::fmax(std::fabs(r[4]), std::fabs(r[5]))), &e);
    Reference out;
    out.ray = {{r[0], r[1], r[2]},
               {std::ldexp(r[3], -e), std::ldexp(r[4], -e), std::ldexp(r[5], -e)},
               std::ldexp(r[6], e),
               std::ldexp(r[7], e)};
    out.t = std::ldexp(answer, -e);
    return out;
}

TEST(TraceRayScaling, SameBitsAsLdexpOverTheWholeExponentRange) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> dirExp(-140, 127), tExp(-149, 127);
    uint64_t checked = 0, slowPath = 0;
    for (int i = 0; i < 200000; ++i) {
        const int ed = dirExp(rng);
        float row[8] = {unit(rng),
                        unit(rng),
                        unit(rng),
                        std::ldexp(unit(rng), ed),
                        std::ldexp(unit(rng), ed - (i % 30)),
                        std::ldexp(unit(rng), ed - (i % 7)),
                        std::fabs(std::ldexp(unit(rng), tExp(rng))),
                        std::fabs(std::ldexp(unit(rng), tExp(rng)))};
        if (i % 5 == 0) row[7] = INFINITY;
        const float largest =
            std::fmax(std::fabs(row[3]), std::fmax(std::fabs(row[4]), std::fabs(row[5])));
        if (largest == 0.0f) continue;
        const float answer = i % 3 == 0 ? INFINITY : std::ldexp(std::fabs(unit(rng)), tExp(rng));
        Ray seen{};
        float t = 0.0f;
        int32_t prim = 0;
        RecordingAccel accel{&seen, answer};
        traceRayAt(0, accel, RayBatchView{row, &t, &prim, 1});
        const Reference want = reference(row, answer);
        ASSERT_EQ(bitsOf(seen.dir.x), bitsOf(want.ray.dir.x)) << "row " << i;
        ASSERT_EQ(bitsOf(seen.dir.y), bitsOf(want.ray.dir.y)) << "row " << i;
        ASSERT_EQ(bitsOf(seen.dir.z), bitsOf(want.ray.dir.z)) << "row " << i;
        ASSERT_EQ(bitsOf(seen.tmin), bitsOf(want.ray.tmin)) << "row " << i;
        ASSERT_EQ(bitsOf(seen.tmax), bitsOf(want.ray.tmax)) << "row " << i;
        ASSERT_EQ(bitsOf(t), bitsOf(want.t)) << "row " << i;
        ASSERT_EQ(bitsOf(seen.org.x), bitsOf(row[0]));
        ++checked;
        int e = 0;
        std::frexp(largest, &e);
        slowPath += e < -120 || e > 120;
    }
    EXPECT_GT(checked, 190000u);
    EXPECT_GT(slowPath, 1000u) << "the ldexpf form must be exercised too";
}

}  // namespace
}  // namespace oct
