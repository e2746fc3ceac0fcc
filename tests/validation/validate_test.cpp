// End-to-end validation (validation/validate.h): every layout on the CPU against Embree on the
// committed meshes and a generated cloud must pass; a layout corrupted on purpose (one leaf's
// list emptied, one hash bucket dropped) must fail and name the pixels it breaks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/octree/built_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "tests/validation/fixtures.h"
#include "validation/report/diff_image.h"
#include "validation/report/report.h"

namespace oct {
namespace {

using octtest::cpuTracers;
using octtest::meshPath;
using octtest::smallOptions;

void expectPasses(const Scene& scene, const ValidationReport& rep) {
    ASSERT_EQ(rep.runs.size(), layouts().size());  // every layout of the registry
    for (const RunReport& run : rep.runs) {
        SCOPED_TRACE(scene.name + " " + run.layout);
        EXPECT_EQ(run.film.primary.wrong, 0u);
        EXPECT_EQ(run.film.shadow.wrong, 0u);
        EXPECT_EQ(run.rays.all.wrong, 0u);
        EXPECT_LE(run.film.primary.ambiguousRate(), rep.policy.maxAmbiguousRate);
        EXPECT_LE(run.film.shadow.ambiguousRate(), rep.policy.maxAmbiguousRate);
        EXPECT_LE(run.rays.all.ambiguousRate(), rep.policy.maxAmbiguousRate);
        EXPECT_EQ(run.film.primary.compared, uint64_t(rep.width) * uint64_t(rep.height));
        EXPECT_EQ(run.rays.all.compared, rep.rayCount);
        EXPECT_GT(run.film.primary.compared - run.film.primary.bothMiss, 0u) << "nothing hit";
        EXPECT_GT(run.film.shadow.compared, 0u) << "no shadow ray compared";
    }
    EXPECT_TRUE(rep.passes());
}

TEST(Validate, PassesOnCommittedMeshesAllLayoutsCpu) {
    for (const std::string& name : octtest::committedMeshes()) {
        Scene scene = loadScene(meshPath(name));
        auto t = cpuTracers(scene);
        ValidateOptions o = smallOptions();
        o.replication = false;  // checked on its own in replication_test.cpp
        expectPasses(scene, validateScene(scene, t.tracers, t.canonical, o));
    }
}

TEST(Validate, PassesOnGeneratedCloudAllLayoutsCpu) {
    Scene scene = makeGridCloud(3000, 5);
    auto t = cpuTracers(scene);
    ValidationReport rep = validateScene(scene, t.tracers, t.canonical, smallOptions(64, 6000));
    expectPasses(scene, rep);
    ASSERT_TRUE(rep.replication);
    EXPECT_EQ(rep.replication->falseNegatives, 0u);
    EXPECT_EQ(rep.replication->octreeFaces, 3000u);  // one leaf per sphere by construction
}

// The fault-injection fixture: teapot, a 64x64 frame, its Embree reference film and the leaf
// in which most primary hits land (emptying it must lose some of them).
struct Corruption : ::testing::Test {
    Scene scene = loadScene(meshPath("teapot.obj"));
    ValidateOptions opt = smallOptions();
    FrameParams frame = makeFrame(scene.bounds(), opt.camera);
    HitClassifier classifier{scene, opt.policy};
    EmbreeTracer embree{scene};
    Film reference;
    Octree tree = buildOctree(scene, BuildParams{});
    uint32_t leaf = 0;  // index into tree.nodes

