#include "core/scene/slivers.h"

#include <array>
#include <new>
#include <random>
#include <string>
#include <vector>

namespace oct {
namespace {

struct GridPoint {
    int64_t x, y;  // multiples of 2^-24
};

// Twice the signed area of (a, b, c) in grid units: exact (|coordinates| <= 2^24).
int64_t orient(GridPoint a, GridPoint b, GridPoint c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

void checkCount(uint64_t n) {
    const std::string spec = "slivers:" + std::to_string(n);
    if (n < 2)
        throw SceneError(spec + ": a slivers scene needs at least the square's 2 triangles; use " +
                         "slivers:N with an even N >= 2");
    if (n > kSliversMaxTriangles)
        throw SceneError(spec + ": more than the maximum of " +
                         std::to_string(kSliversMaxTriangles) + " triangles; use at most " +
                         std::to_string(kSliversMaxTriangles));
    if (n % 2 != 0)
        throw SceneError(spec + ": N is the number of triangles, and each split adds two to the " +
                         "square's two, so N must be even; use slivers:" + std::to_string(n - 1) +
                         " or slivers:" + std::to_string(n + 1));
}

}  // namespace

Scene makeSlivers(uint64_t n, uint64_t seed) {
    checkCount(n);
    const std::string spec = "slivers:" + std::to_string(n) + ":" + std::to_string(seed);
    constexpr int64_t kOne = int64_t{1} << kSliversGridBits;
    Scene scene;
    scene.name = spec;
    scene.kind = PrimKind::Triangles;
    scene.report.format = "slivers";
    try {
        std::vector<GridPoint> v = {{0, 0}, {kOne, 0}, {kOne, kOne}, {0, kOne}};
        std::vector<std::array<uint32_t, 3>> tri = {{0, 1, 2}, {0, 2, 3}};
        v.reserve(n / 2 + 3);
        tri.reserve(n);
        std::mt19937_64 engine(seed);
        const uint64_t mixRange = kSliversMixHi - kSliversMixLo + 1;
        // Some split always succeeds with a fair chance (the largest triangle is wide enough):
        // the bound only turns a bug into an error instead of a hang.
        const uint64_t maxDraws = 1000 + 1000 * n;
        for (uint64_t draws = 0; tri.size() < n; ++draws) {
            if (draws == maxDraws)
                throw SceneError(spec + ": no split point found in " + std::to_string(maxDraws) +
                                 " draws; report this with the spec");
            const size_t k = size_t(engine() % tri.size());
            const int64_t a = kSliversMixLo + int64_t(engine() % mixRange);
            const int64_t b = kSliversMixLo + int64_t(engine() % mixRange);
            const std::array<uint32_t, 3> t = tri[k];
            const GridPoint p = v[t[0]], q = v[t[1]], r = v[t[2]];
            // Fixed point: m has 16 fraction bits, s2 32 (all values >= 0, below 2^57).
            auto mix = [&](int64_t pc, int64_t qc, int64_t rc) {
                const int64_t m = (pc << 16) + (qc - pc) * a;
                const int64_t s2 = (m << 16) + ((rc << 16) - m) * b;
                return int64_t((uint64_t(s2) + (uint64_t{1} << 31)) >> 32);
            };
            const GridPoint s = {mix(p.x, q.x, r.x), mix(p.y, q.y, r.y)};
            if (orient(p, q, s) <= 0 || orient(q, r, s) <= 0 || orient(r, p, s) <= 0) continue;
            const uint32_t id = uint32_t(v.size());
            v.push_back(s);
            tri[k] = {t[0], t[1], id};
            tri.push_back({t[1], t[2], id});
            tri.push_back({t[2], t[0], id});
        }
        auto at = [&](uint32_t i) {
            constexpr double kStep = 1.0 / double(kOne);
            return Vec3{float(double(v[i].x) * kStep), float(double(v[i].y) * kStep), 0.0f};
        };
        scene.triangles.reserve(n);
        scene.sourceFace.reserve(n);
        for (const std::array<uint32_t, 3>& t : tri) {
            scene.sourceFace.push_back(uint32_t(scene.triangles.size()));
            scene.triangles.push_back({at(t[0]), at(t[1]), at(t[2])});
        }
        scene.report.verticesRead = v.size();
        scene.report.facesRead = n;
    } catch (const std::bad_alloc&) {
        throw SceneError(spec + ": out of memory for " + std::to_string(n) +
                         " triangles; use fewer");
    }
    return scene;
}

bool isSliversScene(const Scene& scene) {
    return scene.kind == PrimKind::Triangles && scene.report.format == "slivers";
}

}  // namespace oct
