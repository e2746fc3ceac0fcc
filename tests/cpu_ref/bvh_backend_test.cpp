// The bvh backend (cpu_ref/bvh_backend.h) against the host backend's octree layouts: the same
// triangle test and nearest-hit rule, so every ray must get the same t and primitive to the
// bit; only which triangles are tested differs. The rays: every standard set each committed
// mesh can make (camera, shadow, around, inside, axis, edges, vertices, grazing, tmin-tmax;
// slivers on a slivers scene), and rays made here for what a BVH walk can get wrong: direction
// components that are exactly zero, origins inside, and segments that end or start exactly at
// a hit or one float step short of it. A walk that loses a subtree (its far child, say) fails
// here.
#include "cpu_ref/bvh_backend.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/exhaustive.h"
#include "core/render/frame.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "tests/cpu_ref/standard_rays.h"
#include "tests/paths.h"
#include "validation/rays/ray_sets.h"

namespace oct {
namespace {

const BackendDesc& bvh() {
    const BackendDesc* b = findBackend(bvhBackend().name);
    EXPECT_NE(b, nullptr) << "the bvh backend is not in the backend list";
    return b ? *b : hostBackend();
}

using Hits = octtest::TracedHits;

Hits traceBvh(const Scene& scene, const std::vector<float>& rays) {
    const BuiltScene bare = bareScene(scene);
    return octtest::traceAll(*bvh().prepare(bare), rays);
}

Hits traceOctree(const Scene& scene, const LayoutDesc& layout, const std::vector<float>& rays) {
    const BuiltScene built = buildScene(scene, layout, LayoutOptions{});
    return octtest::traceAll(*hostBackend().prepare(built), rays);
}

uint32_t bitsOf(float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// The rows where the BVH and an octree layout answer differently, by why (a row of none of the
// three kinds is a wrong answer):
//  - tie: the same t, a different primitive, which the BVH's primitive alone also hits at that
//    t. Two triangles hit at the same float t (the two sides of an edge) are kept by the lower
//    id only when met lower id first, as in one octree leaf; intersectTriangle's range test
//    against the closest t so far may refuse the other at the same t (t * det rounds);
//  - outside its box: the octree's hit point lies outside its triangle's own box, which a
//    tight box cannot hold: a ray nearly in the triangle's plane whose edge tests passed in
//    float, while its t, from the plane, lands off the triangle (docs/CERTIFY.md: grazing
//    rays are ambiguous);
//  - octree culled: the BVH answers what exhaustive tracing answers, and the octree does not
//    (a segment ending exactly at a hit that lies on a cell's face, culled by the cell's
//    rounded interval).
struct Disagreement {
    uint64_t rows = 0, ties = 0, outsideItsBox = 0, octreeCulled = 0, wrong = 0;
    std::string first;  // the first wrong rows, described
};

Hit traceOneRow(const BvhView& bvhView, const PrimitivesView& prims, const float* row,
                bool exhaustive) {
    int e = 0;
    const Ray ray = scaledRay(row, e);
    TraceCost cost{0, 0};
    Hit h =
        exhaustive ? closestHit(ExhaustiveView{prims}, ray, cost) : closestHit(bvhView, ray, cost);
    h.t = unscaledT(h.t, e);
    return h;
}

bool hitsAloneAt(const PrimitivesView& prims, const float* row, int32_t prim, float t) {
    int e = 0;
    const Ray ray = scaledRay(row, e);
    float tHit = 0.0f;
    const bool hit = intersectTriangle(makeShearedRay(ray.org, ray.dir), prims.tris[prim], ray.tmin,
                                       ray.tmax, tHit);
    return hit && bitsOf(unscaledT(tHit, e)) == bitsOf(t);
}

bool pointOutsideItsBox(const Scene& scene, const float* row, int32_t prim, float t) {
    if (prim < 0) return false;
    const Triangle& tri = scene.triangles[prim];
    Aabb box = emptyAabb();
    for (Vec3 v : {tri.v0, tri.v1, tri.v2}) grow(box, v);
    const Vec3 p = Vec3{row[0], row[1], row[2]} + Vec3{row[3], row[4], row[5]} * t;
    const Vec3 slack = makeVec3(1e-5f * length(box.extent()) + 1e-6f);
    return !Aabb{box.lo - slack, box.hi + slack}.contains(p);
}

Disagreement compare(const Scene& scene, const BinaryBvh& bvhTree, const Hits& bvhHits,
                     const Hits& octree, const std::vector<float>& rays) {
    Disagreement d;
    const PrimitivesView prims = primitivesView(scene);
    for (size_t i = 0; i < bvhHits.t.size(); ++i) {
        if (bitsOf(bvhHits.t[i]) == bitsOf(octree.t[i]) && bvhHits.prim[i] == octree.prim[i])
            continue;
        ++d.rows;
        const float* r = &rays[8 * i];
        if (bitsOf(bvhHits.t[i]) == bitsOf(octree.t[i]) && bvhHits.prim[i] >= 0 &&
            hitsAloneAt(prims, r, bvhHits.prim[i], bvhHits.t[i])) {
            ++d.ties;
            continue;
        }
        if (pointOutsideItsBox(scene, r, octree.prim[i], octree.t[i])) {
            ++d.outsideItsBox;
            continue;
        }
        const Hit all = traceOneRow(bvhTree.view(), prims, r, true);
        if (bitsOf(all.t) == bitsOf(bvhHits.t[i]) && all.prim == bvhHits.prim[i]) {
            ++d.octreeCulled;
            continue;
        }
        if (++d.wrong > 5) continue;
        char line[400];
        std::snprintf(line, sizeof line,
                      "  row %zu (%a %a %a -> %a %a %a, [%a, %a]): bvh t=%a prim %d, octree t=%a "
                      "prim %d, exhaustive t=%a prim %d\n",
                      i, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], bvhHits.t[i],
                      bvhHits.prim[i], octree.t[i], octree.prim[i], all.t, all.prim);
        d.first += line;
    }
    return d;
}

// At most this share of the rows may differ (by the kinds above): ties are a few rays in 10^4
// on meshes of coplanar pairs (the Cornell box), and segments made to end exactly at a hit
// are where rounding decides.
constexpr double kFewRows = 1e-3;
constexpr double kFewEndRows = 3e-3;

void appendRay(std::vector<float>& rays, Vec3 o, Vec3 d, float tmin, float tmax) {
    rays.insert(rays.end(), {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax});
}

// Rays whose direction has one, two or no zero components (the slab test's parallel case on
// every axis), from a grid of origins around and inside the scene's box: the 26 directions of
// a cube's faces, edges and corners, from 5 x 5 x 5 origins spanning the box and a margin.
std::vector<float> axisAndInsideRays(const Scene& scene) {
    const Aabb b = scene.bounds();
    const Vec3 lo = b.lo - b.extent() * 0.1f, span = b.extent() * 1.2f;
    std::vector<float> rays;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) {
                const Vec3 o = lo + span * Vec3{i / 4.0f, j / 4.0f, k / 4.0f};
                for (int dx = -1; dx <= 1; ++dx)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dz = -1; dz <= 1; ++dz)
                            if (dx || dy || dz)
                                appendRay(rays, o, Vec3{float(dx), float(dy), float(dz)}, 0.0f,
                                          INFINITY);
            }
    return rays;
}

