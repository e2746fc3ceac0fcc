// validate's ray-scaling check: trace's power-of-two scaling (scaledRay, unscaledT and their use
// in traceRayAt, core/render/kernel.h) against its definition, std::ldexp in double
// (policy/ray_definitions.h, docs/VALIDATION.md "The kernel's rays against their definitions").
// Every tracer of validate and certify, Embree included, traces a row through traceRayAt, and
// the ray sets' directions are unit vectors, whose scaling is the identity: a fault in it
// passes every other check. Here traceRayAt runs through a probe (checks/kernel_probe.h) on
// rows whose largest direction component spans every float exponent, subnormal to the largest,
// with tmin and tmax from 0 to +inf, and on validate's own ray rows; the ray it traces and the
// t it writes back must be the definition's bit for bit (the scaling is exact, or rounds once
// where it leaves float's range), and so must scaledRay's answer and exponent.
#include <chrono>
#include <cmath>
#include <cstring>

#include "validation/checks/check.h"
#include "validation/checks/definition_result.h"
#include "validation/checks/kernel_probe.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using report_detail::fmt;

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Rows of extreme magnitudes: the largest |direction component| 2^k times 1, 1.5 and the
// largest mantissa for every float exponent k (subnormals included), on each axis in turn, with
// smaller components down to underflow, and tmin, tmax from 0 through subnormals to +inf.
std::vector<float> extremeRows() {
    const double mantissas[] = {1.0, 1.5, 2.0 - 0x1p-23};
    const float tmins[] = {0.0f, 0x1p-149f, 1e-30f, 0.25f, 3e38f};
    const float tmaxs[] = {INFINITY, 0x1p-140f, 1.0f, 1e30f, 3.4e38f, 0x1p-126f};
    std::vector<float> rows;
    uint32_t n = 0;
    for (int k = -149; k <= 127; ++k)
        for (double m : mantissas) {
            const float largest = roundToFloat(std::ldexp(m, k));
            if (!(largest > 0.0f) || std::isinf(largest)) continue;
            const int axis = (k + 149) % 3;
            float d[3];
            d[axis] = (k % 2) ? -largest : largest;
            d[(axis + 1) % 3] = -0.75f * largest;
            d[(axis + 2) % 3] = std::ldexp(largest, -3 * ((k + 149) % 11));
            const float row[8] = {float(k), float(m), -0.5f * float(k), d[0],
                                  d[1],     d[2],     tmins[n % 5],     tmaxs[n % 6]};
            rows.insert(rows.end(), row, row + 8);
            ++n;
        }
    return rows;
}

// What the probe answers for row i: distances across float's range, a miss now and then.
Hit answerFor(uint64_t i) {
    const float ts[] = {0.0f, 0x1p-149f, 0x1p-126f, 0.75f, 1e20f, 3.4e38f, INFINITY};
    const float t = ts[i % 7];
    return {t, std::isinf(t) ? -1 : int32_t(i % 1000)};
}

std::string rowText(const float* r) {
    return fmt("%.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g", r[0], r[1], r[2], r[3], r[4], r[5], r[6],
               r[7]);
}

std::string rayText(const Ray& r) {
    return fmt("dir %.9g,%.9g,%.9g [%.9g, %.9g]", r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
}

// The ray the definition traces for a row, with its origin as given.
bool matches(const Ray& k, const float* row, const ReferenceScaling& d) {
    return sameBits(k.org.x, row[0]) && sameBits(k.org.y, row[1]) && sameBits(k.org.z, row[2]) &&
           sameBits(k.dir.x, d.dir[0]) && sameBits(k.dir.y, d.dir[1]) &&
           sameBits(k.dir.z, d.dir[2]) && sameBits(k.tmin, d.tmin) && sameBits(k.tmax, d.tmax);
}

void checkRows(const float* rows, uint64_t count, RayDefinitionReport& rep) {
    ProbeLog log;
    const RayProbe probe{&log};
    float t = 0.0f;
    int32_t prim = 0;
    for (uint64_t i = 0; i < count; ++i) {
        const float* row = rows + 8 * i;
        const float largest = std::max({std::fabs(row[3]), std::fabs(row[4]), std::fabs(row[5])});
        if (!(largest > 0.0f) || std::isinf(largest)) {
            ++rep.unjudged;  // no scale: trace refuses such a row
            continue;
        }
        const ReferenceScaling d = referenceScaledRow(row);
        int e = 0;
        const Ray scaled = scaledRay(row, e);
        log.answer = answerFor(i);
        log.closestCalls = 0;
        traceRayAt(0, probe, {row, &t, &prim, 1});
        const float back = referenceUnscaledT(log.answer.t, d.e);
        const bool ok = e == d.e && matches(scaled, row, d) && log.closestCalls == 1 &&
                        matches(log.closest, row, d) && sameBits(t, back) &&
                        prim == log.answer.prim;
        rep.judge(ok ? 0.0 : INFINITY, [&] {
            return fmt(
                "ray scaling: row %s: scaledRay gives e %d, %s; traceRayAt traced %s and "
                "wrote t %.9g for a hit at %.9g; the definition: e %d, dir %.9g,%.9g,%.9g "
                "[%.9g, %.9g], t %.9g",
                rowText(row).c_str(), e, rayText(scaled).c_str(), rayText(log.closest).c_str(), t,
                log.answer.t, d.e, d.dir[0], d.dir[1], d.dir[2], d.tmin, d.tmax, back);
        });
    }
}

class RayScalingCheck : public SceneCheck {
public:
    const char* name() const override { return "ray_scaling"; }

    void run(const CheckInputs& in, ValidationReport& out) const override {
        const auto start = std::chrono::steady_clock::now();
        RayDefinitionReport rep;
        const std::vector<float> rows = extremeRows();
        checkRows(rows.data(), rows.size() / 8, rep);
        checkRows(in.rays.rays.data(), in.rays.count(), rep);
        rep.scope =
            fmt("%llu rows of extreme magnitudes and validate's %llu ray rows through "
                "traceRayAt",
                (unsigned long long)(rows.size() / 8), (unsigned long long)in.rays.count());
        rep.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        out.rayScaling = std::move(rep);
    }

    CheckResult result(const ValidationReport& rep) const override {
        if (!rep.rayScaling) return notRun("ray_scaling");
        return definitionResult("ray_scaling", "ray scale", "against std::ldexp in double",
                                *rep.rayScaling);
    }
};

}  // namespace

const SceneCheck& rayScalingCheck() {
    static const RayScalingCheck check;
    return check;
}

}  // namespace oct
