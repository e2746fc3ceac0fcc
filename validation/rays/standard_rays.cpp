#include "validation/rays/standard_rays.h"

#include <algorithm>
#include <memory>

#include "backends/backend_list.h"
#include "core/io/name_list.h"
#include "core/system/resources.h"
#include "validation/ambiguity_bound.h"
#include "validation/policy/hit_check.h"

namespace oct {

std::vector<const RaySetDesc*> chooseRaySets(const std::string& text, const Scene& scene,
                                             std::vector<std::string>& notes) {
    std::vector<const RaySetDesc*> listed;
    std::vector<bool> named;  // given by name, not by "all"
    for (const std::string& name : splitList(text)) {
        if (name == "all") {
            for (const RaySetDesc& kind : standardRaySets())
                if (std::find(listed.begin(), listed.end(), &kind) == listed.end()) {
                    listed.push_back(&kind);
                    named.push_back(false);
                }
            continue;
        }
        const RaySetDesc* k = findRaySet(name);
        if (!k) throw RaySetChoiceError("unknown set '" + name + "' (" + raySetNames() + ", all)");
        if (std::find(listed.begin(), listed.end(), k) != listed.end())
            throw RaySetChoiceError("'" + name + "' is named twice");
        listed.push_back(k);
        named.push_back(true);
    }
    const std::vector<std::string> why = raySetsUnavailable(scene, listed);
    std::vector<const RaySetDesc*> out;
    for (size_t i = 0; i < listed.size(); ++i) {
        if (why[i].empty())
            out.push_back(listed[i]);
        else if (named[i])
            throw RaySetChoiceError(std::string(listed[i]->name) + ": " + why[i] +
                                    " (leave the set out, or use all)");
        else
            notes.push_back(std::string("set ") + listed[i]->name + " left out: " + why[i]);
    }
    if (out.empty())
        throw RaySetChoiceError("'" + text + "' names no set (" + raySetNames() + ", all)");
    return out;
}

namespace {

// The rows `spec` makes: each seeded set's share, a camera-made set's pixels.
uint64_t rowCount(const RaySetSpec& spec) {
    const uint64_t pixels =
        uint64_t(std::max(spec.camera.width, 0)) * uint64_t(std::max(spec.camera.height, 0));
    uint64_t rows = 0;
    for (const RaySetDesc* k : spec.sets)
        rows = saturatingAdd(rows, k->seeded ? seededShare(spec, *k) : pixels);
    return rows;
}

}  // namespace

StandardRays makeStandardRays(const Scene& scene, const RaySetSpec& given, const std::string& what,
                              const std::string& advice) {
    // Before a row is drawn: the sets' memory against the machine's (core/system/resources.h).
    checkMemory(
        saturatingAdd(raySetPeakBytes(given), saturatingMul(rowCount(given), kBaselineBytesPerRow)),
        what, advice);
    // The default policy's classifier: its double truth seals the targets, and it judges
    // octrace's own answers for the baseline.
    const HitClassifier classifier(scene, ValidationPolicy{});
    RaySetSpec spec = given;
    if (!spec.truth) spec.truth = &classifier.truth();
    // The shadow set starts at the reference's camera hits: the backend list's reference.
    std::unique_ptr<SceneTracer> reference;
    const BuiltScene bare = bareScene(scene);
    if (std::any_of(spec.sets.begin(), spec.sets.end(),
                    [](const RaySetDesc* k) { return k->needsReference; }))
        reference = referenceBackend().prepare(bare);
    TraceBatch trace;
    if (reference) trace = [&reference](RayBatchView b) { reference->trace(b); };
    StandardRays out;
    out.rays = makeRaySet(scene, spec, trace);
    // What octrace's kernel scores on these rows, for certify's per-set bound: measured here,
    // by the build that makes the rays, never by the one that certifies (ambiguity_bound.h).
    out.rays.baseline = measureAmbiguityBaseline(classifier, out.rays);
    out.manifest = describeRaySet(scene, spec, out.rays);
    return out;
}

}  // namespace oct
