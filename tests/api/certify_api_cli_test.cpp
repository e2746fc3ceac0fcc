// The façade against the command line it stands for: makeRays and loadTriangles give the bytes
// `octrace rays` writes (R.npy, R.json, --triangles T.npy), and certify on arrays gives the
// verdicts `octrace certify --verdicts` writes for the same hits, and its exit status's outcome.
#include <gtest/gtest.h>
#include <octrace/certify.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;

using octtest::kTeapot;
using octtest::quote;
using octtest::RunResult;
using octtest::show;

class CertifyApiCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
        root_ = std::make_unique<octtest::TempDir>("certify_api_cli");
    }
    RunResult run(const std::string& args) const {
        return octtest::runOctrace(args, root_->path() / "capture");
    }
    std::string path(const std::string& name) const { return root_->str(name); }

    // `octrace rays` on the teapot, and the façade's call with the same options.
    void raysBothWays(octrace::StandardRays& api) {
        const RunResult r =
            run("rays " + quote(kTeapot) + " --count 700 --size 16x16 --seed 3 --out " +
                quote(path("R.npy")) + " --triangles " + quote(path("T.npy")));
        ASSERT_EQ(r.status, 0) << show(r);
        octrace::RayOptions o;
        o.count = 700;
        o.width = o.height = 16;
        o.seed = 3;
        api = octrace::makeRays(kTeapot, o);
    }

    std::unique_ptr<octtest::TempDir> root_;
};

// An .npy file's data as values of T (the dtype checked).
template <class T>
std::vector<T> npyValues(const std::string& path, const std::string& descr) {
    const oct::NpyArray a = oct::readNpy(path);
    EXPECT_EQ(a.descr, descr) << path;
    std::vector<T> v(a.data.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), a.data.data(), v.size() * sizeof(T));
    return v;
}

TEST_F(CertifyApiCli, MakeRaysAndLoadTrianglesGiveTheBytesOfOctraceRays) {
    octrace::StandardRays api;
    ASSERT_NO_FATAL_FAILURE(raysBothWays(api));
    const std::vector<float> rays = npyValues<float>(path("R.npy"), "<f4");
    ASSERT_EQ(rays.size(), api.rays.size());
    EXPECT_EQ(std::memcmp(rays.data(), api.rays.data(), rays.size() * 4), 0);
    EXPECT_EQ(octtest::readFile(path("R.json")), api.manifestJson);
    const std::vector<float> triangles = npyValues<float>(path("T.npy"), "<f4");
    const std::vector<float> loaded = octrace::loadTriangles(kTeapot);
    ASSERT_EQ(triangles.size(), loaded.size());
    EXPECT_EQ(std::memcmp(triangles.data(), loaded.data(), loaded.size() * 4), 0);
}

TEST_F(CertifyApiCli, CertifyGivesTheVerdictsOfOctraceCertify) {
    octrace::StandardRays api;
    ASSERT_NO_FATAL_FAILURE(raysBothWays(api));
    // Embree's fast mode: a tracer with wrong answers and leaks, so the verdicts differ per row.
    RunResult r = run("trace " + quote(kTeapot) + " --rays " + quote(path("R.npy")) + " --out " +
                      quote(path("H")) + " --backend embree-fast");
    ASSERT_EQ(r.status, 0) << show(r);
    r = run("certify " + quote(kTeapot) + " --rays " + quote(path("R.npy")) + " --hits " +
            quote(path("H")) + " --verdicts " + quote(path("V")));
    ASSERT_TRUE(r.status == 0 || r.status == 1) << show(r);  // PASS or FAIL, not an error
    const std::vector<float> t = npyValues<float>(path("H.t.npy"), "<f4");
    const std::vector<int32_t> prim = npyValues<int32_t>(path("H.prim.npy"), "<i4");
    ASSERT_EQ(t.size(), api.count());
    const octrace::CertifyResult c = octrace::certify(kTeapot, api.rays.data(), api.count(),
                                                      t.data(), prim.data(), api.manifestJson);
    EXPECT_EQ(c.outcome, r.status == 0 ? "PASS" : "FAIL") << show(r);
    EXPECT_EQ(c.classes, npyValues<uint8_t>(path("V.class.npy"), "|u1"));
    EXPECT_EQ(c.reasons, npyValues<uint32_t>(path("V.reasons.npy"), "<u4"));
    EXPECT_EQ(c.leaks, npyValues<uint8_t>(path("V.leak.npy"), "|u1"));
}

}  // namespace
