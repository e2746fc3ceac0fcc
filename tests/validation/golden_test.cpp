// Golden images of the regression set (validation/regression/golden.h, regression_run.h): the
// committed frames rendered by this build, with every layout of each entry and with Embree's
// hits, against the images in tests/data/regression/; our kernel is held to 0 differing pixels,
// Embree to the portable rule; an altered image fails; the rule's boundaries; --update's report.
#include "validation/regression/golden.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "backends/backend_list.h"
#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "tests/validation/fixtures.h"
#include "tests/validation/regression_fixture.h"
#include "validation/rays/ray_manifest.h"
#include "validation/regression/artifacts.h"
#include "validation/regression/regression_run.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using oct::GoldenReport;
using oct::GoldenRow;
using oct::ImageDiff;
using oct::RegressionMode;

using octtest::kRoot;
using octtest::readJson;

GoldenReport checkGolden(const std::string& manifest) {
    return *oct::runRegression(manifest, RegressionMode::Check, kRoot).golden;
}

TEST(Golden, CommittedFramesMatchEveryLayoutAndEmbree) {
    const GoldenReport r = checkGolden(octtest::kRegressionManifest);
    EXPECT_TRUE(r.passes()) << oct::humanSummary(r);
    std::set<std::string> scenes, views;
    std::set<std::pair<int, int>> sizes;
    std::set<int> depths;
    std::set<double> scales;
    for (const GoldenRow& row : r.rows) {
        scenes.insert(row.scene);
        views.insert(row.view);
        sizes.insert({row.render.width, row.render.height});
        depths.insert(row.render.build.maxDepth);
        scales.insert(row.render.scale);
        // Same build flags, same bits: the CPU kernel reproduces its own goldens exactly
        // (docs/VALIDATION.md, "Golden images"), which is its rule in the committed manifest.
        if (row.tracer != "embree") {
            EXPECT_EQ(row.tolerance.maxOverFraction, 0.0) << row.file;
            EXPECT_EQ(row.diff.differing, 0u)
                << row.file << " " << row.tracer << ": max " << row.diff.maxDiff << "/255 at ("
                << row.diff.worstX << ", " << row.diff.worstY << ")";
        }
    }
    // Every committed mesh and a generated cloud are pinned, from more than one side, at a
    // size that is not square, as a single leaf, as a tree deeper than 10 levels, and at a
    // thousandth and a thousand times a mesh's size.
    for (const std::string& mesh : octtest::committedMeshes())
        EXPECT_TRUE(scenes.count("meshes/" + mesh)) << mesh << " has no golden image";
    EXPECT_TRUE(std::any_of(scenes.begin(), scenes.end(),
                            [](const std::string& s) { return s.rfind("grid:", 0) == 0; }));
    for (const char* v : {"default", "+x", "-x", "+y", "-y", "-z", "inside"})
        EXPECT_TRUE(views.count(v)) << "no frame from view " << v;
    EXPECT_TRUE(std::any_of(sizes.begin(), sizes.end(),
                            [](const std::pair<int, int>& s) { return s.first > s.second; }));
    EXPECT_TRUE(std::any_of(sizes.begin(), sizes.end(),
                            [](const std::pair<int, int>& s) { return s.first < s.second; }));
    EXPECT_TRUE(depths.count(0));
    EXPECT_TRUE(*scales.begin() <= 1e-3 && *scales.rbegin() >= 1e3);  // an epsilon in world units
    EXPECT_TRUE(*depths.rbegin() > 10);
}

// The teapot's entry with `count` pixels of its golden altered by `by` levels (red channel).
GoldenReport checkAltered(int count, int by) {
    octtest::TempDir dir("golden_altered");
    const std::string manifest = octtest::copyRegression(dir.path(), {"teapot.obj"}, [](json& m) {
        m["scenes"][0].erase("views");  // the default view alone keeps the test fast
        json f = m["scenes"][0]["frames"][0];
        m["scenes"][0]["frames"] = json::array({f});
    });
    int w = 0, h = 0;
    const std::string png = dir.str("teapot.obj.png");
    std::vector<uint8_t> rgb = oct::readPngRgb(png, w, h);
    for (int i = 0; i < count; ++i) {
        uint8_t& r = rgb[3 * size_t(i * 7)];  // spread over the first rows
        r = uint8_t(r >= by ? r - by : r + by);
    }
    oct::writePng(png, w, h, rgb);
    return checkGolden(manifest);
}

