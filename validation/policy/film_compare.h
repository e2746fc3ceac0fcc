// Per-pixel comparison of two tracers' answers by the policy of docs/VALIDATION.md: both miss ->
// agree; both hit with |dt| <= tolerance * scene extent -> agree (another primitive at the same t
// is a tie, not an error); anything else is a mismatch. Mismatches are classified further by the
// certification checks (validation/: `octrace validate` also rechecks each tie against the
// primitive's distance to the hit point), this comparison only counts them.
#pragma once

#include <cstdint>
#include <vector>

#include "core/render/frame.h"

namespace oct {

// Default |dt| tolerance relative to the scene's extent (its bounding-box diagonal): float hit
// distances computed by different algorithms differ by a few ulps of t, t <= ~2 diagonals away.
constexpr double kDefaultRelativeTolerance = 1e-5;

struct PixelMismatch {
    int x, y;
    float tA, tB;
    int32_t primA, primB;
};

struct FilmComparison {
    uint64_t pixels = 0;
    uint64_t bothMiss = 0;
    uint64_t bothHitAgree = 0;         // |dt| within tolerance, same primitive
    uint64_t ties = 0;                 // |dt| within tolerance, different primitive
    uint64_t hitMissMismatch = 0;      // one hit, the other missed
    uint64_t distanceMismatch = 0;     // both hit, |dt| beyond tolerance
    uint64_t shadowMismatch = 0;       // shadow ray outcome differs where both traced one
    double maxRelativeDt = 0.0;        // over pixels both hit, |dt| / extent
    std::vector<PixelMismatch> worst;  // up to 16 mismatching pixels, largest |dt| first

    uint64_t agreeing() const { return bothMiss + bothHitAgree + ties; }
    uint64_t mismatches() const { return hitMissMismatch + distanceMismatch; }
};

// Compares the t/prim/shadow arrays of two films of the same size. `extent` is the scene's
// bounding-box diagonal.
FilmComparison compareFilms(const Film& a, const Film& b, double extent,
                            double relativeTolerance = kDefaultRelativeTolerance);

// Same, for ray batches (octrace trace): t and prim arrays of equal length.
FilmComparison compareHits(const std::vector<float>& tA, const std::vector<int32_t>& pA,
                           const std::vector<float>& tB, const std::vector<int32_t>& pB,
                           double extent, double relativeTolerance = kDefaultRelativeTolerance);

}  // namespace oct
