#include "validation/certify_run.h"

#include <chrono>
#include <stdexcept>

#include "core/io/ray_file.h"

namespace oct {

CertifyRun certifyRows(const Scene& scene, std::vector<float> rows, const HitArrays& hits,
                       const std::optional<RayManifest>& manifest, const CertifyRunOptions& o) {
    if (rows.size() % 8 != 0)
        throw std::invalid_argument(o.raysName + ": " + std::to_string(rows.size()) +
                                    " floats are not rows of 8 (ox oy oz dx dy dz tmin tmax)");
    const uint64_t n = rows.size() / 8;
    if (n == 0)
        throw std::invalid_argument(o.raysName +
                                    " holds no rays: nothing to certify (make some with "
                                    "octrace rays)");
    if (hits.t.size() != n || (hits.primIds && hits.prim.size() != n))
        throw std::invalid_argument(
            "the hits hold " + std::to_string(hits.t.size()) + " distances and " +
            std::to_string(hits.primIds ? hits.prim.size() : n) + " primitive ids for " +
            std::to_string(n) + " rays in " + o.raysName + "; give one of each per ray");
    // trace's rule on every row (the CLI's reader applies it to a file; arrays from the Python
    // module and the façade come here unchecked): a negative tmin would reach Embree's assert.
    checkRayRows(rows.data(), n, o.raysName);
    if (manifest) {
        checkManifestRows(*manifest, n, o.raysName);
        checkSameScene(*manifest, scene, o.raysName);  // before building anything
    }
    using Clock = std::chrono::steady_clock;
    auto clock = Clock::now();
    auto lap = [&clock] {
        const auto now = Clock::now();
        const double s = std::chrono::duration<double>(now - clock).count();
        clock = now;
        return s;
    };
    const auto start = clock;
    CertifyRun run;
    // One double truth of the scene (the classifier's) seals the rebuilt targets and rechecks
    // the answers.
    const HitClassifier classifier(scene, o.policy);
    run.truthSeconds = lap();
    std::vector<std::string> notes;
    run.rays =
        raySetFromFile(scene, std::move(rows), manifest, o.raysName, notes, &classifier.truth());
    run.setsSeconds = lap();
    run.report = certifyTracer(classifier, run.rays, hits, o.query);
    run.report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    run.report.require = o.require;
    run.report.rays = o.raysName;
    run.report.manifest = manifest.has_value();
    run.report.seed = manifest ? manifest->seed : 0;
    run.report.notes = std::move(notes);
    return run;
}

}  // namespace oct
