// The package's façade (api/octrace/certify.h) in process: its defaults are octrace's own, the
// hits of octrace's own tracer pass through it and a hit moved off the surface fails naming its
// row, and every failure reaches the caller as an octrace::Error of one line, whatever octrace
// threw inside. (That its rays and verdicts are `octrace rays`' and `octrace certify`'s:
// certify_api_cli_test.cpp.)
#include <gtest/gtest.h>
#include <octrace/certify.h>

#include <cmath>
#include <functional>
#include <string>
#include <typeinfo>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"
#include "validation/certify_run.h"
#include "validation/rays/standard_rays.h"

namespace {

using octtest::kCube;
using octtest::kTeapot;

// A small run of every set the teapot takes.
octrace::RayOptions smallRays() {
    octrace::RayOptions o;
    o.count = 900;
    o.seed = 4;
    o.width = o.height = 20;
    return o;
}

struct Hits {
    std::vector<float> t;
    std::vector<int32_t> prim;
};

// octrace's own answers (the host backend, linear layout): a tracer that passes.
Hits octraceHits(const std::string& scenePath, const std::vector<float>& rays) {
    const oct::Scene scene = oct::loadScene(scenePath);
    const oct::BuiltScene built =
        oct::buildScene(scene, oct::findLayout("linear"), oct::LayoutOptions{});
    const uint64_t n = rays.size() / 8;
    Hits h{std::vector<float>(n), std::vector<int32_t>(n)};
    oct::traceWith(oct::hostBackend(), built, {rays.data(), h.t.data(), h.prim.data(), n});
    return h;
}

TEST(CertifyApi, DefaultsAreOctracesOwn) {
    const octrace::CertifyPolicy p;
    const oct::CertifyRunOptions o;
    EXPECT_EQ(p.tTolerance, o.policy.tTolerance);
    EXPECT_EQ(p.edgeTolerance, o.policy.edgeTolerance);
    EXPECT_EQ(p.grazingCos, o.policy.grazingCos);
    EXPECT_EQ(p.maxAmbiguousRate, o.policy.maxAmbiguousRate);
    EXPECT_EQ(p.maxRechecks, o.policy.maxRechecks);
    EXPECT_EQ(p.worstCount, o.policy.worstCount);
    EXPECT_EQ(p.require, oct::requireName(o.require));
    EXPECT_EQ(o.query.ownSets, oct::QueryKind::Closest);
    EXPECT_EQ(p.query, "closest");
    const octrace::RayOptions r;
    const oct::RaySetSpec spec;
    EXPECT_EQ(r.count, spec.count);
    EXPECT_EQ(r.seed, spec.seed);
    EXPECT_EQ(r.width, spec.camera.width);  // the façade's own copy of the shared defaults
    EXPECT_EQ(r.height, spec.camera.height);
    EXPECT_EQ(r.sets, oct::kDefaultRaySets);
}

TEST(CertifyApi, OctracesOwnHitsPassAndAMovedHitFailsNamingItsRow) {
    const octrace::StandardRays rays = octrace::makeRays(kTeapot, smallRays());
    ASSERT_GT(rays.count(), 0u);
    Hits h = octraceHits(kTeapot, rays.rays);
    auto certify = [&](const int32_t* prim) {
        return octrace::certify(kTeapot, rays.rays.data(), rays.count(), h.t.data(), prim,
                                rays.manifestJson);
    };
    const octrace::CertifyResult good = certify(h.prim.data());
    EXPECT_TRUE(good.pass) << good.summary;
    EXPECT_EQ(good.outcome, "PASS");
    EXPECT_EQ(good.correct, "PASS");
    EXPECT_EQ(good.watertight, "PASS");  // the edges and vertices sets are there
    ASSERT_EQ(good.classes.size(), rays.count());
    ASSERT_EQ(good.reasons.size(), rays.count());
    ASSERT_EQ(good.leaks.size(), rays.count());
    EXPECT_NE(good.json.find("\"verdict\": \"PASS\""), std::string::npos) << good.json;
    EXPECT_TRUE(certify(nullptr).pass);  // distances only

    size_t row = 0;
    while (row < h.prim.size() && h.prim[row] < 0) ++row;
    ASSERT_LT(row, h.prim.size());
    h.t[row] *= 1.5f;
    const octrace::CertifyResult bad = certify(h.prim.data());
    EXPECT_FALSE(bad.pass);
    EXPECT_EQ(bad.outcome, "FAIL");
    EXPECT_EQ(bad.correct, "FAIL");
    for (size_t i = 0; i < bad.classes.size(); ++i)
        EXPECT_EQ(bad.classes[i] == 3, i == row)
            << "row " << i << ", class " << int(bad.classes[i]);
}

TEST(CertifyApi, WithoutAManifestTheRaysAreOneSet) {
    // Sets that are not adversarial: as one set "all" their ambiguous rays count against the
    // rate (the edges and vertices sets' would fail it).
    octrace::RayOptions o = smallRays();
    o.sets = "camera,around,inside";
    const octrace::StandardRays rays = octrace::makeRays(kTeapot, o);
    const Hits h = octraceHits(kTeapot, rays.rays);
    const octrace::CertifyResult r =
        octrace::certify(kTeapot, rays.rays.data(), rays.count(), h.t.data(), h.prim.data());
    EXPECT_TRUE(r.pass) << r.summary;
    EXPECT_EQ(r.watertight, "not tested");  // no set has leak targets without the manifest
    EXPECT_NE(r.summary.find("no manifest"), std::string::npos) << r.summary;
}

// Each call throws exactly octrace::Error (not a subclass, not octrace's internal types), with
// one line holding `says`.
void expectError(const std::function<void()>& call, const std::string& says) {
    try {
        call();
        ADD_FAILURE() << "no error; expected one saying '" << says << "'";
    } catch (const std::exception& e) {
        const std::string what = e.what();
        EXPECT_TRUE(typeid(e) == typeid(octrace::Error)) << typeid(e).name() << ": " << what;
        EXPECT_NE(what.find(says), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

TEST(CertifyApi, EveryFailureIsAnOctraceErrorOfOneLine) {
    const std::string missing = octtest::kMeshes + "/no_such_mesh.obj";
    expectError([&] { octrace::loadTriangles(missing); }, "no_such_mesh.obj");
    expectError([] { octrace::loadTriangles("grid:100"); }, "is a point cloud");
    expectError([&] { octrace::makeRays(missing); }, "no_such_mesh.obj");
    auto raysWith = [](const std::function<void(octrace::RayOptions&)>& change) {
        return [change] {
            octrace::RayOptions o = smallRays();
            change(o);
            octrace::makeRays(kTeapot, o);
        };
    };
    expectError(raysWith([](auto& o) { o.sets = "camera,nonsense"; }),
                "RayOptions::sets: unknown set 'nonsense'");
    expectError(raysWith([](auto& o) { o.sets = "camera,camera"; }), "named twice");
    expectError(raysWith([](auto& o) { o.sets = "slivers"; }), "slivers");
    expectError(raysWith([](auto& o) { o.width = 0; }), "RayOptions::width 0 is not in [1, 16384]");
    expectError(raysWith([](auto& o) { o.count = 200000000; }), "RayOptions::count");
    expectError(raysWith([](auto& o) { o.radius = NAN; }), "RayOptions::radius");

    const octrace::StandardRays rays = octrace::makeRays(kTeapot, smallRays());
    const uint64_t n = rays.count();
    const Hits h = octraceHits(kTeapot, rays.rays);
    auto certifyWith = [&](std::vector<float> rows, const std::string& manifest,
                           const octrace::CertifyPolicy& p = {}) {
        return [&, rows, manifest, p] {
            octrace::certify(kTeapot, rows.data(), rows.size() / 8, h.t.data(), h.prim.data(),
                             manifest, p);
        };
    };
    expectError([&] { octrace::certify(kTeapot, nullptr, 0, nullptr, nullptr); }, "holds no rays");
    expectError([&] { octrace::certify(kTeapot, rays.rays.data(), n, nullptr, nullptr); },
                "t is null");
    expectError([&] { octrace::certify(missing, rays.rays.data(), n, h.t.data(), nullptr); },
                "no_such_mesh.obj");
    octrace::CertifyPolicy p;
    p.require = "everything";
    expectError(certifyWith(rays.rays, rays.manifestJson, p), "CertifyPolicy::require");
    p = {};
    p.tTolerance = NAN;
    expectError(certifyWith(rays.rays, rays.manifestJson, p), "CertifyPolicy::tTolerance");
    p = {};
    p.maxRechecks = 0;
    expectError(certifyWith(rays.rays, rays.manifestJson, p), "CertifyPolicy::maxRechecks");
    expectError(certifyWith(rays.rays, "{not json"), "ray manifest 'rays.json': not JSON");
    expectError(certifyWith(rays.rays, "{}"), "ray manifest 'rays.json'");
    // Rows the manifest does not describe: one row fewer, one row edited.
    std::vector<float> fewer(rays.rays.begin(), rays.rays.end() - 8);
    expectError(certifyWith(fewer, rays.manifestJson), "rays.json");
    std::vector<float> edited = rays.rays;
    edited[8 * (n - 1)] += 1.0f;
    expectError(certifyWith(edited, rays.manifestJson), "the rays were changed");
    // The cube's rays and hits certified on the teapot: another scene.
    const octrace::StandardRays cube = octrace::makeRays(kCube, smallRays());
    const Hits cubeHits = octraceHits(kCube, cube.rays);
    expectError(
        [&] {
            octrace::certify(kTeapot, cube.rays.data(), cube.count(), cubeHits.t.data(),
                             cubeHits.prim.data(), cube.manifestJson);
        },
        "another scene");
}

}  // namespace
