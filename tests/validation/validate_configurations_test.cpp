// `octrace validate` on the configurations its default run does not reach (docs/VALIDATION.md,
// "Configurations beyond the default run"), each of which a fault can hide in: a frame that is not
// square (a width/height slip is invisible in a square one), on a mesh and on a cloud; the teapot
// at a thousandth and a thousand times its size (an epsilon in world units passes at one scale);
// a tree that is a single leaf (--max-depth 0, and a mesh of fewer triangles than --max-prims);
// a tree deeper than 10 levels, whose Morton keys need more than 32 bits. Every one must PASS with
// every layout that can hold it. Needs the octrace binary of the same build; skipped without it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli_harness.h"
#include "tests/far_meshes.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;

using octtest::kTeapot;
using octtest::quote;
using octtest::RunResult;

class ValidateConfigurations : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
    }

    // Runs `octrace ARGS --json -` and returns the report of a run that must PASS (exit 0).
    nlohmann::json passes(const std::string& args) {
        const RunResult r = octtest::runOctrace(args + " --json -", capture_.path());
        EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
        nlohmann::json j;
        EXPECT_NO_THROW(j = nlohmann::json::parse(r.out)) << args << ": stdout is not JSON\n"
                                                          << r.out;
        return j;
    }

    // The canonical octree `octrace info` builds for SCENE with OPTIONS.
    nlohmann::json octree(const std::string& scene, const std::string& options) {
        return passes("info " + quote(scene) + " " + options)["octree"];
    }

    // validate's verdict and the frame's size, every run having judged every pixel.
    static void expectPassAt(const nlohmann::json& j, int width, int height, size_t runs) {
        EXPECT_TRUE(j.value("pass", false)) << j.dump().substr(0, 2000);
        EXPECT_EQ(j["frame"]["width"], width);
        EXPECT_EQ(j["frame"]["height"], height);
        ASSERT_EQ(j["runs"].size(), runs);
        for (const auto& run : j["runs"]) {
            SCOPED_TRACE(run["layout"].get<std::string>());
            EXPECT_EQ(run["primary"]["compared"], uint64_t(width) * uint64_t(height));
            EXPECT_GT(run["shadow"]["compared"].get<uint64_t>(), 0u) << "no shadow ray compared";
            EXPECT_EQ(run["primary"]["wrong"], 0u);
        }
    }

    octtest::TempDir capture_{"validate_configurations"};
};

const std::string kCheap = " --rays 3000 --box-rays 2000";

TEST_F(ValidateConfigurations, FramesThatAreNotSquareOnAMeshAndACloud) {
    expectPassAt(passes("validate " + quote(kTeapot) + " --size 97x61 --accel all" + kCheap), 97,
                 61, 4);
    expectPassAt(passes("validate grid:3000:5 --size 61x97 --accel all" + kCheap), 61, 97, 4);
}

TEST_F(ValidateConfigurations, TheTeapotAtAThousandthAndAThousandTimesItsSize) {
    const double teapotExtent = oct::sceneExtent(oct::loadScene(kTeapot));
    for (const double factor : {1e-3, 1e3}) {
        SCOPED_TRACE(factor);
        const std::string obj = octtest::writeObj(
            capture_, "teapot-x" + std::to_string(factor) + ".obj", octtest::scaledTeapot(factor));
        const nlohmann::json j =
            passes("validate " + quote(obj) + " --size 64x48 --accel all" + kCheap);
        expectPassAt(j, 64, 48, 4);
        EXPECT_NEAR(j["scene"]["extent"].get<double>(), factor * teapotExtent,
                    1e-5 * factor * teapotExtent);
    }
}

TEST_F(ValidateConfigurations, ATreeThatIsASingleLeaf) {
    // --max-depth 0: the root is the only node, a leaf listing all 992 triangles.
    EXPECT_EQ(octree(kTeapot, "--max-depth 0")["nodes"], 1u);
    expectPassAt(
        passes("validate " + quote(kTeapot) + " --max-depth 0 --size 48x32 --accel all" + kCheap),
        48, 32, 4);
    // A regular tetrahedron: 4 triangles, fewer than the default --max-prims 8, so the root is
    // not split. Its faces are not edge-on to the default view (down -z) and its box's centre,
    // the inside view's eye, lies inside it.
    octtest::Mesh tet;
    tet.v = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tet.f = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    const std::string obj = octtest::writeObj(capture_, "tetrahedron.obj", tet);
    EXPECT_EQ(octree(obj, "")["nodes"], 1u);
    expectPassAt(passes("validate " + quote(obj) + " --size 48x32 --accel all" + kCheap), 48, 32,
                 4);
}

TEST_F(ValidateConfigurations, ATreeDeeperThanTenLevels) {
    // 14 levels: keys of 1 + 3 * 14 = 43 bits. The linear layout's complete array would hold
    // (8^15 - 1) / 7 records (241 TB), so only the layouts that store what exists are run.
    const nlohmann::json tree = octree(kTeapot, "--max-depth 14");
    EXPECT_EQ(tree["depth"], 14);
    expectPassAt(passes("validate " + quote(kTeapot) +
                        " --max-depth 14 --size 64x48 --accel hash,compact" + kCheap),
                 64, 48, 2);
}

}  // namespace
