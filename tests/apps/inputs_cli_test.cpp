// Bad input gets one line, fast (issue 21), through the `octrace` binary: hit files, ray
// manifests and the regression files that are FIFOs, devices or directories are refused as ray
// files are, without reading (a FIFO hung certify and validate's regression files; a
// manifest symlinked to /dev/zero ate memory); a manifest is bounded in size; its set counts
// are checked against the rows before any set is rebuilt; rays made for another scene are
// refused as such. Every refusal is one line and exit status 2 (kExitError), within seconds.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/io/npy.h"
#include "tests/cli_harness.h"
#include "tests/far_meshes.h"
#include "tests/paths.h"

namespace inputs_cli {  // a name of its own: the unity build joins the folder's files
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using octtest::isOneLineError;
using octtest::RunResult;
using octtest::show;

class InputsCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
        root_ = std::make_unique<octtest::TempDir>("inputs_cli");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
    }
    RunResult run(const std::vector<std::string>& args, double timeout = 20,
                  const std::string& cwd = "") const {
        octtest::RunOptions opt;
        opt.timeoutSeconds = timeout;
        opt.workingDir = cwd;
        return octtest::runOctrace(args, root_->path() / "capture", opt);
    }
    std::string path(const std::string& name) const { return (work_ / name).string(); }

    // R.npy, R.json and H.{t,prim}.npy for `scene`.
    void raysAndHits(const std::string& scene, const std::string& sets = "all",
                     const std::string& count = "300") {
        RunResult r = run({"rays", scene, "--count", count, "--size", "16x16", "--set", sets,
                           "--out", path("R.npy")},
                          120);
        ASSERT_EQ(r.status, 0) << show(r);
        r = run({"trace", scene, "--rays", path("R.npy"), "--out", path("H"), "--backend", "cpu"},
                120);
        ASSERT_EQ(r.status, 0) << show(r);
    }
    std::vector<std::string> certify(const std::string& scene,
                                     const std::string& hits = "H") const {
        return {"certify", scene, "--rays", path("R.npy"), "--hits", path(hits)};
    }
    json manifest() const { return json::parse(octtest::readFile(work_ / "R.json")); }
    void writeManifest(const json& j) const {
        ASSERT_TRUE(octtest::writeFile(work_ / "R.json", j.dump(2)));
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
};

// A one-line refusal with exit status 2, quickly, naming `path` and containing `text`.
void expectRefused(const RunResult& r, const std::string& path, const std::string& text) {
    ASSERT_FALSE(r.timedOut) << "killed after " << r.seconds << " s: it waited or read on";
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_EQ(r.status, 2) << show(r);
    EXPECT_NE(r.err.find(path), std::string::npos) << "names the file: " << r.err;
    EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
    EXPECT_LT(r.seconds, 10.0);
}

// Replaces `p` by a FIFO without a writer, a symlink to /dev/zero or a directory.
enum class Special { Fifo, DevZero, Directory };
const char* kindText(Special s) {
    return s == Special::Fifo ? "FIFO" : s == Special::DevZero ? "character device" : "directory";
}
void makeSpecial(const fs::path& p, Special s) {
    fs::remove_all(p);
    if (s == Special::Fifo) {
        ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0);
    } else if (s == Special::DevZero) {
        fs::create_symlink("/dev/zero", p);
    } else {
        fs::create_directories(p);
    }
}

TEST_F(InputsCli, HitFilesThatAreNotRegularFilesAreRefused) {
    ASSERT_NO_FATAL_FAILURE(raysAndHits(octtest::kCube, "around,edges"));
    for (const char* file : {"H.t.npy", "H.prim.npy"})
        for (Special s : {Special::Fifo, Special::DevZero, Special::Directory}) {
            SCOPED_TRACE(std::string(file) + " as a " + kindText(s));
            fs::remove_all(path("K.t.npy"));
            fs::remove_all(path("K.prim.npy"));
            fs::copy_file(path("H.t.npy"), path("K.t.npy"));
            fs::copy_file(path("H.prim.npy"), path("K.prim.npy"));
            const std::string k = std::string("K") + (file + 1);
            makeSpecial(path(k), s);
            expectRefused(run(certify(octtest::kCube, "K")), path(k), kindText(s));
        }
}

TEST_F(InputsCli, ManifestsThatAreNotRegularFilesOrTooLargeAreRefused) {
    ASSERT_NO_FATAL_FAILURE(raysAndHits(octtest::kCube, "around,edges"));
    const std::string saved = octtest::readFile(work_ / "R.json");
    for (Special s : {Special::Fifo, Special::DevZero, Special::Directory}) {
        SCOPED_TRACE(kindText(s));
        makeSpecial(path("R.json"), s);
        expectRefused(run(certify(octtest::kCube)), path("R.json"), kindText(s));
    }
    // A manifest is small: one past 16 MiB is refused with its size, before it is read.
    fs::remove_all(path("R.json"));
    {
        std::ofstream out(path("R.json"));
        out << saved;
    }
    fs::resize_file(path("R.json"), (uint64_t(16) << 20) + 1);
    expectRefused(run(certify(octtest::kCube)), path("R.json"), "16777217 bytes");
}