// For each ray that hits at t: the segment ending exactly at t (a hit at tmax counts), one
// float step short of it, the point [t, t], and the segment starting one step past it (the next
// surface behind, if any). Where the two structures' pruning by the closest hit so far could
// differ, it is at these ends.
std::vector<float> rangeEndRays(const std::vector<float>& rays, const Hits& hits) {
    std::vector<float> out;
    for (size_t i = 0; i < hits.t.size(); ++i) {
        if (hits.prim[i] < 0) continue;
        const float* r = &rays[8 * i];
        const Vec3 o{r[0], r[1], r[2]}, d{r[3], r[4], r[5]};
        const float t = hits.t[i];
        appendRay(out, o, d, r[6], t);
        if (t > r[6]) appendRay(out, o, d, r[6], std::nextafter(t, 0.0f));
        appendRay(out, o, d, t, t);
        appendRay(out, o, d, std::nextafter(t, INFINITY), INFINITY);
    }
    return out;
}

// Every octree layout's answers against the BVH's on `rays`: the same t and primitive to the
// bit, or a disagreement of one of Disagreement's kinds, on at most `allowed` of the rows.
void expectSameAsOctrees(const Scene& scene, const std::vector<float>& rays,
                         const std::string& what, double allowed) {
    const BinaryBvh tree(scene);
    const Hits mine = traceBvh(scene, rays);
    uint64_t hits = 0;
    for (int32_t p : mine.prim) hits += p >= 0;
    const uint64_t n = rays.size() / 8;
    for (const LayoutDesc& l : layouts()) {
        if (!l.usesOctree) continue;
        const Disagreement d = compare(scene, tree, mine, traceOctree(scene, l, rays), rays);
        EXPECT_EQ(d.wrong, 0u) << what << ": " << d.wrong << " of " << n
                               << " rays answered differently from the " << l.name
                               << " layout, not a tie, not outside the triangle's box, and not "
                                  "exhaustive tracing's answer\n"
                               << d.first;
        EXPECT_LE(double(d.rows), allowed * double(n))
            << what << ", against " << l.name << ": " << d.ties << " ties, " << d.outsideItsBox
            << " hits outside their triangle's box, " << d.octreeCulled
            << " culled by the octree, of " << n << " rays";
        if (d.rows > 0)
            std::printf(
                "%s, against %s: %llu ties, %llu outside their box, %llu octree culled, of "
                "%llu rays\n",
                what.c_str(), l.name, (unsigned long long)d.ties,
                (unsigned long long)d.outsideItsBox, (unsigned long long)d.octreeCulled,
                (unsigned long long)n);
    }
    // Not a vacuous agreement: most sets hit something.
    EXPECT_GT(hits, 0u) << what;
}

