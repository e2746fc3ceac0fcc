// The regression set's manifest (validation/regression/regression_manifest.h) and its runs
// (regression_run.h): what a malformed or loosening manifest is refused with, --regression-add
// filling every derived field of a new entry (its layouts, views and size honoured), an entry
// without frames failing as missing, the views' cameras, and a backend the manifest names that
// this build lacks being skipped, never passed.
#include "validation/regression/regression_manifest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/io/input_file.h"
#include "core/scene/load_scene.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "tests/validation/regression_fixture.h"
#include "validation/regression/regression_run.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using oct::RegressionMode;
using octtest::kRoot;
using octtest::readJson;

// The manifest cut to the cube, `edit` applied; what reading it throws ("" when it reads).
template <class Edit>
std::string refusal(Edit edit) {
    octtest::TempDir dir("regression_manifest_bad");
    const std::string path = octtest::copyRegression(dir.path(), {"cube_binary.ply"}, edit);
    try {
        oct::readRegressionManifest(path);
    } catch (const oct::IoError& e) {
        return e.what();
    }
    return "";
}

TEST(RegressionManifest, TheCommittedManifestReads) {
    const oct::RegressionManifest m = oct::readRegressionManifest(octtest::kRegressionManifest);
    EXPECT_EQ(m.backends, std::vector<std::string>{"cpu"});
    EXPECT_EQ(m.goldenTolerance("cpu").maxOverFraction, 0.0);
    EXPECT_EQ(m.goldenTolerance("embree").channel, 1);
    // A backend the file does not list gets the ceiling, never more.
    EXPECT_EQ(m.goldenTolerance("another").maxOverFraction, oct::goldenCeiling().maxOverFraction);
    EXPECT_EQ(refusal([](json&) {}), "");
}

// Version 1 named a frame's cost "nodes" and "prims"; such a file still reads, to the same
// totals, so --update can rewrite it as version 2.
TEST(RegressionManifest, AVersion1ManifestReadsWithItsOldKeys) {
    octtest::TempDir dir("regression_manifest_v1");
    const std::string now = octtest::copyRegression(dir.path(), {"cube_binary.ply"}, [](json&) {});
    const oct::RegressionManifest current = oct::readRegressionManifest(now);
    octtest::TempDir old("regression_manifest_v1_old");
    const std::string v1 = octtest::copyRegression(old.path(), {"cube_binary.ply"}, [](json& m) {
        m["version"] = 1;
        for (json& f : m["scenes"][0]["frames"])
            for (auto& [layout, c] : f["cost"].items()) {
                c = {{"nodes", c["boxes_tested"]},
                     {"prims", c["prims_tested"]},
                     {"nodes_per_pixel", c["boxes_per_pixel"]},
                     {"prims_per_pixel", c["prims_per_pixel"]}};
            }
    });
    const oct::RegressionManifest read = oct::readRegressionManifest(v1);
    ASSERT_EQ(read.scenes.size(), current.scenes.size());
    ASSERT_FALSE(read.scenes[0].frames.empty());
    for (size_t i = 0; i < current.scenes[0].frames.size(); ++i)
        for (const auto& [layout, t] : current.scenes[0].frames[i].cost) {
            const oct::CostTotals& o = read.scenes[0].frames[i].cost.at(layout);
            EXPECT_EQ(o.nodes, t.nodes) << layout;
            EXPECT_EQ(o.prims, t.prims) << layout;
        }
}