TEST_F(InputsCli, RegressionFilesThatAreNotRegularFilesAreRefused) {
    // --regression FILE.
    for (Special s : {Special::Fifo, Special::DevZero, Special::Directory}) {
        SCOPED_TRACE(kindText(s));
        makeSpecial(path("regression.json"), s);
        expectRefused(run({"validate", "--regression", path("regression.json")}),
                      path("regression.json"), kindText(s));
        fs::remove_all(path("regression.json"));
    }
    // A golden PNG: the cube's entry, its image a FIFO (read after the render).
    json g =
        json::parse(octtest::readFile(OCT_SOURCE_DIR "/tests/data/regression/regression.json"));
    json one = json::array();
    for (const json& e : g["scenes"])
        if (e["scene"] == "meshes/cube_binary.ply") one.push_back(e);
    ASSERT_EQ(one.size(), 1u);
    g["scenes"] = one;
    fs::create_directories(work_ / "regression");
    ASSERT_TRUE(octtest::writeFile(work_ / "regression" / "regression.json", g.dump(2)));
    const std::string image = one[0]["frames"][0]["image"];
    makeSpecial(work_ / "regression" / image, Special::Fifo);
    expectRefused(
        run({"validate", "--regression", path("regression/regression.json")}, 60, OCT_SOURCE_DIR),
        image, "FIFO");
}

