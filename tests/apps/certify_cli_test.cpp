// `octrace rays` and `octrace certify` run as a user runs them: rays, then a tracer (octrace
// trace with every layout, embree-fast, the Python example), then certify. Its own hits pass;
// bad hit files are one-line errors; a faulty answer fails naming its row; edited rays, a wrong
// scene or an output over an input are refused; info says whether a mesh is closed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "core/octree/layout_registry.h"
#include "core/scene/load_scene.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "validation/rays/ray_sets.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::kCube;
using octtest::kMeshes;
using octtest::kTeapot;

using octtest::isOneLineError;
using octtest::isOneLineVerdict;
using octtest::quote;
using octtest::RunResult;
using octtest::show;

class CertifyCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
        root_ = std::make_unique<octtest::TempDir>("certify_cli");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
    }
    RunResult run(const std::string& args) const {
        return octtest::runOctrace(args, root_->path() / "capture");
    }
    std::string q(const std::string& name) const { return quote((work_ / name).string()); }
    std::string path(const std::string& name) const { return (work_ / name).string(); }

    // rays + trace (one layout, CPU) into R.npy and H.*.npy.
    void raysAndTrace(const std::string& scene, const std::string& extra = "") {
        RunResult r = run("rays " + quote(scene) + " --count 700 --size 16x16 --seed 3 --out " +
                          q("R.npy") + " --triangles " + q("T.npy") + extra);
        ASSERT_EQ(r.status, 0) << show(r);
        r = run("trace " + quote(scene) + " --rays " + q("R.npy") + " --out " + q("H") +
                " --backend cpu --accel linear --max-depth 5");
        ASSERT_EQ(r.status, 0) << show(r);
    }
    std::string certify(const std::string& scene = kCube, const std::string& hits = "H") const {
        return "certify " + quote(scene) + " --rays " + q("R.npy") + " --hits " + q(hits);
    }
    void writeNpy(const std::string& name, const std::string& descr,
                  const std::vector<uint64_t>& shape, const void* data, size_t elem) const {
        std::vector<uint8_t> b = encodeNpy(descr, shape, data, elem);
        ASSERT_TRUE(octtest::writeFile(work_ / name, std::string(b.begin(), b.end())));
    }
    template <class T>
    std::vector<T> readArray(const std::string& name) const {
        NpyArray a = readNpy(path(name));
        std::vector<T> v(a.elementCount());
        if (!v.empty()) std::memcpy(v.data(), a.data.data(), a.data.size());
        return v;
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
};

TEST_F(CertifyCli, OwnTraceOfEveryLayoutPasses) {
    for (const std::string& scene : {kCube, kTeapot}) {
        ASSERT_NO_FATAL_FAILURE(raysAndTrace(scene));
        nlohmann::json manifest = nlohmann::json::parse(octtest::readFile(work_ / "R.json"));
        EXPECT_EQ(manifest["format"], "octrace-rays");
        EXPECT_EQ(manifest["sets"].size(), 9u);
        for (const LayoutDesc& l : layouts()) {
            SCOPED_TRACE(scene + " " + l.name);
            RunResult r = run("trace " + quote(scene) + " --rays " + q("R.npy") + " --out " +
                              q("H") + " --backend cpu --max-depth 5 --accel " + l.name);
            ASSERT_EQ(r.status, 0) << show(r);
            r = run(certify(scene) + " --json -");
            ASSERT_EQ(r.status, 0) << show(r);
            nlohmann::json j;
            ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << "stdout is not JSON:\n" << r.out;
            EXPECT_TRUE(j["pass"].get<bool>());
            EXPECT_EQ(j["wrong"], 0);
            EXPECT_EQ(j["leaks"], 0);
            EXPECT_TRUE(j["manifest"].get<bool>());
            EXPECT_EQ(j["result"]["sets"].size(), 9u);
            // The camera set's rows against the camera's definition, every pixel.
            EXPECT_TRUE(j["camera_rows"]["pass"].get<bool>()) << j["camera_rows"].dump();
            EXPECT_EQ(j["camera_rows"]["compared"],
                      manifest["camera"]["width"].get<uint64_t>() *
                          manifest["camera"]["height"].get<uint64_t>());
            EXPECT_NE(r.err.find("PASS"), std::string::npos) << "the summary goes to stderr";
        }
    }
}