TEST(RegressionManifest, MalformedOrLooseningFilesAreRefusedNamingTheField) {
    auto expectRefused = [](const std::string& what, const char* needle) {
        EXPECT_NE(what.find(needle), std::string::npos) << what;
        EXPECT_NE(what.find("regression.json"), std::string::npos) << what;
    };
    expectRefused(refusal([](json& m) { m["version"] = 3; }), "version 1 to 2");
    expectRefused(refusal([](json& m) { m["version"] = 0; }), "version 1 to 2");
    expectRefused(
        refusal([](json& m) { m["tolerances"]["golden"]["cpu"]["max_over_fraction"] = 0.01; }),
        "looser than the rule's ceiling");
    expectRefused(refusal([](json& m) { m["tolerances"]["golden"]["embree"]["channel"] = 2; }),
                  "looser than the rule's ceiling");
    expectRefused(refusal([](json& m) { m["tolerances"]["cost"] = 0.2; }), "tolerances.cost");
    expectRefused(refusal([](json& m) {
                      m["scenes"][0]["layouts"] = {"linear", "octtree"};
                  }),
                  "octtree");
    expectRefused(refusal([](json& m) { m["scenes"][0]["views"] = {"+w"}; }), "+w");
    expectRefused(refusal([](json& m) { m["scenes"][0]["views"] = {"+y", "+y"}; }), "twice");
    expectRefused(refusal([](json& m) { m["scenes"].push_back(m["scenes"][0]); }), "listed twice");
    expectRefused(refusal([](json& m) { m["scenes"][0]["frames"][0]["image"] = "../x.png"; }),
                  "plain file name");
    expectRefused(refusal([](json& m) { m["scenes"][0]["max_depth"] = 99; }), "max_depth");
    expectRefused(refusal([](json& m) { m["scenes"][0]["scale"] = 0.0; }), "scale");
    expectRefused(refusal([](json& m) { m["defaults"].erase("views"); }), "'defaults'");
    expectRefused(refusal([](json& m) { m["scenes"] = json::array(); }), "--regression-add");
}

TEST(RegressionManifest, AddFillsEveryDerivedFieldWithTheSettingsGiven) {
    octtest::TempDir dir("regression_add");
    const std::string path = octtest::copyRegression(dir.path(), {"cube_binary.ply"});
    oct::RegressionAddition add;
    add.scene = "meshes/teapot.obj";
    add.settings.width = 64;
    add.settings.height = 48;
    add.settings.layouts = std::vector<std::string>{"hash"};
    add.settings.views = std::vector<std::string>{"default", "+y"};
    const oct::RegressionReport r = oct::runRegression(path, RegressionMode::Add, kRoot, {}, &add);
    ASSERT_TRUE(r.golden && r.cost);
    EXPECT_EQ(r.golden->rows.size(), 2u);  // one image per view, the cube untouched
    EXPECT_EQ(r.cost->rows.size(), 2u);    // hash, per view
    const json m = readJson(path);
    ASSERT_EQ(m["scenes"].size(), 2u);
    const json& e = m["scenes"][1];
    EXPECT_EQ(e["scene"], "meshes/teapot.obj");
    EXPECT_EQ(e["width"], 64);
    EXPECT_FALSE(e.contains("max_depth")) << "only what was given is the entry's own";
    ASSERT_EQ(e["frames"].size(), 2u);
    EXPECT_EQ(e["frames"][1]["view"], "+y");
    EXPECT_EQ(e["frames"][1]["image"], "teapot.obj-ypos.png");
    EXPECT_EQ(e["frames"][1]["pixels"], 64 * 48);
    EXPECT_EQ(e["frames"][1]["cost"].size(), 1u);
    EXPECT_TRUE(e["frames"][1]["cost"].contains("hash"));
    int w = 0, h = 0;
    oct::readPngRgb(dir.str("teapot.obj-ypos.png"), w, h);
    EXPECT_EQ(w, 64);
    EXPECT_EQ(h, 48);
    // The new entry passes its check: the hash layout and Embree only.
    const oct::RegressionReport c = oct::runRegression(path, RegressionMode::Check, kRoot);
    EXPECT_TRUE(c.passes()) << oct::humanSummary(c);
    for (const oct::GoldenRow& row : c.golden->rows) {
        if (row.scene == "meshes/teapot.obj") {
            EXPECT_TRUE(row.tracer == "hash" || row.tracer == "embree") << row.tracer;
        }
    }
    // Twice is refused, and nothing is written.
    const std::string before = octtest::readFile(path);
    EXPECT_THROW(oct::runRegression(path, RegressionMode::Add, kRoot, {}, &add),
                 std::runtime_error);
    EXPECT_EQ(octtest::readFile(path), before);
    // Under another name the same scene is a second entry (a configuration of its own).
    add.name = "teapot-single-leaf";
    add.settings = {};
    add.settings.maxDepth = 0;
    oct::runRegression(path, RegressionMode::Add, kRoot, {}, &add);
    EXPECT_TRUE(fs::exists(dir.path() / "teapot-single-leaf.png"));
    EXPECT_EQ(readJson(path)["scenes"][2]["max_depth"], 0);
}

