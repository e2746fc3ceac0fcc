// `octrace validate` as a library call: each tracer under test (a layout on a backend, given as
// two callables that fill a Film and a ray batch) against Embree, per pixel (primary and
// shadow rays) and per ray of the seeded ray sets, plus the replication check of the canonical
// octree. The per-ray check is `octrace certify`'s (certify.h): validate generates our hits for
// the standard sets around, inside and axis, then certifies them. The callables keep validation
// away from the layouts' insides; the CLI builds them from the backend list's SceneTracers
// (backends/backend_list.h), the tests from the OpenMP launcher or a deliberately corrupted
// layout.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"
#include "validation/certify.h"
#include "validation/exact/box_contract.h"
#include "validation/exact/layout_structure.h"
#include "validation/exact/replication.h"
#include "validation/policy/hit_validation.h"
#include "validation/policy/judged_scene.h"
#include "validation/policy/ray_definitions.h"

namespace oct {

struct TracerUnderTest {
    std::string layout;  // names for the report
    std::string backend;
    std::function<void(const FrameParams&, Film&)> render;  // fills (and sizes) the Film
    std::function<void(RayBatchView)> trace;                // closest hits of a ray batch
    // The layout's nodes by Morton key, as its traversal finds them (layout_structure.h);
    // empty for a layout without an octree (exhaustive): no structural check.
    NodeLookupFn lookup;
};

// Work shared among processes (MPI ranks: `octrace validate` under mpirun fills it from dist/).
// Every process calls validateScene alike and computes the same report: `render` runs a render
// call by image rows and leaves the whole Film on every process, `trace` a trace call by ray
// rows leaving every answer on every process, and `rows(n)` names the rows of n seeded rays whose
// per-ray check (the rechecks) this process does (certify.h, RowShare). An empty member: this
// process does that work alone. The tracers under test come shared already (the caller's).
struct WorkShare {
    using RenderCall = std::function<void(const FrameParams&, Film&)>;
    using TraceCall = std::function<void(RayBatchView)>;
    std::function<void(const FrameParams&, Film&, const RenderCall&)> render;
    std::function<void(RayBatchView, const TraceCall&)> trace;
    std::function<RowShare(uint64_t rows)> rows;
};

struct ValidateOptions {
    ValidationPolicy policy;
    CameraOptions camera = defaultValidateCamera();
    uint64_t rays = 30000;  // seeded rays (ray_sets.h); 0 for none
    uint64_t seed = 1;
    bool replication = true;  // needs the canonical octree
    // Rays of the box-test contract (box_contract.h) on the canonical octree's boxes; 0: none.
    uint64_t boxContractRays = 20000;
    // A second frame seen and lit from the centre of the scene's box (docs/VALIDATION.md, "The
    // inside view"): every visible surface faces the light, and shadow rays have the geometry
    // behind the eye beyond their end (the default light lies outside the scene, so an any-hit
    // query ignoring tmax passes unnoticed there).
    bool lightInside = true;
    WorkShare share;  // empty: this process does all the work

    static CameraOptions defaultValidateCamera() {
        CameraOptions c;
        c.width = c.height = 256;
        return c;
    }
};

struct RunReport {
    std::string layout, backend;
    FilmValidation film;
    std::optional<FilmValidation> lightInside;  // the inside view
    std::optional<StructureReport> structure;   // null without a lookup (no octree)
    RayCertification rays;
    double renderSeconds = 0.0, traceSeconds = 0.0, checkSeconds = 0.0;

    bool passes(double maxAmbiguousRate) const;    // every run check (validation/checks/check.h)
    bool complete(double maxAmbiguousRate) const;  // nothing left unverified by a recheck cap
    uint64_t wrong() const {
        return film.primary.wrong + film.shadow.wrong + rays.all.wrong +
               (lightInside ? lightInside->primary.wrong + lightInside->shadow.wrong : 0);
    }
    uint64_t ambiguous() const {
        return film.primary.ambiguous + film.shadow.ambiguous + rays.all.ambiguous +
               (lightInside ? lightInside->primary.ambiguous + lightInside->shadow.ambiguous : 0);
    }
};

struct ValidationReport : JudgedScene {
    int width = 0, height = 0;
    uint64_t rayCount = 0, seed = 0;
    std::vector<RaySetRange> raySets;  // around, inside, axis
    double referenceSeconds = 0.0;     // Embree: build, frame and rays
    std::vector<RunReport> runs;
    std::optional<ReplicationReport> replication;
    std::optional<BoxContractReport> boxContract;  // null without the canonical octree
    // The kernel's own rays against their definitions in double (policy/ray_definitions.h).
    std::optional<RayDefinitionReport> camera, shadowRays, rayScaling;
    double seconds = 0.0;

    uint64_t wrong() const;
    uint64_t ambiguous() const;
    bool passes() const;    // every run, every scene check
    bool complete() const;  // nothing left unverified by a recheck cap
};

// The inside view's camera (docs/VALIDATION.md, "The inside view"): `camera`'s size and field
// of view, the eye at the centre of the scene's box looking along +z, the light 1% of the
// extent above the eye, so that shadow rays do not retrace the primary rays exactly.
CameraOptions insideViewCamera(const Scene& scene, const CameraOptions& camera);

// About the most memory validateScene holds at once for `tracers` tracers, beyond the scene and
// its layouts: the reference's Films and one run's (each view), every run's per-pixel classes
// and |dt| (kept for the diff image), the seeded rays and their answers (the reference's and
// one run's). `octrace validate` checks it against the machine before rendering.
uint64_t validatePeakBytes(const ValidateOptions& o, size_t tracers);

// Validates every tracer against Embree on `scene`. `canonical` (may be null) is the octree the
// layouts were converted from, for the replication check. Throws on unusable options.
ValidationReport validateScene(const Scene& scene, const std::vector<TracerUnderTest>& tracers,
                               const Octree* canonical, const ValidateOptions& options);

}  // namespace oct