// The manifest's counts are checked against the rows (and each other) before a set is rebuilt:
// a 16384 x 16384 camera or 2e8 seeded rays were built first (4-6 GB), 2^64 - 1 gave
// "vector::reserve".
TEST_F(InputsCli, ManifestCountsAreCheckedBeforeAnythingIsRebuilt) {
    ASSERT_NO_FATAL_FAILURE(raysAndHits(octtest::kCube, "camera,around,edges"));
    const json good = manifest();
    struct Case {
        const char* what;
        std::function<void(json&)> edit;
        const char* text;
    };
    const std::vector<Case> cases = {
        {"camera 16384x16384",
         [](json& j) { j["camera"]["width"] = j["camera"]["height"] = 16384; }, "camera"},
        {"camera 2^64-1 wide", [](json& j) { j["camera"]["width"] = UINT64_MAX; }, "width"},
        {"count 2e8", [](json& j) { j["count"] = 200000000; }, "count"},
        {"count 2^64-1", [](json& j) { j["count"] = UINT64_MAX; }, "count"},
        {"count off by one", [](json& j) { j["count"] = j["count"].get<uint64_t>() + 1; }, "count"},
        {"set count 2^64-1", [](json& j) { j["sets"][1]["count"] = UINT64_MAX; }, "around"},
        {"set begin 2^64-1", [](json& j) { j["sets"][2]["begin"] = UINT64_MAX; }, "edges"},
        {"rows 2^64-1", [](json& j) { j["rows"] = UINT64_MAX; }, "rows"},
        {"primitives 2^32 + 12",
         [](json& j) { j["scene"]["primitives"] = (uint64_t(1) << 32) + 12; }, "primitives"},
        {"fov nan-like 1e300", [](json& j) { j["camera"]["fov"] = 1e300; }, "fov"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        json j = good;
        c.edit(j);
        writeManifest(j);
        const RunResult r = run(certify(octtest::kCube), 20);
        expectRefused(r, path("R.json"), c.text);
        EXPECT_LT(r.seconds, 5.0) << "built something first";
    }
}

// Rays made for grid:1000 certified against grid:1000:2 (the same count, bounds and rows)
// reported 47,990 wrong instead of "another scene"; the same scene by another path is the same.
TEST_F(InputsCli, AnotherSceneIsRefusedAndTheSameSceneByAnotherPathIsNot) {
    ASSERT_NO_FATAL_FAILURE(raysAndHits("grid:1000", "camera,around,inside"));
    RunResult r = run(certify("grid:1000:2"));
    expectRefused(r, "grid:1000", "another scene");
    EXPECT_NE(r.err.find("certify them against that scene"), std::string::npos) << r.err;
    r = run(certify("grid:1000"));
    EXPECT_EQ(r.status, 0) << show(r);

    // A mesh by its absolute path, then by a relative one and through a symlink.
    ASSERT_NO_FATAL_FAILURE(raysAndHits(octtest::kCube, "around,edges"));
    fs::create_symlink(octtest::kCube, work_ / "cube.ply");
    for (const std::string& scene :
         {std::string("meshes/cube_binary.ply"), std::string("./meshes/../meshes/cube_binary.ply"),
          path("cube.ply")}) {
        r = run(certify(scene), 60, OCT_SOURCE_DIR);
        EXPECT_EQ(r.status, 0) << scene << "\n" << show(r);
    }
    // Another mesh of the same kind and primitive count (the cube's 12 triangles, one corner
    // moved): its geometry differs.
    {
        std::ofstream out(path("other.obj"));
        out << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1.5\nv 0 1 1\n"
               "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
               "f 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    }
    r = run(certify(path("other.obj")));
    expectRefused(r, octtest::kCube, "another scene");
    // And another primitive count.
    r = run(certify(octtest::kTeapot));
    expectRefused(r, octtest::kCube, "another scene");
}

// `octrace rays` writes only rows `octrace trace` accepts: on an 8 x 8 heightfield whose
// vertices are 1-2 ulps apart, tmin-tmax rows had NaN tmax or inf tmin, and trace refused the
// file. Far from the origin the whole pipeline runs (a UTM-like terrain at y = 4e6).
TEST_F(InputsCli, RaysWritesOnlyRowsTraceAccepts) {
    const std::vector<std::pair<std::string, octtest::Mesh>> meshes = {
        {"ulp-1e6.obj", octtest::ulpHeightfield(1e6f, 5)},
        {"ulp-6.5e10.obj", octtest::ulpHeightfield(6.5e10f, 5)},
        {"utm.obj", octtest::utmTerrain()}};
    for (const auto& [name, mesh] : meshes) {
        SCOPED_TRACE(name);
        const std::string file = octtest::writeObj(*root_, name, mesh);
        ASSERT_NO_FATAL_FAILURE(raysAndHits(file, "all", "3000"));  // trace took every row
        if (name == "utm.obj") {
            const RunResult r = run(certify(file), 120);
            EXPECT_EQ(r.status, 0) << show(r);
        }
    }
}

// `--set all` on a mesh without a shared edge (one triangle) or a closed fan (a quad) leaves the
// edges / vertices sets out with a note, as the triangle-only sets on a point cloud; named, such a
// set is refused with one line.
TEST_F(InputsCli, SetAllLeavesOutWhatTheMeshCannotMake) {
    ASSERT_TRUE(octtest::writeFile(work_ / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_TRUE(octtest::writeFile(work_ / "quad.obj",
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
    struct Case {
        const char* mesh;
        std::vector<std::string> leftOut, kept;
    };
    for (const Case& c : {Case{"tri.obj", {"edges", "vertices"}, {"grazing", "tmin-tmax"}},
                          Case{"quad.obj", {"vertices"}, {"edges", "grazing"}}}) {
        SCOPED_TRACE(c.mesh);
        RunResult r =
            run({"rays", path(c.mesh), "--count", "300", "--size", "8x8", "--out", path("R.npy")});
        ASSERT_EQ(r.status, 0) << show(r);
        for (const std::string& set : c.leftOut)
            EXPECT_NE(r.out.find("note    set " + set + " left out"), std::string::npos) << r.out;
        const json m = manifest();
        for (const std::string& set : c.kept) {
            bool found = false;
            for (const json& s : m["sets"]) found = found || s["name"] == set;
            EXPECT_TRUE(found) << set;
        }
        r = run({"trace", path(c.mesh), "--rays", path("R.npy"), "--out", path("H"), "--backend",
                 "cpu"});
        ASSERT_EQ(r.status, 0) << show(r);
        r = run(certify(path(c.mesh)));
        EXPECT_NE(r.status, 2) << show(r);  // certified (the verdict is certify's business)
        for (const std::string& set : c.leftOut) {
            r = run({"rays", path(c.mesh), "--set", "around," + set, "--out", path("S.npy")});
            expectRefused(r, c.mesh, set + ":");
        }
    }
}

// The exit status (apps/cli.h): 0 PASS, 1 FAIL (a verdict), 2 when the command could not judge
// (bad input or usage), for certify and validate alike.
TEST_F(InputsCli, ExitStatusIsTheVerdictOrTwoForBadInput) {
    ASSERT_NO_FATAL_FAILURE(raysAndHits(octtest::kCube, "around,edges"));
    EXPECT_EQ(run(certify(octtest::kCube)).status, 0);
    // One hit moved to half its distance: wrong, FAIL.
    oct::NpyArray t = oct::readNpy(path("H.t.npy"));
    auto* values = reinterpret_cast<float*>(t.data.data());
    uint64_t i = 0;
    while (i < t.elementCount() && !std::isfinite(values[i])) ++i;
    ASSERT_LT(i, t.elementCount());
    values[i] *= 0.5f;
    oct::writeNpy(path("W.t.npy"), "<f4", t.shape, values, 4);
    fs::copy_file(path("H.prim.npy"), path("W.prim.npy"));
    RunResult r = run(certify(octtest::kCube, "W"));
    EXPECT_TRUE(octtest::isOneLineVerdict(r, 1));
    // Could not judge: 2.
    EXPECT_EQ(run(certify(octtest::kCube, "missing")).status, 2);
    std::vector<std::string> args = certify(octtest::kCube);
    args.push_back("--t-tolerance=nan");
    EXPECT_EQ(run(args).status, 2);
    EXPECT_EQ(run({"certify", octtest::kCube}).status, 2);  // no --rays
    EXPECT_EQ(run({"validate", path("none.obj")}).status, 2);
    EXPECT_EQ(run({"validate", octtest::kCube, "--grazing-cos", "inf"}).status, 2);
    EXPECT_EQ(run({"validate", octtest::kCube, "--no-such-option"}).status, 2);
}

}  // namespace
}  // namespace inputs_cli
