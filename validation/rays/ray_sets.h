// The standard ray sets of `octrace rays` and `octrace validate --rays`: the configurations
// image rays rarely meet and tracers get wrong, one row each in standardRaySets(). A ray file
// is its sets' rows one after another (RaySetRange), in the trace format (docs/TRACE_FORMAT.md).
// Invariants: every row is one `octrace trace` accepts (rayRowProblem, core/io/ray_file.h); an
// edges or vertices target counts for the leak check only when sealed as stored in float; the
// same seed gives the same bytes on every machine. What each set holds, what "sealed" means and
// how the streams are seeded: docs/CERTIFY.md, "The ray sets".
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/render/frame.h"
#include "core/render/kernel.h"
#include "core/scene/mesh_topology.h"
#include "core/scene/scene.h"
#include "validation/policy/ray_definitions.h"

namespace oct {

struct RaySet;
struct RaySetContext;  // what the generators share: the scene, its boxes, topology (ray_sets.cpp)
struct RaySetRng;      // one set's random stream (ray_sets.cpp)

// One standard set: a row of the table standardRaySets() returns. Adding a set is its generator
// in ray_sets.cpp and one row there, with a new id.
struct RaySetDesc {
    uint8_t id;           // seeds the set's random stream: never renumber
    const char* name;     // "camera", ..., "slivers"
    bool seeded;          // drawn from the seed; false: made from the camera (camera, shadow)
    bool needsTriangles;  // edges, vertices, grazing, tmin-tmax, slivers
    bool needsSlivers;    // slivers: a slivers:N scene (core/scene/slivers.h)
    bool needsReference;  // starts at a reference tracer's camera hits (shadow): not rebuilt
    // Built from edge cases on purpose (all but the first five): nearly every ray is
    // touchy, so ambiguous answers are expected there and do not count against the rate.
    bool adversarial;
    // Appends the set's rows (`n`: the seeded sets' share; the camera sets make their own count).
    void (*generate)(RaySetContext& c, RaySetRng& rng, uint64_t n, RaySet& out);
    // An occlusion query (shadow): any hit on the segment is right, not only the closest.
    bool anyHit = false;
    // How much more often than octrace's kernel on the same rows another correct tracer may
    // answer ambiguously (validation/ambiguity_bound.h): a quarter, or the double on grazing
    // rays, where t is ill-conditioned by up to 1/|cos| and a float test less exact than
    // octrace's differs from the reference more often (measured: docs/CERTIFY.md).
    double ambiguousSlack = 0.25;
};

const std::vector<RaySetDesc>& standardRaySets();       // in `--set all` order
const RaySetDesc* findRaySet(const std::string& name);  // null for another name
std::string raySetNames();                              // "camera, shadow, ..., slivers"
// Why set k cannot be made on `scene` ("needs a triangle mesh", "needs a slivers:N scene"), or ""
// when it can: `--set all` leaves such sets out, naming them.
std::string raySetMisfit(const RaySetDesc& k, const Scene& scene);

// Rows [begin, begin + count) of a ray file belong to the set `name`.
struct RaySetRange {
    std::string name;
    uint64_t begin = 0, count = 0;
};

// The target of an edges, vertices or slivers ray, for the leak check.
struct RayTarget {
    uint64_t row = 0;
    // The ray parameter nearest to the target point (double, float ray); slivers: where the
    // float ray meets the square's plane.
    double t = 0.0;
    // Welded vertex ids (mesh_topology.h): the edge a < b; a vertex a == b. A slivers ray aimed
    // inside a triangle names the triangle's edge nearest to its point.
    uint32_t a = 0, b = 0;
    Vec3 pa{}, pb{};  // their positions
    // The target's own triangles (primitive ids, ascending): the edge's two, the vertex's fan.
    std::vector<uint32_t> triangles;
    // Sealed as the header says: the truth hits one of `triangles` at t, so a crack-free tracer
    // hits at or before t. False: no draw sealed it; the row tests nothing about the target and
    // must not count as checked for leaks.
    bool sealed = true;
    bool vertex() const { return a == b; }
};

class DoubleTracer;  // validation/policy/double_tracer.h
struct MeshTargets;  // below

// What octrace's own kernel scored on a ray file's rows when they were made (`octrace rays`,
// manifest field `expected_ambiguous`): per set, its count of ambiguous answers against the
// reference, under the tolerances named. certify bounds each set's ambiguous count by it
// (validation/certify.h, ambiguousLimit): a tracer that turns right answers into excused ones
// (a hit at a range end dropped) shows as a count above it, set by set. Recorded when the rays
// are made, by the build that made them, so that a faulty build certifying its own answers
// cannot raise its own bound.
struct AmbiguityBaseline {
    std::string tracer;                                              // "octrace 0.1.0 linear (cpu)"
    double tTolerance = 0.0, edgeTolerance = 0.0, grazingCos = 0.0;  // the policy it was judged by
    std::vector<uint64_t> ambiguous;  // per set, in RaySet::sets order
};

struct RaySet {
    std::vector<float> rays;           // N x 8: ox oy oz dx dy dz tmin tmax
    std::vector<RaySetRange> sets;     // contiguous, in file order, covering every row
    std::vector<RayTarget> targets;    // edges, vertices and slivers rows, ascending row
    std::optional<FrameParams> frame;  // when there is a camera or shadow set
    // What generating had to do, for the user: rows drawn again, targets left unsealed.
    std::vector<std::string> notes;
    // The mesh's targets when an edges or vertices set was made (shareable: RaySetSpec::mesh).
    std::shared_ptr<const MeshTargets> mesh;
    // Made by octrace rays (makeStandardRays) or read from its manifest; absent otherwise.
    std::optional<AmbiguityBaseline> baseline;
    // Read from a file with a camera set (raySetFromFile): its rows against the pinhole camera's
    // definition in double (policy/ray_definitions.h), which shares no code with the camera that
    // made them; a fault there makes and rebuilds the same rows, so only this sees it.
    std::optional<RayDefinitionReport> cameraRows;
    uint64_t count() const { return rays.size() / 8; }
    Ray ray(uint64_t i) const {
        const float* r = &rays[8 * i];
        return {{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, r[6], r[7]};
    }
    const RaySetRange* find(const std::string& name) const;
};

// What the edges and vertices sets draw from, made once per mesh (meshTargets) and shared
// between makeRaySet calls and with certify's report: the topology, the edges two triangles
// share, and the vertices whose triangles close a fan, with each fan's link.
struct MeshTargets {
    MeshTopology topology;
    std::vector<uint32_t> interiorEdges, fanVertices;
    std::vector<std::vector<uint32_t>> links;  // per fan vertex
};
std::shared_ptr<const MeshTargets> meshTargets(const Scene& scene);

// The camera and shadow sets' image when none is given: 256x256, render's framing and light.
// `octrace rays` and octrace.rays both take their defaults from RaySetSpec{}, so that the same
// options (or none) give the same rows through either (issue 39: a brace-initialised copy of
// this in the Python module filled CameraOptions::from and left the size at render's 512x512).
constexpr int kRaysImageSide = 256;
inline CameraOptions raysCamera() {
    CameraOptions c;
    c.width = c.height = kRaysImageSide;
    return c;
}

struct RaySetSpec {
    std::vector<const RaySetDesc*> sets;  // rows of standardRaySets(), in file order, each once
    uint64_t count = 30000;               // rays over the seeded sets together
    uint64_t seed = 1;
    CameraOptions camera = raysCamera();  // camera and shadow sets
    // Optional, to share what one scene's sets need between calls (made when absent): the
    // mesh's targets, and a double truth of the scene to seal them with (certify's classifier's:
    // its closest hits do not depend on its tolerances).
    std::shared_ptr<const MeshTargets> mesh;
    const DoubleTracer* truth = nullptr;
};

// About the most memory makeRaySet holds at once for `spec`, in bytes: every set's rows while
// the sets are drawn in parallel (the camera and shadow sets a row per pixel each, the shadow
// set's own camera rays and hits besides), the targets of edges, vertices and slivers, and the
// joined array. `octrace rays` checks it against the machine before drawing a row
// (core/system/resources.h). Saturates instead of overflowing.
uint64_t raySetPeakBytes(const RaySetSpec& spec);

// The rows of one seeded set's share, as the spec splits count.
uint64_t seededShare(const RaySetSpec& spec, const RaySetDesc& k);

// Closest hits of a batch by a reference tracer: the shadow set needs the camera hits (the CLI
// passes Embree from the backend list). May be empty when there is no shadow set.
using TraceBatch = std::function<void(RayBatchView)>;

// For each of `sets`, why it cannot be made on `scene`, or "" when it can: one that does not fit
// the scene (raySetMisfit: a triangle-only set on a point cloud, the slivers set elsewhere than
// on a slivers scene), edges on a mesh with no edge shared by exactly two triangles (a single
// triangle), vertices with no vertex whose triangles close a fan (a quad). `octrace rays --set
// all` leaves those out with a note; a set named explicitly is refused with the reason.
std::vector<std::string> raySetsUnavailable(const Scene& scene,
                                            const std::vector<const RaySetDesc*>& sets);

// Throws std::invalid_argument for a null or repeated set, a set that does not fit the scene
// (raySetMisfit), a shadow set without a reference, or a mesh offering no target (no shared
// edge, no closed fan).
RaySet makeRaySet(const Scene& scene, const RaySetSpec& spec, const TraceBatch& reference = {});

// validate's seeded sets: around, inside, axis, N split evenly.
RaySet makeValidationRays(const Scene& scene, uint64_t n, uint64_t seed);

// 64-bit FNV-1a of bytes (the rays' float32 little-endian bytes: R.npy's data section).
uint64_t fnv1a64(const void* data, size_t bytes);
std::string hex64(uint64_t v);  // 16 lowercase hex digits

}  // namespace oct
