#include "validation/ambiguity_bound.h"

#include <cmath>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "validation/certify.h"
#include "validation/rays/ray_manifest.h"

namespace oct {

double ambiguousSlack(const std::string& name) {
    const RaySetDesc* d = findRaySet(name);
    return d ? d->ambiguousSlack : kAmbiguousSlack;
}

std::optional<uint64_t> ambiguousLimit(uint64_t rows, std::optional<uint64_t> expected,
                                       bool adversarial, const ValidationPolicy& policy,
                                       double slack) {
    if (expected)
        return *expected + uint64_t(std::ceil(slack * double(*expected) +
                                              policy.maxAmbiguousRate * double(rows)));
    if (adversarial) return uint64_t(std::floor(kAdversarialAmbiguousShare * double(rows)));
    return std::nullopt;
}

bool baselineApplies(const AmbiguityBaseline& b, const ValidationPolicy& p) {
    return b.tTolerance == p.tTolerance && b.edgeTolerance == p.edgeTolerance &&
           b.grazingCos == p.grazingCos;
}

AmbiguityBaseline measureAmbiguityBaseline(const HitClassifier& classifier, const RaySet& rays) {
    const Scene& scene = classifier.scene();
    const LayoutDesc& layout = findLayout(kDefaultLayout);
    const BuiltScene built = buildScene(scene, layout, LayoutOptions{});
    HitArrays ours;
    ours.t.resize(rays.count());
    ours.prim.resize(rays.count());
    traceWith(hostBackend(), built,
              RayBatchView{rays.rays.data(), ours.t.data(), ours.prim.data(), rays.count()});
    // The counts do not depend on a bound (a baseline the rays may carry already).
    const CertifyReport rep = certifyTracer(classifier, rays, ours);
    const ValidationPolicy& p = classifier.policy();
    AmbiguityBaseline b;
    b.tracer = std::string("octrace ") + octraceVersion() + " " + layout.name + " (" +
               hostBackend().name + ")";
    b.tTolerance = p.tTolerance;
    b.edgeTolerance = p.edgeTolerance;
    b.grazingCos = p.grazingCos;
    for (const SetCertification& s : rep.result.sets) b.ambiguous.push_back(s.ambiguousCounted);
    return b;
}

}  // namespace oct