// Sphere scenes: a generated grid cloud (its radius is fixed, so certify must not hand the
// manifest's radius back to the loader, which refuses a radius for grid:N) and a point cloud
// file whose radius was given to `rays` (certify takes it from the manifest).
TEST_F(CertifyCli, OwnTraceOfSphereScenesPasses) {
    const std::string xyz = path("points.xyz");
    ASSERT_TRUE(octtest::writeFile(xyz, "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n0.5 0.5 0.2\n"));
    for (const auto& [scene, radius] : std::vector<std::pair<std::string, std::string>>{
             {"grid:512", ""}, {xyz, " --radius 0.05"}}) {
        SCOPED_TRACE(scene);
        RunResult r = run("rays " + quote(scene) + radius +
                          " --count 700 --size 16x16 --seed 3 --out " + q("R.npy"));
        ASSERT_EQ(r.status, 0) << show(r);
        r = run("trace " + quote(scene) + radius + " --rays " + q("R.npy") + " --out " + q("H") +
                " --backend cpu --accel linear");
        ASSERT_EQ(r.status, 0) << show(r);
        r = run(certify(scene));
        EXPECT_EQ(r.status, 0) << show(r);
    }
}

// The slivers scene and its must-hit set through the command line: hits at the targets pass
// without primitive ids, the same with the edge rows missing fail with exactly those leaks, and
// octrace's own trace hits every row. Other scenes refuse the set or leave it out of `all`.
TEST_F(CertifyCli, SliversRaysMustAllHit) {
    const std::string scene = "slivers:2000";
    RunResult r = run("rays " + scene + " --set slivers --count 2000 --out " + q("R.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    nlohmann::json manifest = nlohmann::json::parse(octtest::readFile(work_ / "R.json"));
    EXPECT_EQ(manifest["scene"]["name"], "slivers:2000:1");
    ASSERT_EQ(manifest["sets"].size(), 1u);
    EXPECT_EQ(manifest["sets"][0]["name"], "slivers");
    // Every row's target is where it crosses z = 0: answer exactly that.
    const std::vector<float> rays = readArray<float>("R.npy");
    std::vector<float> t(rays.size() / 8);
    for (size_t i = 0; i < t.size(); ++i) t[i] = float(-double(rays[8 * i + 2]) / rays[8 * i + 5]);
    writeNpy("H.t.npy", "<f4", {t.size()}, t.data(), 4);
    r = run(certify(scene) + " --no-prim --json -");
    ASSERT_EQ(r.status, 0) << show(r);
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["result"]["leak_checked"], 2000);
    EXPECT_EQ(j["leaks"], 0);
    for (size_t i = 2; i < t.size(); i += 4) t[i] = INFINITY;  // the rows aimed at an edge
    writeNpy("H.t.npy", "<f4", {t.size()}, t.data(), 4);
    r = run(certify(scene) + " --no-prim --json -");
    EXPECT_EQ(r.status, 1) << show(r);
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["leaks"], 500);
    EXPECT_NE(r.err.find("500 leaks (in slivers)"), std::string::npos) << show(r);

    r = run("trace " + scene + " --rays " + q("R.npy") + " --out " + q("O") +
            " --backend cpu --accel linear");
    ASSERT_EQ(r.status, 0) << show(r);
    for (float v : readArray<float>("O.t.npy")) ASSERT_TRUE(std::isfinite(v));

    r = run("rays " + quote(kCube) + " --set slivers --out " + q("C.npy"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("needs a slivers:N scene"), std::string::npos) << show(r);
    r = run("rays " + quote(kCube) + " --count 90 --size 8x8 --out " + q("C.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("set slivers left out: it needs a slivers:N scene"), std::string::npos)
        << show(r);
}

TEST_F(CertifyCli, ValidatesRaysAreTheStandardSetsByteForByte) {
    RunResult r = run("rays " + quote(kTeapot) + " --set around,inside,axis --count 300 --seed 7" +
                      " --out " + q("V.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    RaySet v = makeValidationRays(loadScene(kTeapot), 300, 7);
    EXPECT_EQ(readArray<float>("V.npy"), v.rays);
}

TEST_F(CertifyCli, BadHitFilesAreOneLineErrors) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    const std::vector<float> t = readArray<float>("H.t.npy");
    const std::vector<int32_t> prim = readArray<int32_t>("H.prim.npy");
    const uint64_t n = t.size();
    fs::copy_file(path("H.prim.npy"), path("B.prim.npy"));
    std::vector<double> t64(t.begin(), t.end());
    struct Case {
        const char* what;
        std::function<void()> make;
        const char* file;
    };
    const std::vector<Case> cases = {
        {"float64 t", [&] { writeNpy("B.t.npy", "<f8", {n}, t64.data(), 8); }, "B.t.npy"},
        {"t of shape (N/2, 2)",
         [&] {
             writeNpy("B.t.npy", "<f4", {n / 2, 2}, t.data(), 4);
         },
         "B.t.npy"},
        {"t one short", [&] { writeNpy("B.t.npy", "<f4", {n - 1}, t.data(), 4); }, "B.t.npy"},
        {"prim as float32",
         [&] {
             writeNpy("B.t.npy", "<f4", {n}, t.data(), 4);
             writeNpy("B.prim.npy", "<f4", {n}, t.data(), 4);
         },
         "B.prim.npy"},
        {"prim as int64",
         [&] {
             std::vector<int64_t> p64(prim.begin(), prim.end());
             writeNpy("B.prim.npy", "<i8", {n}, p64.data(), 8);
         },
         "B.prim.npy"},
        {"prim missing", [&] { fs::remove(path("B.prim.npy")); }, "B.prim.npy"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        c.make();
        RunResult r = run(certify(kCube, "B"));
        EXPECT_TRUE(isOneLineError(r));
        EXPECT_NE(r.err.find(c.file), std::string::npos) << r.err;
        EXPECT_EQ(r.out, "");
    }
    // Distances only: no prim file needed.
    RunResult r = run(certify(kCube, "B") + " --no-prim");
    EXPECT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("distances only"), std::string::npos) << r.out;
}

// `trace` writes PREFIX.t.npy and PREFIX.prim.npy by two renames; a run finishing between the
// two left t from one run and prim from the other, whole files of the right length that
// certify judged as one tracer's answers. Forged here as it happens: trace into H (the cube),
// trace into G (the teapot, same rays), then one of G's files renamed over H's. The record trace
// writes beside the pair (H.run.json) vouches for H's files, by their data's hash and their
// identity (inode, size, mtime): one file it vouches for and one it does not is refused.
TEST_F(CertifyCli, PairMixedFromTwoTraceRunsIsRefused) {
    for (const char* column : {"prim", "t"}) {
        SCOPED_TRACE(column);
        ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
        RunResult r = run("trace " + quote(kTeapot) + " --rays " + q("R.npy") + " --out " + q("G") +
                          " --backend cpu --accel linear --max-depth 5");
        ASSERT_EQ(r.status, 0) << show(r);
        ASSERT_NE(readArray<int32_t>("G.prim.npy"), readArray<int32_t>("H.prim.npy"));
        ASSERT_NE(readArray<float>("G.t.npy"), readArray<float>("H.t.npy"));
        fs::rename(path("G." + std::string(column) + ".npy"),
                   path("H." + std::string(column) + ".npy"));
        r = run(certify());
        EXPECT_TRUE(isOneLineError(r));
        EXPECT_EQ(r.status, 2);
        EXPECT_NE(r.err.find(path("H.t.npy")), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(path("H.prim.npy")), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("one run"), std::string::npos) << r.err;
        EXPECT_EQ(r.out, "");
    }
    // Both files rewritten by another tracer: the record vouches for neither and says nothing
    // about this pair; certify judges it (wrong answers for the cube).
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    ASSERT_EQ(run("trace " + quote(kTeapot) + " --rays " + q("R.npy") + " --out " + q("G") +
                  " --backend cpu --accel linear --max-depth 5")
                  .status,
              0);
    for (const char* column : {"t", "prim"})
        fs::copy_file(path("G." + std::string(column) + ".npy"),
                      path("H." + std::string(column) + ".npy"),
                      fs::copy_options::overwrite_existing);
    RunResult r = run(certify());
    EXPECT_TRUE(isOneLineVerdict(r, 1));
    // A pair without the record (another tracer's files) is certified as before.
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    fs::remove(path("H.run.json"));
    r = run(certify());
    EXPECT_EQ(r.status, 0) << show(r);
}

// Another tracer that finds exactly octrace's primitives, with t an ulp away, writes its pair
// over a prefix octrace traced into (each file written anew and renamed, as careful writers do).
// Its prim file has the bytes the record hashed, but not the identity: the record vouches for
// neither file, and the pair is judged, not refused as a mix (it was, by the hash alone).
TEST_F(CertifyCli, AnotherTracersPairWithTheSameIdsIsJudgedNotRefused) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    std::vector<float> t = readArray<float>("H.t.npy");
    const std::vector<int32_t> prim = readArray<int32_t>("H.prim.npy");
    for (size_t i = 0; i < 256; ++i)  // the camera set's rows (16x16), whose tmax is +inf
        if (std::isfinite(t[i])) t[i] = std::nextafter(t[i], INFINITY);
    oct::writeNpy(path("H.t.npy"), "<f4", {t.size()}, t.data(), 4);  // a new file, renamed
    oct::writeNpy(path("H.prim.npy"), "<i4", {prim.size()}, prim.data(), 4);
    const RunResult r = run(certify());
    EXPECT_EQ(r.status, 0) << show(r);  // an ulp is within every tolerance
    EXPECT_EQ(r.err.find("one run"), std::string::npos) << r.err;
}

TEST_F(CertifyCli, AFaultyAnswerFailsNamingItsRow) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    std::vector<float> t = readArray<float>("H.t.npy");
    std::vector<int32_t> prim = readArray<int32_t>("H.prim.npy");
    uint64_t row = 0;
    while (prim[row] < 0) ++row;
    t[row] = NAN;
    prim[row + 1] = 1 << 30;
    writeNpy("H.t.npy", "<f4", {t.size()}, t.data(), 4);
    writeNpy("H.prim.npy", "<i4", {prim.size()}, prim.data(), 4);
    RunResult r = run(certify());
    EXPECT_TRUE(isOneLineVerdict(r, 1));
    EXPECT_NE(r.err.find("correct FAIL, 2 wrong"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find(" " + std::to_string(row) + " "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("invalid_hit"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("t=nan"), std::string::npos) << r.out;
}

TEST_F(CertifyCli, EditedRaysAndWrongScenesAreRefused) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    // Another scene than the rays were made for.
    RunResult r = run(certify(kTeapot));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("made for"), std::string::npos) << r.err;
    // One float of one row changed: the manifest's checksum no longer matches.
    std::vector<float> rays = readArray<float>("R.npy");
    rays[8 * 100 + 3] = std::nextafter(rays[8 * 100 + 3], 2.0f);
    writeNpy("R.npy", "<f4", {rays.size() / 8, 8}, rays.data(), 4);
    r = run(certify());
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("R.json"), std::string::npos) << r.err;
    // Without the manifest the rows are one set, "all", judged as a whole: the adversarial rows
    // then count towards the ambiguous rate (what the manifest is for).
    fs::remove(work_ / "R.json");
    r = run(certify() + " --json " + q("C.json"));
    EXPECT_NE(r.status, 2) << show(r);
    nlohmann::json j = nlohmann::json::parse(octtest::readFile(work_ / "C.json"));
    EXPECT_FALSE(j["manifest"].get<bool>());
    EXPECT_EQ(j["result"]["sets"], nlohmann::json::array({"all"}));
    EXPECT_EQ(j["wrong"], 0);
    EXPECT_EQ(j["result"]["leak_checked"], 0);
}

TEST_F(CertifyCli, OutputsNeverReplaceInputs) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    const std::string before = octtest::readFile(work_ / "R.npy");
    RunResult r = run(certify() + " --json " + q("R.npy"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_EQ(octtest::readFile(work_ / "R.npy"), before);
    r = run(certify() + " --json " + q("D.png") + " --diff-image " + q("./D.png"));
    EXPECT_TRUE(isOneLineError(r));
    r = run("rays " + quote(kCube) + " --out " + q("X.npy") + " --triangles " + q("X.json"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_FALSE(fs::exists(work_ / "X.npy"));
    r = run("rays " + quote(kCube) + " --set camera,nope --out " + q("Y.npy"));
    EXPECT_TRUE(isOneLineError(r));
    // Zero rays certify nothing: refused rather than a PASS.
    r = run("rays " + quote(kCube) + " --set around --count 0 --out " + q("Z.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    r = run("certify " + quote(kCube) + " --rays " + q("Z.npy") + " --hits " + q("Z"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("no rays"), std::string::npos) << r.err;
}

TEST_F(CertifyCli, DiffImageOfTheCameraSet) {
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    RunResult r = run(certify() + " --diff-image " + q("D.png"));
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_EQ(octtest::readFile(work_ / "D.png").substr(1, 3), "PNG");
    r = run("rays " + quote(kCube) + " --set around --count 10 --out " + q("R.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    r = run("trace " + quote(kCube) + " --rays " + q("R.npy") + " --out " + q("H"));
    ASSERT_EQ(r.status, 0) << show(r);
    r = run(certify() + " --diff-image " + q("E.png"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("camera"), std::string::npos) << r.err;
}

TEST_F(CertifyCli, InfoSaysWhetherAMeshIsClosed) {
    RunResult r = run("info " + quote(kCube));
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("closed       yes (0 boundary edges, 0 non-manifold edges"),
              std::string::npos)
        << r.out;
    r = run("info " + quote(kMeshes + "/sphere_with_hole.stl") + " --json");
    ASSERT_EQ(r.status, 0) << show(r);
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["topology"]["closed"].get<bool>());
    EXPECT_EQ(j["topology"]["boundary_edges"], 9);
    EXPECT_EQ(j["topology"]["non_manifold_edges"], 0);
    r = run("info grid:50 --json");
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_TRUE(nlohmann::json::parse(r.out)["topology"].is_null());
}

TEST_F(CertifyCli, EmbreeFastIsABackendValidateRefuses) {
    RunResult r = run("list backends --names");
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("embree-fast\n"), std::string::npos) << r.out;
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kCube));
    r = run("trace " + quote(kCube) + " --rays " + q("R.npy") + " --out " + q("F") +
            " --backend embree-fast");
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("embree-bvh-fast"), std::string::npos) << r.out;
    r = run(certify(kCube, "F"));
    EXPECT_TRUE(r.status == 0 || isOneLineVerdict(r, 1)) << show(r);
    r = run("validate " + quote(kCube) + " --backend embree-fast --rays 0 --size 8x8");
    EXPECT_TRUE(isOneLineError(r));
}

// The example tracer of docs/CERTIFY.md still writes what certify reads. Needs Debian's
// /usr/bin/python3 with numpy (python3-numpy); skipped without it.
TEST_F(CertifyCli, ThePythonMollerTrumboreExampleIsCertifiable) {
    if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "no /usr/bin/python3 with numpy (apt-get install python3-numpy)";
    ASSERT_NO_FATAL_FAILURE(raysAndTrace(kTeapot));
    const std::string cmd = "/usr/bin/python3 " +
                            quote(OCT_SOURCE_DIR "/examples/moller_trumbore.py") + " " +
                            q("T.npy") + " " + q("R.npy") + " " + q("M") + " >/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    RunResult r = run(certify(kTeapot, "M") + " --json " + q("M.json"));
    // A verdict, whichever it is: never a format error.
    EXPECT_TRUE(r.status == 0 || isOneLineVerdict(r, 1)) << show(r);
    nlohmann::json j = nlohmann::json::parse(octtest::readFile(work_ / "M.json"));
    EXPECT_EQ(j["result"]["compared"], readArray<float>("R.npy").size() / 8);
}

}  // namespace
}  // namespace oct
