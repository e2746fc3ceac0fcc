// octrace's C++ package façade (docs/PACKAGE.md): certify your own tracer's hits on your own
// arrays, as `octrace rays` and `octrace certify` do on files (docs/CERTIFY.md), through one
// small header. It includes standard headers only, so a project that links octrace::api
// compiles against this file alone and none of octrace's internals, and no exception type of
// theirs reaches it: every failure is an octrace::Error.
//
//   find_package(octrace 0.1 REQUIRED)
//   target_link_libraries(my_tracer PRIVATE octrace::api)
//
//   std::vector<float> tris = octrace::loadTriangles("teapot.obj");          // M x 9
//   octrace::StandardRays r = octrace::makeRays("teapot.obj");               // N x 8
//   ... trace r.rays with your tracer into t (N) and prim (N) ...
//   octrace::CertifyResult c =
//       octrace::certify("teapot.obj", r.rays.data(), r.count(), t.data(), prim.data(),
//                        r.manifestJson);
//   std::cout << c.summary;  // c.pass, c.outcome: "PASS", "FAIL" or "INCOMPLETE"
//
// Arrays are row-major float32 / int32, as the trace format's files hold them
// (docs/TRACE_FORMAT.md): a ray is ox oy oz dx dy dz tmin tmax, in the scene's units; a hit is
// its distance t along the ray (in units of |d|, +inf on a miss) and the primitive's id (-1 on
// a miss), the triangle's index in loadTriangles' order.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace octrace {

// Every failure of the functions below: a scene file that cannot be loaded, an option out of
// range, arrays of another length, a manifest that does not match the rays or the scene, too
// little memory. The message is octrace's one line (what, which value, what to do), as
// `octrace` prints it after "octrace: error: ".
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The triangles of a mesh as octrace numbers them: M x 9 floats, each triangle's v0 v1 v2
// (x y z each) in primitive id order, which is the file's face order after fan triangulation of
// polygons and the dropping of faces octrace refuses (zero area, bad indices; `octrace info`
// counts them). The same floats as `octrace rays SCENE --triangles T.npy` writes. A hit's
// primitive id is an index into these rows. Throws Error for a file that cannot be loaded, and
// for a point cloud (it has spheres, not triangles).
std::vector<float> loadTriangles(const std::string& scenePath);

// The standard ray sets of `octrace rays` (docs/CERTIFY.md, "The ray sets").
struct RayOptions {
    // Comma-separated set names (camera, shadow, around, inside, axis, edges, vertices,
    // grazing, tmin-tmax, slivers) or "all": every set the scene can make (`--set`).
    std::string sets = "all";
    uint64_t count = 30000;  // rays over the seeded sets together, at most 1e8 (`--count`)
    uint64_t seed = 1;       // seed of the seeded sets (`--seed`)
    int width = 256;         // the camera and shadow sets' image, pixels (`--size WxH`),
    int height = 256;        //   each side 1 to 16384; the camera framed as by `octrace rays`
    float radius = 0.0f;     // point clouds: the sphere radius; 0: octrace's rule (`--radius`)
};

struct StandardRays {
    std::vector<float> rays;   // N x 8: ox oy oz dx dy dz tmin tmax, the sets one after another
    std::string manifestJson;  // what the rows are (sets, seed, scene): `octrace rays`' R.json
    // What making them had to say: sets "all" left out, rows drawn again, targets unsealed,
    // faces the loader dropped (`octrace rays` prints them as "note").
    std::vector<std::string> notes;
    uint64_t count() const { return rays.size() / 8; }
};

// The rays and manifest `octrace rays SCENE --set SETS --count COUNT --seed SEED --size WxH`
// writes, byte for byte. Throws Error for a scene that cannot be loaded, an unknown set, a set
// named twice or one the scene cannot make (edges on a point cloud), an option out of range,
// or rays beyond the machine's memory.
StandardRays makeRays(const std::string& scenePath, const RayOptions& options = {});

// The policy of docs/VALIDATION.md, as `octrace certify`'s options set it; the defaults are
// octrace's. Each tolerance lies in [0, 1].
struct CertifyPolicy {
    double tTolerance = 1e-5;        // same hit when |dt| <= this x scene extent (`--t-tolerance`)
    double edgeTolerance = 2e-6;     // an edge or vertex configuration within this x extent
    double grazingCos = 1e-3;        // a grazing ray when |cos(ray, normal)| <= this
    double maxAmbiguousRate = 1e-3;  // correct FAILs above this rate over the non-adversarial sets
    uint64_t maxRechecks = UINT64_MAX;  // mismatches rechecked in double per set; the rest are
                                        //   unverified (INCOMPLETE). At least 1
    int worstCount = 16;                // findings listed per set in the report, at least 0
    // Which verdicts decide `pass` (`--require`): "correct" (no wrong answer), "watertight" (no
    // leak through a sealed edge or vertex) or "all".
    std::string require = "all";
    // How sets of one's own (names in a manifest that are not standard) are judged (`--query`):
    // "closest" hits, or "anyhit" (occlusion: any hit on the segment is right).
    std::string query = "closest";
};

struct CertifyResult {
    bool pass = false;       // outcome == "PASS"
    std::string outcome;     // the required verdicts combined: "PASS", "FAIL" or "INCOMPLETE"
    std::string correct;     // each verdict alone: "PASS", "FAIL", "INCOMPLETE" or "not tested"
    std::string watertight;  //   (watertight is not tested without edges, vertices or slivers)
    std::string summary;     // the text report `octrace certify` prints (lines ending in '\n')
    std::string json;        // the JSON report of `octrace certify --json` (docs/CERTIFY.md)
    // Per ray, as `octrace certify --verdicts` writes them (docs/CERTIFY.md; never renumbered):
    std::vector<uint8_t> classes;   // 0 agree, 1 tie, 2 ambiguous, 3 wrong, 4 unverified
    std::vector<uint32_t> reasons;  // bit i: reason i (0 edge_or_vertex, ..., 12 off_surface)
    std::vector<uint8_t> leaks;     // 0 sealed, 1 leak, 2 not a target, 3 unsealed, 4 unverified
};

// `octrace certify SCENE --rays R.npy --hits PREFIX` on arrays: judges every one of the `count`
// rays' hits against Embree and a double-precision truth, with the leak check, by `policy`.
//   rays: count x 8 floats; t: count floats; prim: count ids, or null to certify distances only
//   (`--no-prim`: a hit's primitive is inferred).
//   manifestJson: the manifest makeRays (or `octrace rays`) gave with these rays, or "" to judge
//   them as one set "all". With it the report is per set, the standard sets are rebuilt and
//   compared with the rays (so edited rays are refused) and the edges, vertices and slivers rows
//   get their leak check; the scene is loaded with its radius.
// Messages call the arrays "rays" and the manifest "rays.json". Throws Error for a scene that
// cannot be loaded, count 0, a null rays or t, a manifest that is not one or does not describe
// these rays on this scene, a policy value out of range, or too little memory. A faulty
// tracer's values (NaN, ids beyond the scene) are never an Error: they are wrong answers.
CertifyResult certify(const std::string& scenePath, const float* rays, uint64_t count,
                      const float* t, const int32_t* prim, const std::string& manifestJson = "",
                      const CertifyPolicy& policy = {});

}  // namespace octrace
