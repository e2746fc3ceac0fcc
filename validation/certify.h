// Certification of any tracer's answers for a ray file (`octrace certify`, docs/CERTIFY.md), and
// the per-ray check `octrace validate` runs on its own layouts: one code path.
//
// Every ray is judged by the policy of policy/hit_check.h (docs/VALIDATION.md): a closest-hit
// query (an any-hit one for the shadow set and for sets of one's own given as such) against the
// reference's answer, a mismatch rechecked in double and called ambiguous or wrong, or left
// unverified past a cap the user set. The leak check needs no reference: an edges or vertices
// ray aimed at a sealed target must hit on a surface at or before it. Two verdicts: correct (no
// wrong answer; the ambiguous rate of the non-adversarial sets, pooled, at or below the limit;
// each set's ambiguous count within its own bound, ambiguity_bound.h) and watertight (no leak);
// each PASS, FAIL, INCOMPLETE (unverified work and nothing wrong) or not tested. A faulty
// tracer's output never crashes the check.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/mesh_topology.h"
#include "validation/policy/hit_validation.h"
#include "validation/policy/judged_scene.h"
#include "validation/rays/hit_files.h"
#include "validation/rays/ray_sets.h"

namespace oct {

// A query's kind: the closest hit, or any hit on the segment (an occlusion query).
enum class QueryKind : uint8_t { Closest = 0, AnyHit = 1 };

// How one certification's rows are shared among processes (MPI ranks, dist/ranks.h): rows are
// dealt in blocks of `block`, block b to process b mod `count`; this one (`index`) judges its
// rows (the reference's answers, the first comparison, the rechecks and the leak rechecks), and
// `combine` merges an array of the run in place from every process, each byte written by the
// process that owns its row and zero on the others. Counts, findings and per-row verdicts then
// follow from the merged arrays on every process alike, in row order, so they equal one
// process's; the recheck caps count in row order too. Every process calls certifyRays with the
// same rows and answers (combine is collective).
struct RowShare {
    uint64_t block = 1;
    uint32_t index = 0, count = 1;
    std::function<void(void* data, uint64_t bytes)> combine;
    bool owns(uint64_t row) const { return (row / block) % count == index; }
};

struct CertifyOptions {
    QueryKind ownSets = QueryKind::Closest;  // sets whose names are not standard (--query)
    const RowShare* share = nullptr;         // null: this process judges every row
};

// Per row, as certify's leak file stores it (docs/CERTIFY.md): never renumber.
enum class LeakState : uint8_t {
    Sealed = 0,      // a target ray that hit a surface at or before its target
    Leak = 1,        // it did not, and the truth meets the target's sealed surface there
    NotTarget = 2,   // the row has no target
    Unsealed = 3,    // a candidate the truth does not meet at the target: not counted as checked
    Unverified = 4,  // a candidate past the recheck cap
};

// A verdict: PASS, FAIL, INCOMPLETE (work left unverified, nothing wrong), or nothing to judge.
enum class Outcome : uint8_t { Pass = 0, Fail = 1, Incomplete = 2, NotTested = 3 };
const char* outcomeName(Outcome o);  // "PASS", "FAIL", "INCOMPLETE", "not tested"
// The worse of two outcomes (Fail over Incomplete over Pass; NotTested counts as Pass).
Outcome worse(Outcome a, Outcome b);

struct LeakFinding {
    uint64_t index = 0;  // row
    std::string set;
    RayTarget target;
    Hit got{INFINITY, -1};    // the tracer's answer
    Hit truth{INFINITY, -1};  // the double-precision closest hit
    bool rechecked = true;    // false: past the recheck cap (unverified)
    Ray ray{};
};

struct SetCertification {
    RaySetRange range;
    bool adversarial = false;
    QueryKind query = QueryKind::Closest;
    ClassCounts counts;
    uint64_t leakChecked = 0;           // target rays judged (sealed or leaking)
    uint64_t leaks = 0;                 // confirmed by the truth
    uint64_t unsealed = 0;              // targets the truth does not meet: not counted as checked
    uint64_t leakUnverified = 0;        // candidates past the recheck cap
    std::vector<Finding> worst;         // wrong, unverified, ambiguous by row, then ties by |dt|
    std::vector<LeakFinding> leakList;  // the first ones by row
    // The set's own bound on ambiguous answers (ambiguity_bound.h): the ambiguous rows that do
    // not leak (leaks are the watertight verdict's), octrace's kernel's count on these rows
    // when there is a baseline that applies, and the most allowed (none: no bound of its own).
    uint64_t ambiguousCounted = 0;
    std::optional<uint64_t> expectedAmbiguous;
    std::optional<uint64_t> ambiguousLimit;
    bool withinAmbiguousLimit() const {
        return !ambiguousLimit || ambiguousCounted <= *ambiguousLimit;
    }
    // No wrong ray, no leak, and the ambiguous count within the set's bound (the ordinary sets'
    // rate is judged over them together).
    bool clean() const { return counts.wrong == 0 && leaks == 0 && withinAmbiguousLimit(); }
};

struct RayCertification {
    std::vector<SetCertification> sets;
    ClassCounts all;
    ClassCounts strict;  // the sets that are not adversarial, pooled: the ambiguous rate's base
    uint64_t leakChecked = 0, leaks = 0, unsealed = 0, leakUnverified = 0;
    // The rays carried a baseline (RaySet::baseline) measured under other tolerances than the
    // policy's: not applied, the adversarial sets held to the fixed share only.
    bool baselineIgnored = false;
    std::vector<Finding> worst;     // over all sets, as ordered per set
    std::vector<Finding> examples;  // the first row of every class and reason that occurred
    // Per row (certify --verdicts): HitClass, AmbiguityReason bits, LeakState.
    std::vector<uint8_t> rayClass;
    std::vector<uint32_t> rayReasons;
    std::vector<uint8_t> rayLeak;
    // The camera set, per pixel, for the diff image: class (HitClass, 255 = both miss) and
    // |dt| / extent. Empty without a camera set.
    std::vector<uint8_t> cameraClass;
    std::vector<float> cameraRelativeDt;

