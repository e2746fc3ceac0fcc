// The standard ray sets of `octrace rays` (docs/CERTIFY.md) and of `octrace validate --rays`: the
// configurations image rays rarely meet and tracers get wrong. Each set is named; a ray file is
// its sets' rows one after another (RaySetRange), in the trace format of docs/TRACE_FORMAT.md.
//
//  camera    the render's pinhole rays, row-major (y * W + x), as makeFrame/primaryRay make them;
//  shadow    for each camera ray a reference tracer hits, the kernel's own shadow ray from that
//            hit (shadowQuery, core/render/kernel.h) when the surface faces the light: a
//            finite segment towards the light;
//  around    origins on a sphere of 1.5 x the scene's bounding radius, aimed at points uniform
//            in the scene's box;
//  inside    origins uniform in the octree's root cube, directions uniform on the sphere; one
//            in four has a finite tmax, uniform in [0, bounding radius];
//  axis      origins uniform in the root cube, directions +-x, +-y, +-z; every other one has
//            one other coordinate moved onto a node boundary plane of depth 1 to 3 (the same
//            float midpoints as childBox), so it runs inside a face shared by two nodes;
//  edges     aimed at a point of an edge shared by exactly two triangles (a parameter in
//            [0.2, 0.8] along it, the point computed in float as a tracer computes a hit
//            point), from the front side of the two triangles (the side their winding's normal
//            points to), at a distance of 1 to 3 times the longest side of the two triangles;
//  vertices  aimed at a vertex whose triangles close a fan around it, the same way;
//  grazing   through a point inside a triangle at |cos(ray, normal)| between 5e-7 and 3e-2;
//  tmin-tmax through a point inside a triangle at |cos| >= 0.2, in four variants by row: the
//            ray starts at the point (tmin 0); tmax is exactly the distance to the triangle's
//            plane; tmin is exactly that distance; tmax is one float below it;
//  slivers   on a slivers:N scene only (core/scene/slivers.h): aimed at a point of its square,
//            by row two in four uniform in the square, one on an interior edge (a parameter in
//            [0, 1], computed in float), one at an interior vertex; from above or below, at
//            |cos(ray, normal)| = u^2 for u uniform in [0.1, 1], 0.25 to 2 away. Kept when the
//            stored float ray meets the plane at least 1e-5 x the extent inside the square:
//            the target is that crossing (t in double), and every ray must hit.
//
// An edges or vertices ray is *sealed* when, for the ray as stored (the float row):
//  - seen along it, the two triangles of its edge (the fan of its vertex) cover a disc of radius
//    1e-5 x the scene's extent around the point where it passes (not the point aimed at: the
//    float origin lies up to half a spacing off, 0.25 at y = 4e6), and every one of them meets
//    the ray at |cos| >= 0.1 (edges) or 0.05 (vertices); and
//  - the double-precision truth (DoubleTracer::closest on the stored ray) hits one of those
//    triangles within the default t tolerance (1e-5 x extent) of the target's t: nothing in
//    front hides the target, and the float ray does meet it (far from the origin the rounded
//    origin moved 43 % of the rays off their targets).
// A tracer without cracks must then hit at or before the target (certify's leak check,
// certify.h), and a leak there is a crack at this edge or vertex. A direction that is not sealed
// is drawn again, up to 200 times; a target that never is keeps its last valid row, marked
// unsealed (RayTarget::sealed): certify judges the row but does not count it as checked for
// leaks. `notes` says how many.
//
// Every row is one `octrace trace` accepts (rayRowProblem, core/io/ray_file.h): a draw that
// breaks the row rule (a NaN direction where the origin rounded onto the target point) is drawn
// again and counted in `notes`, never written.
// A slivers ray is sealed by the square itself: flat, and covered by its triangles without a gap.
//
// Same seed, same bytes, on every machine: each seeded set draws from its own std::mt19937_64
// stream, seeded with splitmix64(seed + 0x9E3779B97F4A7C15 x (set id + 1)), using its raw output
// only (no std::*_distribution, whose output the standard leaves to the implementation), and
// no function whose rounding the platform chooses: directions by rejection from the cube,
// then +, -, x, / and sqrt (IEEE), under -ffp-contract=off. The camera set goes through
// makeFrame, which calls the platform's tanf/atanf/sinf; the shadow set depends on the
// reference tracer's camera hits. The seeded sets' count N is split as evenly as possible over
// them in the order given (the first ones get the remainder).
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

struct RaySet {
    std::vector<float> rays;           // N x 8: ox oy oz dx dy dz tmin tmax
    std::vector<RaySetRange> sets;     // contiguous, in file order, covering every row
    std::vector<RayTarget> targets;    // edges, vertices and slivers rows, ascending row
    std::optional<FrameParams> frame;  // when there is a camera or shadow set
    // What generating had to do, for the user: rows drawn again, targets left unsealed.
    std::vector<std::string> notes;
    // The mesh's targets when an edges or vertices set was made (shareable: RaySetSpec::mesh).
    std::shared_ptr<const MeshTargets> mesh;
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

struct RaySetSpec {
    std::vector<const RaySetDesc*> sets;  // rows of standardRaySets(), in file order, each once
    uint64_t count = 30000;               // rays over the seeded sets together
    uint64_t seed = 1;
    CameraOptions camera;  // camera and shadow sets
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