TEST(Golden, AlteredImageFailsOurKernelAtOnePixelAndEmbreeByTheRule) {
    // One pixel, one level: every frame of our kernel fails (held to 0); Embree's passes.
    GoldenReport r = checkAltered(1, 1);
    EXPECT_FALSE(r.passes());
    for (const GoldenRow& row : r.rows)
        EXPECT_EQ(row.pass, row.tracer == "embree") << row.tracer << oct::humanSummary(r);
    EXPECT_NE(oct::humanSummary(r).find("FAIL"), std::string::npos);
    EXPECT_FALSE(oct::toJson(r)["pass"].get<bool>());
    // One pixel more than the portable rule allows (8 of 16384), off by 2/255: Embree fails too.
    const int tooMany = int(oct::goldenCeiling().maxOverFraction * 128 * 128) + 1;
    r = checkAltered(tooMany, 2);
    EXPECT_EQ(r.failures(), r.rows.size()) << oct::humanSummary(r);
    for (const GoldenRow& row : r.rows) EXPECT_GE(row.diff.over, uint64_t(tooMany)) << row.tracer;
    // Embree: an isolated pixel far off is allowed (a silhouette another tracer flips).
    r = checkAltered(1, 100);
    for (const GoldenRow& row : r.rows) {
        if (row.tracer == "embree") {
            EXPECT_TRUE(row.pass) << oct::humanSummary(r);
        }
    }
}

// A shading constant changed (the ambient term, +0.02), not an image edited: the teapot's frame
// of every layout on every backend of ours present here fails its golden, and the artefacts hold
// the three images of each failing comparison.
TEST(Golden, AChangedShadingConstantFailsOnEveryBackendPresentAndLeavesThreeImages) {
    const oct::RegressionManifest m = oct::readRegressionManifest(octtest::kRegressionManifest);
    const oct::RegressionScene* entry = m.find("teapot.obj");
    ASSERT_NE(entry, nullptr);
    const oct::RegressionRender render = m.render(*entry);
    const oct::Scene scene =
        oct::loadRegressionScene(entry->scene, kRoot, render, octtest::kRegressionManifest);
    oct::FrameParams frame = oct::makeFrame(
        scene.bounds(), oct::viewCamera("default", scene, render.width, render.height));
    frame.shading.ambient += 0.02f;
    int w = 0, h = 0;
    const std::vector<uint8_t> golden =
        oct::readPngRgb(octtest::kRegressionDir + "/" + entry->frames[0].image, w, h);
    oct::RegressionReport report;
    report.golden.emplace();
    std::set<std::string> backendsSeen;
    const auto tree = oct::buildSharedOctree(scene, render.build);
    for (const oct::LayoutDesc& l : oct::layouts()) {
        oct::LayoutOptions opts;
        opts.build = render.build;
        const oct::BuiltScene built =
            oct::convertLayout(scene, l.usesOctree ? tree : nullptr, l, opts);
        for (const oct::BackendDesc& b : oct::backends()) {
            std::string why;
            if (!b.usesLayouts || !b.available(why)) continue;
            oct::Film film;
            oct::renderWith(b, built, frame, film);
            GoldenRow row;
            row.scene = entry->scene;
            row.view = "default";
            row.file = entry->frames[0].image;
            row.tracer = l.name;
            row.backend = b.name;
            row.tolerance = m.goldenTolerance(b.name);
            row = oct::judgeImage(row, film, w, h, golden);
            EXPECT_FALSE(row.pass) << l.name << " on " << b.name;
            EXPECT_GT(row.diff.over, 1000u) << l.name << " on " << b.name;
            backendsSeen.insert(b.name);
            report.golden->rows.push_back(std::move(row));
        }
    }
    EXPECT_TRUE(backendsSeen.count(oct::hostBackend().name));
    octtest::TempDir dir("golden_shading");
    const oct::ArtifactsWritten written =
        oct::writeRegressionArtifacts(dir.str("artifacts"), report, false);
    EXPECT_EQ(written.failingImages, report.golden->rows.size());
    EXPECT_EQ(written.files.size(), 1 + 3 * report.golden->rows.size());  // index.html first
    for (const GoldenRow& row : report.golden->rows)
        for (const char* kind : {"actual", "golden", "diff"})
            EXPECT_TRUE(
                fs::exists(dir.path() / "artifacts" /
                           (row.file + "-" + row.tracer + "-" + row.backend + "-" + kind + ".png")))
                << row.tracer << " " << row.backend << " " << kind;
}

