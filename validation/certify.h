// Certification of any tracer's answers for a ray file (`octrace certify`, docs/CERTIFY.md), and
// the per-ray check `octrace validate` runs on its own layouts: one code path.
//
// Every ray is classified by the policy of hit_check.h (docs/VALIDATION.md): the tracer's hit
// against the reference's (Embree, robust), a mismatch rechecked in double precision and called
// ambiguous or wrong. Counts, rates and the first findings are kept per ray set (ray_sets.h).
//
// Leak check (watertightness, no reference needed): an edges or vertices ray is aimed at a point
// its edge's two triangles (its vertex's fan) seal, seen along the ray (ray_sets.h). A tracer
// without cracks hits at or before that point: t <= target + t tolerance. Any other answer (a
// miss, a later hit, a malformed one) is a leak candidate; the double-precision truth, whose
// triangle test is watertight, then confirms that the float ray as stored does hit there, and
// only then is it a leak (else it is counted as `unsealed`, which construction makes rare).
//
// Pass: in every set, no wrong ray and no leak; and the ambiguous rate over the sets that are
// not adversarial, pooled (camera, shadow, around, inside, axis, and sets of one's own), at or
// below the threshold. The adversarial sets (edges, vertices, grazing, tmin-tmax) are built of
// touchy rays, where ambiguity is the expected outcome of a mismatch: their rate is reported,
// not limited. Pooled, not per set, so that one ambiguous ray in a small set is judged against
// all the rays where ambiguity is rare (validate judged its ray sets together, too).
//
// A faulty tracer's output never crashes the check: NaN, negative or out-of-range t, primitive
// ids beyond the scene or below -1, and misses with a finite t are wrong (invalid_hit).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/scene/mesh_topology.h"
#include "validation/policy/hit_validation.h"
#include "validation/policy/judged_scene.h"
#include "validation/rays/hit_files.h"
#include "validation/rays/ray_sets.h"

namespace oct {

struct LeakFinding {
    uint64_t index = 0;  // row
    std::string set;
    RayTarget target;
    Hit got{INFINITY, -1};    // the tracer's answer
    Hit truth{INFINITY, -1};  // the double-precision closest hit
    bool rechecked = true;    // false: over the recheck budget, counted unconfirmed
    Ray ray{};
};

struct SetCertification {
    RaySetRange range;
    bool adversarial = false;
    ClassCounts counts;
    uint64_t leakChecked = 0;           // rays with a target
    uint64_t leaks = 0;                 // confirmed by the truth (or over the budget)
    uint64_t unsealed = 0;              // candidates the truth does not hit at the target either
    std::vector<Finding> worst;         // wrong and ambiguous by row, then ties by |dt|
    std::vector<LeakFinding> leakList;  // the first ones by row
    // No wrong ray and no leak (the ambiguous rate is judged over the sets together).
    bool clean() const { return counts.wrong == 0 && leaks == 0; }
};

struct RayCertification {
    std::vector<SetCertification> sets;
    ClassCounts all;
    ClassCounts strict;  // the sets that are not adversarial, pooled: the ambiguous rate's base
    uint64_t leakChecked = 0, leaks = 0, unsealed = 0;
    std::vector<Finding> worst;  // over all sets, as ordered per set
    // The camera set, per pixel, for the diff image: class (HitClass, 255 = both miss) and
    // |dt| / extent. Empty without a camera set.
    std::vector<uint8_t> cameraClass;
    std::vector<float> cameraRelativeDt;

    bool passes(double maxAmbiguousRate) const;
};

// Classifies every ray of `rays` (its sets, its targets) from our answers against the
// reference's. Throws std::invalid_argument when an array's length is not the ray count, a
// set's rows lie outside it, or the reference has no primitive ids.
RayCertification certifyRays(const HitClassifier& c, const RaySet& rays, const HitArrays& ours,
                             const HitArrays& reference);

// The camera set's outcome as a FilmValidation, for writeDiffImage
// (validation/report/diff_image.h). Throws std::invalid_argument without a camera set or frame.
FilmValidation cameraDiff(const RayCertification& r, const RaySet& rays);

struct TopologySummary {
    bool closed = false;
    uint64_t vertices = 0, edges = 0, boundaryEdges = 0, nonManifoldEdges = 0;
};
TopologySummary summarize(const MeshTopology& t);

struct CertifyReport : JudgedScene {
    std::string rays, hits;  // the files, as named
    bool primIds = true;
    bool manifest = false;
    uint64_t seed = 0;
    std::vector<std::string> notes;
    std::optional<TopologySummary> topology;  // triangle meshes
    RayCertification result;
    double referenceSeconds = 0.0, checkSeconds = 0.0, seconds = 0.0;

    bool passes() const { return result.passes(policy.maxAmbiguousRate); }
};

// Traces `rays` with Embree (robust mode) as the reference and certifies `ours` against it.
CertifyReport certifyTracer(const Scene& scene, const RaySet& rays, const HitArrays& ours,
                            const ValidationPolicy& policy);

}  // namespace oct
