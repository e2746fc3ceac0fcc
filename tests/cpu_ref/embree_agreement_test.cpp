// The OpenMP backend against two independent references, frame by frame:
//  - Embree (a different traversal and a different triangle/sphere test) per pixel, by the
//    hit-distance policy of docs/VALIDATION.md (validation/policy/film_compare.h);
//  - exhaustive tracing with the same kernel: every layout must return bitwise the same t,
//    primitive, shadow outcome and colour, because the primitive tests and the tie rule are
//    shared and the octree only decides which primitives are tested.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
// cpu_ref_tests links octrace_cpu only; the comparison lives in validation/ (which depends on
// cpu_ref, not the other way round). It is header-light and self-contained, so it is compiled
// into this test directly rather than changing the link graph of the test binaries.
#include "validation/policy/film_compare.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

// Allowed disagreements with Embree, as a fraction of the frame's pixels:
//  - hit/miss: a primary ray through a silhouette edge or a shared edge seen edge-on, where
//    Woop's watertight test and Embree's (robust mode) may round to opposite sides;
//  - shadow outcome: a shadow ray that grazes an occluder's silhouette, or starts from a hit
//    point that differs in the last bits between the tracers.
// Both at most 0.05% of the pixels (32 of 256x256, 8 of 128x128). Distance mismatches are
// never allowed. (Measured when this test was written: 0 of each in every case below.)
constexpr double kMaxHitMissRate = 5e-4;
constexpr double kMaxShadowRate = 5e-4;

enum class View {
    Framed,         // makeFrame's default: the whole bounding sphere in view, along -z
    CornellInside,  // into the open side of the Cornell box
    CloseUp,        // oblique, from 1.2 bounding radii: the mesh fills the frame (silhouettes)
};

struct SceneCase {
    std::string name;
    std::string file;  // relative to OCT_SOURCE_DIR; empty for the grid cloud
    View view = View::Framed;
    // Square frame side. Exhaustive tracing costs pixels x primitives, so the frames of the
    // larger scenes are smaller (the test binary should run in seconds on two cores).
    int side = 256;
    // For the largest mesh exhaustive tracing is skipped and the two octree layouts are
    // compared with each other exactly instead.
    bool exhaustive = true;
};

Scene loadCase(const SceneCase& c) {
    if (c.file.empty()) return makeGridCloud(4096, 5);
    return loadScene(std::string(OCT_SOURCE_DIR) + "/" + c.file);
}

FrameParams frameFor(const SceneCase& c, const Scene& scene) {
    CameraOptions opt;
    opt.width = c.side;
    opt.height = c.side;
    if (c.view == View::CornellInside) {
        // Looking into the open side of the box, as in the original Cornell box photographs.
        opt.eye = Vec3{278.0f, 273.0f, -800.0f};
        opt.target = Vec3{278.0f, 273.0f, 0.0f};
        opt.fovDegrees = 40.0f;
    } else if (c.view == View::CloseUp) {
        Aabb b = scene.bounds();
        float radius = 0.5f * length(b.extent());
        opt.target = b.center();
        opt.eye = b.center() + normalize(Vec3{1.0f, 0.6f, 0.8f}) * (1.2f * radius);
    }
    return makeFrame(scene.bounds(), opt);
}

double diagonal(const Scene& s) { return double(length(s.bounds().extent())); }

Film renderEmbree(const FrameParams& p, const Scene& scene) {
    EmbreeTracer embree(scene);
    Film film(p.width, p.height);
    renderFrameCpu(p, embree.accel(), primitivesView(scene), film.view());
    return film;
}

Film renderLayout(const FrameParams& p, const Scene& scene, const LayoutDesc& layout) {
    BuiltScene built = buildScene(scene, layout, LayoutOptions{});
    Film film;
    renderWith(hostBackend(), built, p, film);
    return film;
}

// Counts pixels whose arrays differ bit for bit (t compared as bits: +inf == +inf, and a
// NaN would differ from everything but itself).
struct ExactDiff {
    uint64_t t = 0, prim = 0, shadow = 0, rgb = 0;
    uint64_t total() const { return t + prim + shadow + rgb; }
};

ExactDiff exactDiff(const Film& a, const Film& b) {
    ExactDiff d;
    for (size_t i = 0; i < a.pixelCount(); ++i) {
        d.t += std::memcmp(&a.t[i], &b.t[i], sizeof(float)) != 0;
        d.prim += a.prim[i] != b.prim[i];
        d.shadow += a.shadow[i] != b.shadow[i];
        d.rgb += std::memcmp(&a.rgb[3 * i], &b.rgb[3 * i], 3) != 0;
    }
    return d;
}