void expectSameAnswersOn(const Scene& scene, const std::string& name) {
    const std::vector<float> standard = octtest::standardRays(scene);
    expectSameAsOctrees(scene, standard, name + ", the standard ray sets", kFewRows);
    const std::vector<float> axis = axisAndInsideRays(scene);
    expectSameAsOctrees(scene, axis, name + ", axis-parallel and inside rays", kFewRows);
    const BuiltScene built = buildScene(scene, findLayout("compact"), LayoutOptions{});
    const std::unique_ptr<SceneTracer> host = hostBackend().prepare(built);
    std::vector<float> both = standard;
    both.insert(both.end(), axis.begin(), axis.end());
    const std::vector<float> ends = rangeEndRays(both, octtest::traceAll(*host, both));
    expectSameAsOctrees(scene, ends, name + ", segments ending at a hit", kFewEndRows);
}

// One test a committed mesh, so that CTest runs them side by side.
struct BvhOnMesh : ::testing::TestWithParam<std::string> {};

TEST_P(BvhOnMesh, SameHitsAsTheOctreeLayouts) {
    expectSameAnswersOn(loadScene(octtest::meshPath(GetParam())), GetParam());
}

std::string meshTestName(const ::testing::TestParamInfo<std::string>& info) {
    std::string name;
    for (char c : info.param) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(CommittedMeshes, BvhOnMesh,
                         ::testing::ValuesIn(octtest::committedMeshes()), meshTestName);

// Sliver triangles sharing edges, where every ray aimed inside the square must hit: a walk that
// drops a subtree shows as a leak.
TEST(BvhBackend, SameHitsAsTheOctreeLayoutsOnSlivers) {
    expectSameAnswersOn(loadScene("slivers:3000:7"), "slivers:3000:7");
}

TEST(BvhBackend, SameHitsOnTheBunnyWhenFetched) {
    const std::string path = octtest::kMeshes + "/cache/bunny.obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "meshes/fetch has not fetched " << path;
    const Scene scene = loadScene(path);
    expectSameAsOctrees(scene, axisAndInsideRays(scene), "bunny, axis-parallel and inside rays",
                        kFewRows);
    expectSameAsOctrees(scene, octtest::standardRays(scene), "bunny, the standard ray sets",
                        kFewRows);
}

// A frame through the BVH: camera rays by closestHit, shadow rays by anyHit, then Phong; every
// pixel's t, primitive, shadow outcome and colour the compact layout's to the bit.
TEST(BvhBackend, FramesEqualTheOctreeKernelsBitForBit) {
    for (const std::string& mesh : {std::string("teapot.obj"), std::string("cornell_box.obj")}) {
        SCOPED_TRACE(mesh);
        const Scene scene = loadScene(octtest::meshPath(mesh));
        CameraOptions cam;
        cam.width = cam.height = 128;
        const FrameParams frame = makeFrame(scene.bounds(), cam);
        Film fromBvh, fromOctree;
        renderWith(bvh(), bareScene(scene), frame, fromBvh);
        renderWith(hostBackend(), buildScene(scene, findLayout("compact"), LayoutOptions{}), frame,
                   fromOctree);
        uint64_t differ = 0, lit = 0;
        for (size_t i = 0; i < fromBvh.pixelCount(); ++i) {
            differ += bitsOf(fromBvh.t[i]) != bitsOf(fromOctree.t[i]) ||
                      fromBvh.prim[i] != fromOctree.prim[i] ||
                      fromBvh.shadow[i] != fromOctree.shadow[i] ||
                      std::memcmp(&fromBvh.rgb[3 * i], &fromOctree.rgb[3 * i], 3) != 0;
            lit += fromBvh.shadow[i] == kLit;
        }
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(lit, 0u);
    }
}

// A point cloud is refused when the backend is prepared, with one line naming the backend, the
// scene and what traces it instead.
TEST(BvhBackend, RefusesAPointCloudSayingWhatToUse) {
    const Scene cloud = makeGridCloud(1000, 3);
    const BuiltScene bare = bareScene(cloud);
    try {
        bvh().prepare(bare);
        FAIL() << "a point cloud was accepted";
    } catch (const BvhError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_NE(what.find(std::string("backend ") + bvh().name), std::string::npos) << what;
        EXPECT_NE(what.find(cloud.name), std::string::npos) << what;
        EXPECT_NE(what.find("point cloud"), std::string::npos) << what;
        EXPECT_NE(what.find(std::string("backend ") + hostBackend().name), std::string::npos)
            << what;
    }
    EXPECT_TRUE(bvh().trianglesOnly);
    EXPECT_FALSE(bvh().usesLayouts);
    EXPECT_FALSE(bvh().reference);
}

}  // namespace
}  // namespace oct
