#include "validation/policy/film_compare.h"

#include <algorithm>
#include <cmath>

namespace oct {
namespace {

// Adds one answer pair to the counts of c; a mismatch is kept as a candidate worst pixel.
void classify(FilmComparison& c, float tA, int32_t pA, float tB, int32_t pB, double extent,
              double tol, int x, int y) {
    bool hitA = pA >= 0, hitB = pB >= 0;
    ++c.pixels;
    if (!hitA && !hitB) {
        ++c.bothMiss;
        return;
    }
    double rel = INFINITY;
    if (hitA && hitB) {
        rel = std::fabs(double(tA) - double(tB)) / extent;
        c.maxRelativeDt = std::max(c.maxRelativeDt, rel);
        if (rel <= tol) {
            ++(pA == pB ? c.bothHitAgree : c.ties);
            return;
        }
        ++c.distanceMismatch;
    } else {
        ++c.hitMissMismatch;
    }
    c.worst.push_back({x, y, tA, tB, pA, pB});
}

void keepWorst(FilmComparison& c) {
    auto key = [](const PixelMismatch& m) {
        double d = std::fabs(double(m.tA) - double(m.tB));
        return std::isnan(d) ? INFINITY : d;  // hit/miss pairs (inf - t) sort first
    };
    std::stable_sort(
        c.worst.begin(), c.worst.end(),
        [&](const PixelMismatch& a, const PixelMismatch& b) { return key(a) > key(b); });
    if (c.worst.size() > 16) c.worst.resize(16);
}

}  // namespace

FilmComparison compareFilms(const Film& a, const Film& b, double extent, double tol) {
    FilmComparison c;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            size_t i = size_t(y) * a.width + x;
            classify(c, a.t[i], a.prim[i], b.t[i], b.prim[i], extent, tol, x, y);
            bool bothShadowRays = a.shadow[i] != kNoShadowRay && b.shadow[i] != kNoShadowRay;
            c.shadowMismatch += bothShadowRays && a.shadow[i] != b.shadow[i];
        }
    keepWorst(c);
    return c;
}

FilmComparison compareHits(const std::vector<float>& tA, const std::vector<int32_t>& pA,
                           const std::vector<float>& tB, const std::vector<int32_t>& pB,
                           double extent, double tol) {
    FilmComparison c;
    for (size_t i = 0; i < tA.size(); ++i)
        classify(c, tA[i], pA[i], tB[i], pB[i], extent, tol, int(i), 0);
    keepWorst(c);
    return c;
}

}  // namespace oct