    // The two verdicts (certify.h's header).
    Outcome correct(double maxAmbiguousRate) const;
    // The sets whose ambiguous count is above their own bound, comma-separated ("" when none).
    std::string setsOverAmbiguousLimit() const;
    Outcome watertight() const;
    // Both verdicts PASS (or watertightness not tested).
    bool passes(double maxAmbiguousRate) const {
        return worse(correct(maxAmbiguousRate), watertight()) == Outcome::Pass;
    }
};

// Classifies every ray of `rays` (its sets, its targets) from our answers against the
// reference's. Throws std::invalid_argument when an array's length is not the ray count, a
// set's rows lie outside it, or the reference has no primitive ids.
// The reference's next hit on row i beyond `after` (its first): a cheap witness for the
// rechecks (HitClassifier::recheckClosest). May be empty.
using NextReferenceHit = std::function<Hit(uint64_t i, Hit after)>;
RayCertification certifyRays(const HitClassifier& c, const RaySet& rays, const HitArrays& ours,
                             const HitArrays& reference, const CertifyOptions& options = {},
                             const NextReferenceHit& next = {});

// The camera set's outcome as a FilmValidation, for writeDiffImage
// (validation/report/diff_image.h). Throws std::invalid_argument without a camera set or frame.
FilmValidation cameraDiff(const RayCertification& r, const RaySet& rays);

struct TopologySummary {
    bool closed = false;
    uint64_t vertices = 0, edges = 0, boundaryEdges = 0, nonManifoldEdges = 0;
};
TopologySummary summarize(const MeshTopology& t);

// Which verdicts decide certify's outcome (and its exit status): --require.
enum class Require : uint8_t { Correct = 0, Watertight = 1, All = 2 };
const char* requireName(Require r);  // "correct", "watertight", "all"

struct CertifyReport : JudgedScene {
    std::string rays, hits;  // the files, as named
    bool primIds = true;
    bool manifest = false;
    uint64_t seed = 0;
    std::vector<std::string> notes;
    std::optional<TopologySummary> topology;  // triangle meshes
    RayCertification result;
    double referenceSeconds = 0.0, checkSeconds = 0.0, seconds = 0.0;

    Require require = Require::All;
    // The standard sets the scene could take that the ray file does not give: a PASS without
    // them is partial (the report says so).
    std::vector<std::string> missingSets;
    // The camera set's rows against the camera's definition (RaySet::cameraRows): off, the ray
    // file is not what it claims, whatever the answers, and the outcome is FAIL.
    std::optional<RayDefinitionReport> cameraRows;
    bool cameraRowsOff() const { return cameraRows && !cameraRows->passes(); }

    // The required verdicts combined: FAIL over INCOMPLETE over PASS; FAIL too when the camera
    // rows are off their definition. A required watertight
    // verdict that could not be tested (no target rays) is INCOMPLETE; under `all` it is left
    // out (the report says which standard sets were not given).
    Outcome outcome() const;
    bool passes() const { return outcome() == Outcome::Pass; }
};

// Traces `rays` with Embree (robust mode) as the reference and certifies `ours` against it.
CertifyReport certifyTracer(const Scene& scene, const RaySet& rays, const HitArrays& ours,
                            const ValidationPolicy& policy, const CertifyOptions& options = {});
// The same with a classifier of the scene made beforehand (its double truth can seal the ray
// sets' targets too: raySetFromFile).
CertifyReport certifyTracer(const HitClassifier& classifier, const RaySet& rays,
                            const HitArrays& ours, const CertifyOptions& options = {});

}  // namespace oct
