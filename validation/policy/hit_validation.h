// Per-pixel validation of one tracer's Film against a reference's, by the policy of
// hit_check.h, and the counts and findings it shares with the per-ray check (certify.h). Inputs
// are Films (plus the scene and the frame for rechecks): validation never sees a layout's
// insides, so a Film rendered from a deliberately corrupted structure is validated exactly like
// any other.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/render/camera.h"
#include "core/render/frame.h"
#include "validation/policy/hit_check.h"

namespace oct {

struct ClassCounts {
    uint64_t compared = 0;  // queries compared (pixels, shadow rays, rays)
    uint64_t bothMiss = 0;  // included in agree
    uint64_t agree = 0;
    uint64_t ties = 0;
    uint64_t ambiguous = 0;
    uint64_t wrong = 0;
    uint64_t unverified = 0;  // mismatches past the user's recheck cap: neither right nor wrong
    uint64_t mismatches = 0;  // before the recheck (hit/miss or |dt| beyond tolerance)
    uint64_t rechecked = 0;
    // Every class by reason (ambiguous: what excuses it; wrong: why it is wrong).
    std::array<uint64_t, kReasonCount> reasons{};
    // Over queries where both hit: |dt| / extent; +inf when a t was not finite.
    double maxRelativeDt = 0.0;

    double ambiguousRate() const { return compared ? double(ambiguous) / double(compared) : 0.0; }
    double wrongRate() const { return compared ? double(wrong) / double(compared) : 0.0; }
    // No wrong answer and the ambiguous rate at or below the threshold.
    bool passes(double maxAmbiguousRate) const {
        return wrong == 0 && ambiguousRate() <= maxAmbiguousRate;
    }
    // Every query judged (none left unverified by a recheck cap).
    bool complete() const { return unverified == 0; }
    void count(HitClass c, uint32_t reasons);
    void merge(const ClassCounts& o);
};

// One query worth reporting. For pixels x, y are the pixel; for rays x = -1, y = -1.
struct Finding {
    int x = -1, y = -1;
    uint64_t index = 0;  // pixel index y * width + x, or ray index
    HitClass cls = HitClass::Agree;
    uint32_t reasons = 0;
    Hit ours = {INFINITY, -1}, reference = {INFINITY, -1};
    bool rechecked = false;
    Hit truth = {INFINITY, -1};  // double-precision closest hit, when rechecked
    double relativeDt = 0.0;     // |dt| / extent (+inf for hit against miss)
    std::string set;             // rays only: the ray set's name
    Ray ray{};
};

struct ShadowFinding {
    int x = -1, y = -1;
    HitClass cls = HitClass::Agree;
    uint32_t reasons = 0;
    uint8_t ours = kNoShadowRay, reference = kNoShadowRay;  // Film shadow states
    int referenceOnOurRay = -1;  // reference rerun on our shadow ray: 1 occluded, 0 lit, -1 not run
    int truthOccluded = -1;      // double truth on our shadow ray, -1 when not rechecked
    Ray ray{};                   // our shadow ray
};

struct FilmValidation {
    int width = 0, height = 0;
    ClassCounts primary;
    ClassCounts shadow;
    uint64_t shadowResolvedByRerun = 0;  // differing shadow states the reference reproduced on
                                         // our own shadow ray (the two shadow rays differed)
    uint64_t shadowNotCompared = 0;      // pixels whose primary hits already mismatch
    std::vector<Finding> worstPixels;    // most severe first, then largest |dt|
    std::vector<ShadowFinding> worstShadows;
    // Per pixel, for the diff image: primary class (HitClass, 255 = both miss), shadow class
    // (255 = not compared) and |dt| / extent (0 when both miss, +inf for hit against miss).
    std::vector<uint8_t> primaryClass, shadowClass;
    std::vector<float> relativeDt;

    bool passes(double maxAmbiguousRate) const {
        return primary.passes(maxAmbiguousRate) && shadow.passes(maxAmbiguousRate);
    }
};

// Re-asks the reference whether a ray is occluded (Embree's rtcOccluded1). Called from several
// threads at once. May be empty: then a shadow mismatch goes straight to the double truth.
using OcclusionQuery = std::function<bool(const Ray&)>;

// Compares two Films rendered with the same frame. Throws std::invalid_argument when their
// sizes differ from the frame's.
FilmValidation validateFilm(const HitClassifier& c, const FrameParams& frame, const Film& ours,
                            const Film& reference, const OcclusionQuery& referenceOccluded = {});

}  // namespace oct
