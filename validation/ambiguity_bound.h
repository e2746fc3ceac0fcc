// Each ray set's own bound on its ambiguous answers (docs/CERTIFY.md, "Each set's bound on
// ambiguous answers"). An ambiguous answer is excused ray by ray (the configuration is touchy),
// so a tracer that turns right answers into excused ones, a hit exactly at a range end dropped,
// passes every ray; only the count per set shows it. The bound of a set is what octrace's own
// kernel scored on the same rows when they were made (RaySet::baseline, recorded by octrace rays
// in the manifest), plus a slack for other correct tracers; a set without one (rays made by
// hand, validate's own sets) that is adversarial is held to a fixed share of its rows.
// Rows that leak are left out of the count: the watertight verdict judges them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "validation/policy/hit_check.h"
#include "validation/rays/ray_sets.h"

namespace oct {

// Above the baseline a set may show a share of it more ambiguous answers (its row's
// RaySetDesc::ambiguousSlack; this for sets of one's own), plus the policy's rate
// (maxAmbiguousRate) of its rows. octrace's kernel reproduces its baseline exactly on every
// layout and backend; the slack is for another tracer's rounding at the same configurations
// (measured: docs/CERTIFY.md), and lies well below the fault it was made for (62 % more
// ambiguous answers in tmin-tmax on the Cornell box).
constexpr double kAmbiguousSlack = 0.25;
// The slack of the set called `name`: its table row's, or kAmbiguousSlack.
double ambiguousSlack(const std::string& name);
// An adversarial set without a baseline: at most this share of its rows ambiguous (octrace's
// kernel shows up to 26 % on the committed meshes, the textbook Moller-Trumbore 34 %).
constexpr double kAdversarialAmbiguousShare = 0.5;

// The most ambiguous answers (leaks not counted) a set of `rows` rows may have: from `expected`
// when there is a baseline, else the fixed share for an adversarial set, else none (the ordinary
// sets' pooled rate, RayCertification::correct, is then their only bound).
std::optional<uint64_t> ambiguousLimit(uint64_t rows, std::optional<uint64_t> expected,
                                       bool adversarial, const ValidationPolicy& policy,
                                       double slack = kAmbiguousSlack);

// Whether `baseline` was judged by the tolerances of `policy` (otherwise its counts do not
// apply: wider tolerances excuse more).
bool baselineApplies(const AmbiguityBaseline& baseline, const ValidationPolicy& policy);

// What measuring a baseline holds per row besides the rays, at most: the two tracers' answers
// (16 bytes) and the check's per-row state and verdicts (under 24). octrace rays counts it in
// its memory check before drawing a row.
constexpr uint64_t kBaselineBytesPerRow = 48;

// octrace's own kernel (the host backend, the default layout) traced on `rays` and certified as
// any tracer is (certifyTracer, with the classifier's policy): its ambiguous count per set,
// leaks left out. What octrace rays records (makeStandardRays).
AmbiguityBaseline measureAmbiguityBaseline(const HitClassifier& classifier, const RaySet& rays);

}  // namespace oct