std::string describe(const FilmComparison& c) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "pixels %llu: both miss %llu, agree %llu, ties %llu, hit/miss %llu, distance "
                  "%llu, shadow %llu, max |dt|/extent %.3g",
                  (unsigned long long)c.pixels, (unsigned long long)c.bothMiss,
                  (unsigned long long)c.bothHitAgree, (unsigned long long)c.ties,
                  (unsigned long long)c.hitMissMismatch, (unsigned long long)c.distanceMismatch,
                  (unsigned long long)c.shadowMismatch, c.maxRelativeDt);
    std::string s = buf;
    for (const PixelMismatch& m : c.worst) {
        std::snprintf(buf, sizeof buf, "\n    (%d,%d) t %.9g vs %.9g prim %d vs %d", m.x, m.y,
                      double(m.tA), double(m.tB), m.primA, m.primB);
        s += buf;
    }
    return s;
}

class EmbreeAgreement : public ::testing::TestWithParam<SceneCase> {};

TEST_P(EmbreeAgreement, EveryLayoutAgreesWithEmbreeAndExactlyWithExhaustive) {
    const SceneCase& c = GetParam();
    if (!c.file.empty() && !fs::exists(std::string(OCT_SOURCE_DIR) + "/" + c.file))
        GTEST_SKIP() << c.file << " is not present";
    Scene scene = loadCase(c);
    FrameParams frame = frameFor(c, scene);
    double extent = diagonal(scene);
    Film embree = renderEmbree(frame, scene);
    const double pixels = double(embree.pixelCount());

    // Every layout of the registry, so a new layout is checked here without editing this test.
    // The first one rendered is the reference for the exact comparison: exhaustive tracing, or
    // the first octree layout where tracing without a structure is skipped (the bunny).
    std::vector<const LayoutDesc*> chosen;
    for (const LayoutDesc& l : layouts())
        if (c.exhaustive || l.usesOctree) chosen.push_back(&l);
    ASSERT_GE(chosen.size(), 2u);
    Film reference;
    for (const LayoutDesc* lp : chosen) {
        const LayoutDesc& layout = *lp;
        SCOPED_TRACE(std::string(layout.name));
        Film film = renderLayout(frame, scene, layout);
        FilmComparison cmp = compareFilms(film, embree, extent);
        std::printf("[ %-8s ] %-14s %-10s vs embree: %s\n", "agree", c.name.c_str(), layout.name,
                    describe(cmp).c_str());
        EXPECT_EQ(cmp.pixels, embree.pixelCount());
        EXPECT_EQ(cmp.distanceMismatch, 0u) << describe(cmp);
        EXPECT_LE(cmp.maxRelativeDt, kDefaultRelativeTolerance) << describe(cmp);
        EXPECT_LE(double(cmp.hitMissMismatch), kMaxHitMissRate * pixels) << describe(cmp);
        EXPECT_LE(double(cmp.shadowMismatch), kMaxShadowRate * pixels) << describe(cmp);
        // The frame must show the scene, or agreement would be vacuous.
        EXPECT_GT(cmp.bothHitAgree + cmp.ties, uint64_t(0.04 * pixels)) << describe(cmp);

        if (lp == chosen.front()) {
            reference = std::move(film);
            continue;
        }
        ExactDiff d = exactDiff(film, reference);
        std::printf(
            "[ %-8s ] %-14s %-10s vs %s: differing t %llu, prim %llu, shadow %llu, "
            "rgb %llu\n",
            "agree", c.name.c_str(), layout.name, chosen.front()->name, (unsigned long long)d.t,
            (unsigned long long)d.prim, (unsigned long long)d.shadow, (unsigned long long)d.rgb);
        EXPECT_EQ(d.t, 0u);
        EXPECT_EQ(d.prim, 0u);
        EXPECT_EQ(d.shadow, 0u);
        EXPECT_EQ(d.rgb, 0u);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, EmbreeAgreement,
    ::testing::Values(SceneCase{"CornellInside", "meshes/cornell_box.obj", View::CornellInside,
                                256},
                      SceneCase{"CornellFramed", "meshes/cornell_box.obj", View::Framed, 256},
                      SceneCase{"Teapot", "meshes/teapot.obj", View::Framed, 192},
                      SceneCase{"TeapotCloseUp", "meshes/teapot.obj", View::CloseUp, 192},
                      SceneCase{"Wuson", "meshes/wuson.obj", View::Framed, 128},
                      SceneCase{"WusonCloseUp", "meshes/wuson.obj", View::CloseUp, 160},
                      SceneCase{"GridCloud4096", "", View::Framed, 192},
                      SceneCase{"GridCloseUp", "", View::CloseUp, 128},
                      // 69,666 triangles, fetched by meshes/fetch: skipped when absent.
                      SceneCase{"Bunny", "meshes/cache/bunny.obj", View::CloseUp, 256, false}),
    [](const ::testing::TestParamInfo<SceneCase>& info) { return info.param.name; });

}  // namespace
}  // namespace oct