TEST(RegressionManifest, AScaledEntryIsTheMeshTimesItsScaleAndACloudIsRefused) {
    oct::RegressionRender render;
    render.scale = 1e-3;
    const oct::Scene small =
        oct::loadRegressionScene("meshes/teapot.obj", kRoot, render, "regression.json");
    const oct::Scene teapot = oct::loadScene(OCT_SOURCE_DIR "/meshes/teapot.obj");
    ASSERT_EQ(small.triangles.size(), teapot.triangles.size());
    EXPECT_NEAR(oct::sceneExtent(small), 1e-3 * oct::sceneExtent(teapot),
                1e-6 * oct::sceneExtent(teapot));
    EXPECT_FLOAT_EQ(small.triangles[7].v1.y, float(double(teapot.triangles[7].v1.y) * 1e-3));
    try {
        oct::loadRegressionScene("grid:100", kRoot, render, "regression.json");
        FAIL() << "a scaled cloud was accepted";
    } catch (const oct::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("point cloud"), std::string::npos) << e.what();
    }
}

TEST(RegressionManifest, AnEntryWithoutFramesFailsAsMissing) {
    octtest::TempDir dir("regression_missing");
    const std::string path = octtest::copyRegression(
        dir.path(), {"cube_binary.ply"}, [](json& m) { m["scenes"][0].erase("frames"); });
    const oct::RegressionReport r = oct::runRegression(path, RegressionMode::Check, kRoot);
    EXPECT_FALSE(r.passes());
    for (const oct::GoldenRow& row : r.golden->rows) {
        EXPECT_TRUE(row.missing);
        EXPECT_FALSE(row.pass);
    }
    for (const oct::CostRow& row : r.cost->rows) EXPECT_EQ(row.verdict, oct::CostVerdict::Missing);
    EXPECT_NE(oct::humanSummary(r).find("--update"), std::string::npos) << oct::humanSummary(r);
}

TEST(RegressionManifest, AxisViewsFrameTheSceneFromTheirSide) {
    const oct::Scene scene = oct::loadScene(OCT_SOURCE_DIR "/meshes/teapot.obj");
    const oct::Vec3 c = scene.bounds().center();
    auto eye = [&](const char* view) {
        return oct::makeFrame(scene.bounds(), oct::viewCamera(view, scene, 64, 64)).camera.eye;
    };
    const oct::Vec3 d = eye("default");
    EXPECT_GT(d.z, c.z);
    const float dist = d.z - c.z;
    EXPECT_NEAR(eye("+x").x - c.x, dist, 1e-3f * dist);
    EXPECT_NEAR(c.x - eye("-x").x, dist, 1e-3f * dist);
    EXPECT_NEAR(eye("+y").y - c.y, dist, 1e-3f * dist);
    EXPECT_NEAR(c.y - eye("-y").y, dist, 1e-3f * dist);
    EXPECT_NEAR(c.z - eye("-z").z, dist, 1e-3f * dist);
    const oct::Vec3 in = eye("inside");
    EXPECT_FLOAT_EQ(in.x, c.x);
    EXPECT_FLOAT_EQ(in.z, c.z);
    EXPECT_EQ(oct::regressionImageName("teapot.obj", "-x"), "teapot.obj-xneg.png");
    EXPECT_EQ(oct::regressionEntryName("grid:3000:5", std::nullopt), "grid-3000-5");
}

TEST(RegressionManifest, ABackendTheManifestNamesThatThisBuildLacksIsSkipped) {
    octtest::TempDir dir("regression_backend");
    const std::string path = octtest::copyRegression(dir.path(), {"cube_binary.ply"}, [](json& m) {
        m["backends"] = {"cpu", "no-such-backend"};
    });
    const oct::RegressionReport r = oct::runRegression(path, RegressionMode::Check, kRoot);
    EXPECT_TRUE(r.passes());
    ASSERT_EQ(r.skipped.size(), 1u);
    EXPECT_EQ(r.skipped[0].name, "no-such-backend");
    EXPECT_TRUE(r.incomplete());
}

}  // namespace