    void SetUp() override {
        reference = Film(frame.width, frame.height);
        renderFrameCpu(frame, embree.accel(), primitivesView(scene), reference.view());
        std::map<uint32_t, int> hitsPerLeaf;
        for (int y = 0; y < frame.height; ++y)
            for (int x = 0; x < frame.width; ++x) {
                Vec3 p = hitPoint(x, y);
                if (!isFinite(p)) continue;
                for (uint32_t k = 0; k < tree.nodes.size(); ++k)
                    if (tree.nodes[k].nodeType() == NodeType::Leaf && tree.nodes[k].box.contains(p))
                        ++hitsPerLeaf[k];
            }
        ASSERT_FALSE(hitsPerLeaf.empty());
        leaf = std::max_element(hitsPerLeaf.begin(), hitsPerLeaf.end(), [](auto& a, auto& b) {
                   return a.second < b.second;
               })->first;
    }
    Vec3 hitPoint(int x, int y) const {
        size_t i = size_t(y) * size_t(frame.width) + size_t(x);
        if (reference.prim[i] < 0) return {NAN, NAN, NAN};
        Ray r = primaryRay(frame.camera, x, y, frame.width, frame.height);
        return r.org + r.dir * reference.t[i];
    }
    // Every wrong pixel is named, and at least one of them hits inside the corrupted leaf.
    void expectNamed(const FilmValidation& v) {
        EXPECT_GT(v.primary.wrong, 0u);
        EXPECT_FALSE(v.passes(opt.policy.maxAmbiguousRate));
        ASSERT_FALSE(v.worstPixels.empty());
        EXPECT_EQ(v.worstPixels[0].cls, HitClass::Wrong);
        bool inLeaf = false;
        Aabb box = tree.nodes[leaf].box;
        for (const Finding& f : v.worstPixels) {
            if (f.cls != HitClass::Wrong) continue;
            EXPECT_TRUE(f.rechecked);
            EXPECT_LE(std::fabs(double(f.reference.t) - double(f.truth.t)),
                      opt.policy.tTolerance * classifier.extent())
                << "the double truth should side with Embree at " << f.x << "," << f.y;
            EXPECT_EQ(v.primaryClass[size_t(f.y) * size_t(v.width) + size_t(f.x)],
                      uint8_t(HitClass::Wrong));
            inLeaf = inLeaf || box.contains(hitPoint(f.x, f.y));
        }
        EXPECT_TRUE(inLeaf) << "no wrong pixel hits inside the corrupted leaf";
    }
};

TEST_F(Corruption, EmptiedLinearLeafFailsAndNamesPixels) {
    ASSERT_GT(tree.nodes[leaf].primCount, 0u);
    LinearOctree lin = buildLinear(tree);
    lin.nodes[linearIndexOfKey(tree.nodes[leaf].key)].primCount = 0;  // the corruption
    PrimitivesView prims = primitivesView(scene);
    LinearOctreeView view = linearView(lin, tree, prims);
    TracerUnderTest bad = octtest::cpuTracer("linear-corrupted", view, prims);
    ValidateOptions o = opt;
    o.replication = false;
    ValidationReport rep = validateScene(scene, {bad}, nullptr, o);
    EXPECT_FALSE(rep.passes());
    ASSERT_EQ(rep.runs.size(), 1u);
    expectNamed(rep.runs[0].film);
    // The same corruption seen through the lower-level call on Films.
    Film film;
    bad.render(frame, film);
    expectNamed(validateFilm(classifier, frame, film, reference));
    // And in the report a person reads.
    nlohmann::json j = toJson(rep);
    EXPECT_FALSE(j["pass"].get<bool>());
    EXPECT_GT(j["wrong"].get<uint64_t>(), 0u);
    EXPECT_EQ(j["runs"][0]["worst_pixels"][0]["class"], "wrong");
    EXPECT_NE(humanSummary(rep).find("FAIL"), std::string::npos);
    // The diff image marks the wrong pixels red.
    const Finding& w = rep.runs[0].film.worstPixels[0];
    std::vector<uint8_t> img = diffImage(rep.runs[0].film, o.policy.tTolerance);
    size_t px = 3 * (size_t(w.y) * size_t(frame.width) + size_t(w.x));
    EXPECT_EQ(img[px], 255);
    EXPECT_EQ(img[px + 1], 0);
    EXPECT_EQ(img[px + 2], 0);
}

TEST_F(Corruption, DroppedHashBucketFailsAndNamesPixels) {
    HashOctree hash = buildHash(tree);
    uint64_t bucket = tree.nodes[leaf].key % hash.bucketCount;
    for (uint32_t s = 0; s < hash.bucketSlots; ++s)  // the corruption: every slot emptied
        hash.slots[bucket * hash.bucketSlots + s] = OctreeNode{};
    PrimitivesView prims = primitivesView(scene);
    HashOctreeView view = hashView(hash, tree, prims);
    Film film(frame.width, frame.height);
    renderFrameCpu(frame, view, prims, film.view());
    EmbreeTracer& e = embree;
    expectNamed(validateFilm(classifier, frame, film, reference, [&e](const Ray& r) {
        TraceCost c = {0, 0};
        return anyHit(e.accel(), r, c);
    }));
}

TEST_F(Corruption, OneFalsePixelIsNamed) {
    // Synthetic: our film is the reference with one pixel's hit pushed 1% of the scene back.
    Film ours = reference;
    int x = -1, y = -1;
    for (int yy = 0; yy < frame.height && x < 0; ++yy)
        for (int xx = 0; xx < frame.width; ++xx)
            if (reference.prim[size_t(yy) * frame.width + xx] >= 0 && yy > frame.height / 2) {
                x = xx;
                y = yy;
                break;
            }
    ASSERT_GE(x, 0);
    size_t i = size_t(y) * size_t(frame.width) + size_t(x);
    ours.t[i] += float(0.01 * classifier.extent());
    FilmValidation v = validateFilm(classifier, frame, ours, reference);
    EXPECT_EQ(v.primary.wrong, 1u);
    EXPECT_EQ(v.primary.ambiguous, 0u);
    ASSERT_FALSE(v.worstPixels.empty());
    EXPECT_EQ(v.worstPixels[0].x, x);
    EXPECT_EQ(v.worstPixels[0].y, y);
    EXPECT_EQ(v.worstPixels[0].cls, HitClass::Wrong);
    // The untouched film passes.
    EXPECT_TRUE(validateFilm(classifier, frame, reference, reference).passes(1e-9));
}

TEST_F(Corruption, FalseShadowIsNamed) {
    // Our film claims a shadow at a lit pixel whose shadow ray is clearly unobstructed.
    Film ours = reference;
    size_t pick = SIZE_MAX;
    for (size_t i = 0; i < ours.pixelCount() && pick == SIZE_MAX; ++i)
        if (ours.shadow[i] == kLit) pick = i;
    ASSERT_NE(pick, SIZE_MAX);
    ours.shadow[pick] = kOccluded;
    EmbreeTracer& e = embree;
    FilmValidation v = validateFilm(classifier, frame, ours, reference, [&e](const Ray& r) {
        TraceCost c = {0, 0};
        return anyHit(e.accel(), r, c);
    });
    EXPECT_EQ(v.primary.wrong, 0u);
    EXPECT_EQ(v.shadow.wrong + v.shadow.ambiguous, 1u);
    ASSERT_FALSE(v.worstShadows.empty());
    EXPECT_EQ(size_t(v.worstShadows[0].y) * frame.width + size_t(v.worstShadows[0].x), pick);
    EXPECT_EQ(v.worstShadows[0].referenceOnOurRay, 0);
    EXPECT_EQ(v.worstShadows[0].truthOccluded, 0);
    EXPECT_EQ(v.shadow.wrong, 1u) << "reasons " << reasonNames(v.worstShadows[0].reasons);
}

TEST(Validate, MismatchedFilmSizesAreRejected) {
    Scene scene = loadScene(meshPath("cube_binary.ply"));
    ValidationPolicy pol;
    HitClassifier c(scene, pol);
    CameraOptions cam;
    cam.width = cam.height = 8;
    FrameParams p = makeFrame(scene.bounds(), cam);
    Film a(8, 8), b(8, 4);
    EXPECT_THROW(validateFilm(c, p, a, b), std::invalid_argument);
}

}  // namespace
}  // namespace oct