TEST(Golden, ToleranceRuleBoundaries) {
    const int w = 128, h = 128;
    const std::vector<uint8_t> a(3 * w * h, 100);
    const oct::GoldenTolerance rule = oct::goldenCeiling();
    auto diffWith = [&](int pixels, int by, int channel) {
        std::vector<uint8_t> b = a;
        for (int i = 0; i < pixels; ++i) b[3 * i + 2] = uint8_t(100 + by);
        return oct::compareImages(w, h, a, b, channel);
    };
    const uint64_t allowed = uint64_t(rule.maxOverFraction * w * h);  // 8
    ImageDiff d = diffWith(int(allowed), 2, rule.channel);
    EXPECT_EQ(d.over, allowed);
    EXPECT_TRUE(rule.passes(d));
    EXPECT_FALSE(rule.passes(diffWith(int(allowed) + 1, 2, rule.channel)));
    EXPECT_TRUE(rule.passes(diffWith(w * h, 1, rule.channel)));
    EXPECT_TRUE(rule.passes(diffWith(1, 155, rule.channel)));  // no cap on one pixel by default
    const oct::GoldenTolerance capped{1, 1e-3, 50};
    EXPECT_TRUE(capped.passes(diffWith(1, 50, 1)));
    EXPECT_FALSE(capped.passes(diffWith(1, 51, 1)));
    const oct::GoldenTolerance exact{0, 0.0, 0};  // our kernel's rule in the committed manifest
    EXPECT_TRUE(exact.passes(diffWith(0, 1, 0)));
    EXPECT_FALSE(exact.passes(diffWith(1, 1, 0)));
    d = oct::compareImages(w, h, a, std::vector<uint8_t>(3 * w * (h - 1), 100), rule.channel);
    EXPECT_TRUE(d.sizeMismatch);
    EXPECT_FALSE(rule.passes(d));
}

TEST(Golden, UpdateRewritesAndSaysWhatChanged) {
    octtest::TempDir dir("golden_update");
    const std::string manifest = octtest::copyRegression(dir.path(), {"cube_binary.ply"});
    const std::string png = dir.str("cube_binary.ply.png");
    int w = 0, h = 0;
    std::vector<uint8_t> rgb = oct::readPngRgb(png, w, h);
    for (int i = 0; i < 5; ++i) rgb[3 * i] ^= 0x40;
    oct::writePng(png, w, h, rgb);
    const GoldenReport u = *oct::runRegression(manifest, RegressionMode::Update, kRoot).golden;
    ASSERT_EQ(u.rows.size(), 1u);
    EXPECT_EQ(u.rows[0].diff.differing, 5u);
    EXPECT_NE(oct::humanSummary(u).find("5 pixels changed"), std::string::npos)
        << oct::humanSummary(u);
    EXPECT_EQ(readJson(manifest)["octrace"], std::string(oct::octraceVersion()));
    // The rewritten image is the committed one again.
    EXPECT_EQ(oct::readPngRgb(png, w, h),
              oct::readPngRgb(octtest::kRegressionDir + "/cube_binary.ply.png", w, h));
    EXPECT_TRUE(checkGolden(manifest).passes());
}

TEST(Golden, MissingManifestOrImageIsNamed) {
    octtest::TempDir dir("golden_missing");
    try {
        checkGolden(dir.str("regression.json"));
        FAIL() << "no manifest accepted";
    } catch (const oct::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("regression.json"), std::string::npos) << e.what();
    }
    const std::string manifest = octtest::copyRegression(dir.path(), {"cube_binary.ply"});
    fs::remove(dir.path() / "cube_binary.ply.png");
    try {
        checkGolden(manifest);
        FAIL() << "missing image accepted";
    } catch (const oct::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("cube_binary.ply.png"), std::string::npos) << e.what();
    }
}

}  // namespace
