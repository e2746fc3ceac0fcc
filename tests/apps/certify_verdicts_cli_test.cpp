// `octrace certify`'s per-ray outputs and the options that choose what decides the exit status,
// run as a user runs them (docs/CERTIFY.md): --verdicts writes one class, reason set and leak
// state per row, --baseline names the rows that got worse or better against an earlier run,
// --require picks the verdicts that decide, --max-rechecks leaves work unverified (exit 3, never
// wrong), and examples/verdicts.py reads the files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "validation/policy/double_tracer.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::isOneLineVerdict;
using octtest::kTeapot;
using octtest::quote;
using octtest::RunResult;
using octtest::show;

class CertifyVerdictsCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
        root_ = std::make_unique<octtest::TempDir>("certify_verdicts_cli");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
        // The teapot, every standard set, octrace's linear layout: a correct answer in G.*.
        RunResult r = run("rays " + quote(kTeapot) + " --count 3000 --size 32x32 --seed 3 --out " +
                          q("R.npy"));
        ASSERT_EQ(r.status, 0) << show(r);
        r = run("trace " + quote(kTeapot) + " --rays " + q("R.npy") + " --out " + q("G") +
                " --backend cpu --accel linear");
        ASSERT_EQ(r.status, 0) << show(r);
        t_ = readArray<float>("G.t.npy");
        prim_ = readArray<int32_t>("G.prim.npy");
        manifest_ = nlohmann::json::parse(octtest::readFile(work_ / "R.json"));
    }
    RunResult run(const std::string& args) const {
        return octtest::runOctrace(args, root_->path() / "capture");
    }
    std::string q(const std::string& name) const { return quote((work_ / name).string()); }
    std::string certify(const std::string& hits) const {
        return "certify " + quote(kTeapot) + " --rays " + q("R.npy") + " --hits " + q(hits);
    }
    template <class T>
    std::vector<T> readArray(const std::string& name) const {
        NpyArray a = readNpy((work_ / name).string());
        std::vector<T> v(a.elementCount());
        if (!v.empty()) std::memcpy(v.data(), a.data.data(), a.data.size());
        return v;
    }
    nlohmann::json readJson(const std::string& name) const {
        return nlohmann::json::parse(octtest::readFile(work_ / name));
    }
    // The answer G with the hit of `row` moved to half its distance (its primitive kept: a point
    // off the triangle, wrong in any set) and, when `missRow` is set, that row a miss.
    void writeCorrupt(const std::string& prefix, uint64_t row, int64_t missRow = -1) const {
        std::vector<float> t = t_;
        std::vector<int32_t> prim = prim_;
        t[row] *= 0.5f;
        if (missRow >= 0) {
            t[size_t(missRow)] = INFINITY;
            prim[size_t(missRow)] = -1;
        }
        const std::vector<uint8_t> bt = encodeNpy("<f4", {t.size()}, t.data(), 4);
        const std::vector<uint8_t> bp = encodeNpy("<i4", {prim.size()}, prim.data(), 4);
        ASSERT_TRUE(
            octtest::writeFile(work_ / (prefix + ".t.npy"), std::string(bt.begin(), bt.end())));
        ASSERT_TRUE(
            octtest::writeFile(work_ / (prefix + ".prim.npy"), std::string(bp.begin(), bp.end())));
    }
    // The manifest's set named `name`: its first row and its row count.
    std::pair<uint64_t, uint64_t> set(const std::string& name) const {
        for (const auto& s : manifest_["sets"])
            if (s["name"] == name) return {s["begin"].get<uint64_t>(), s["count"].get<uint64_t>()};
        ADD_FAILURE() << "no set " << name;
        return {0, 0};
    }
    // The first row of `name` that hits, at least `skip` rows in.
    uint64_t firstHit(const std::string& name, uint64_t skip = 0) const {
        const auto [begin, count] = set(name);
        for (uint64_t i = begin + skip; i < begin + count; ++i)
            if (prim_[i] >= 0 && t_[i] > 0.1f) return i;
        ADD_FAILURE() << "no hit in " << name;
        return begin;
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
    std::vector<float> t_;
    std::vector<int32_t> prim_;
    nlohmann::json manifest_;
};

TEST_F(CertifyVerdictsCli, VerdictFilesHoldOneVerdictPerRow) {
    const uint64_t row = firstHit("camera", 100);
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("C", row));
    const RunResult r = run(certify("C") + " --verdicts " + q("V") + " --json " + q("C.json"));
    ASSERT_TRUE(isOneLineVerdict(r, 1));
    const nlohmann::json j = readJson("C.json");
    const std::vector<uint8_t> cls = readArray<uint8_t>("V.class.npy");
    const std::vector<uint32_t> reasons = readArray<uint32_t>("V.reasons.npy");
    const std::vector<uint8_t> leak = readArray<uint8_t>("V.leak.npy");
    ASSERT_EQ(cls.size(), t_.size());
    ASSERT_EQ(reasons.size(), t_.size());
    ASSERT_EQ(leak.size(), t_.size());
    EXPECT_EQ(cls[row], 3) << "wrong";
    EXPECT_NE(reasons[row] & kOffSurface, 0u) << reasons[row];
    EXPECT_EQ(std::count(cls.begin(), cls.end(), uint8_t(3)), j["wrong"].get<int64_t>());
    EXPECT_EQ(std::count(leak.begin(), leak.end(), uint8_t(1)), j["leaks"].get<int64_t>());
    EXPECT_TRUE(std::all_of(cls.begin(), cls.end(), [](uint8_t c) { return c <= 4; }));
    EXPECT_TRUE(std::all_of(leak.begin(), leak.end(), [](uint8_t c) { return c <= 4; }));
    // Only edges and vertices rows are leak targets (2: not a target elsewhere).
    const auto [eb, ec] = set("edges");
    const auto [vb, vc] = set("vertices");
    for (uint64_t i = 0; i < leak.size(); ++i) {
        const bool target = (i >= eb && i < eb + ec) || (i >= vb && i < vb + vc);
        if (!target) {
            ASSERT_EQ(leak[i], 2) << "row " << i;
        }
    }
    EXPECT_GT(std::count(leak.begin(), leak.end(), uint8_t(0)), 0) << "sealed targets";
}

TEST_F(CertifyVerdictsCli, BaselineNamesTheRowsThatGotWorseAndBetter) {
    const uint64_t row = firstHit("around", 10);
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("C", row));
    ASSERT_EQ(run(certify("G") + " --verdicts " + q("VG")).status, 0);
    RunResult r = run(certify("C") + " --verdicts " + q("VC") + " --baseline " + q("VG") +
                      " --json " + q("C.json"));
    ASSERT_TRUE(isOneLineVerdict(r, 1));
    nlohmann::json b = readJson("C.json")["baseline"];
    EXPECT_EQ(b["worse"], 1) << b.dump(1);
    EXPECT_EQ(b["better"], 0);
    EXPECT_EQ(b["by_set"]["around"]["worse"], 1);
    EXPECT_EQ(b["by_set"]["around"]["first_worse"][0]["row"], row);
    EXPECT_EQ(b["by_set"]["around"]["first_worse"][0]["class"][1], "wrong");
    EXPECT_NE(r.out.find("1 worse"), std::string::npos) << r.out;
    // The other way round: the fixed answer is one row better, and passes.
    r = run(certify("G") + " --baseline " + q("VC") + " --json " + q("G.json"));
    EXPECT_EQ(r.status, 0) << show(r);
    b = readJson("G.json")["baseline"];
    EXPECT_EQ(b["worse"], 0);
    EXPECT_EQ(b["better"], 1);
    // A baseline of another ray file (other row count) is a one-line error.
    r = run("rays " + quote(kTeapot) + " --count 500 --size 8x8 --out " + q("S.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    r = run("trace " + quote(kTeapot) + " --rays " + q("S.npy") + " --out " + q("S") +
            " --backend cpu --accel linear");
    ASSERT_EQ(r.status, 0) << show(r);
    r = run("certify " + quote(kTeapot) + " --rays " + q("S.npy") + " --hits " + q("S") +
            " --baseline " + q("VG"));
    EXPECT_TRUE(octtest::isOneLineError(r)) << show(r);
}

TEST_F(CertifyVerdictsCli, RequireChoosesTheVerdictsThatDecide) {
    // A wrong camera hit (no camera row is a leak target): correct FAIL, watertight PASS.
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("C", firstHit("camera", 50)));
    EXPECT_TRUE(isOneLineVerdict(run(certify("C")), 1));
    EXPECT_TRUE(isOneLineVerdict(run(certify("C") + " --require correct"), 1));
    RunResult r = run(certify("C") + " --require watertight");
    EXPECT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("(not required)"), std::string::npos) << r.out;
    // A sealed edge target missed: a leak too, so watertight fails as well.
    std::vector<uint8_t> leak;
    ASSERT_EQ(run(certify("G") + " --verdicts " + q("VG")).status, 0);
    leak = readArray<uint8_t>("VG.leak.npy");
    const int64_t sealed = std::find(leak.begin(), leak.end(), uint8_t(0)) - leak.begin();
    ASSERT_LT(size_t(sealed), leak.size());
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("L", firstHit("camera", 50), sealed));
    r = run(certify("L") + " --require watertight --json " + q("L.json"));
    EXPECT_TRUE(isOneLineVerdict(r, 1));
    EXPECT_EQ(readJson("L.json")["require"], "watertight");
    EXPECT_GE(readJson("L.json")["leaks"].get<int>(), 1);
}

TEST_F(CertifyVerdictsCli, MaxRechecksLeavesWorkUnverifiedNeverWrong) {
    // Without a cap every mismatch is rechecked and the correct answer passes.
    RunResult r = run(certify("G") + " --json " + q("G.json"));
    ASSERT_EQ(r.status, 0) << show(r);
    nlohmann::json j = readJson("G.json");
    ASSERT_GT(j["result"]["rechecked"].get<int64_t>(), 20) << "mismatches to cap";
    EXPECT_TRUE(j["policy"]["max_rechecks"].is_null());
    r = run(certify("G") + " --max-rechecks 1 --verdicts " + q("V") + " --json " + q("I.json"));
    ASSERT_TRUE(isOneLineVerdict(r, 3));
    EXPECT_NE(r.err.find("INCOMPLETE"), std::string::npos) << r.err;
    j = readJson("I.json");
    EXPECT_EQ(j["wrong"], 0);
    EXPECT_GT(j["unverified"].get<int64_t>(), 0);
    EXPECT_EQ(j["policy"]["max_rechecks"], 1);
    const std::vector<uint8_t> cls = readArray<uint8_t>("V.class.npy");
    const std::vector<uint32_t> reasons = readArray<uint32_t>("V.reasons.npy");
    EXPECT_EQ(std::count(cls.begin(), cls.end(), uint8_t(3)), 0);
    const int64_t unverified = std::count(cls.begin(), cls.end(), uint8_t(4));
    EXPECT_GT(unverified, 0);
    for (size_t i = 0; i < cls.size(); ++i)
        if (cls[i] == 4) {
            ASSERT_NE(reasons[i] & kNotRechecked, 0u) << "row " << i;
        }
    // A wrong answer within the cap still fails: the cap never turns wrong into unverified
    // for what it did recheck, and FAIL outranks INCOMPLETE.
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("C", firstHit("camera", 50)));
    EXPECT_TRUE(isOneLineVerdict(run(certify("C") + " --max-rechecks 1"), 1));
}

TEST_F(CertifyVerdictsCli, TheNumpyExampleReadsTheVerdictFiles) {
    if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "no /usr/bin/python3 with numpy (apt-get install python3-numpy)";
    const uint64_t row = firstHit("inside", 5);
    ASSERT_NO_FATAL_FAILURE(writeCorrupt("C", row));
    ASSERT_TRUE(isOneLineVerdict(run(certify("C") + " --verdicts " + q("V")), 1));
    const fs::path out = work_ / "example.txt";
    const std::string cmd = "/usr/bin/python3 " + quote(OCT_SOURCE_DIR "/examples/verdicts.py") +
                            " " + q("V") + " " + q("R.json") + " off_surface > " +
                            quote(out.string());
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string text = octtest::readFile(out);
    EXPECT_NE(text.find("off_surface rows (1): [" + std::to_string(row) + "]"), std::string::npos)
        << text;
    for (const auto& s : manifest_["sets"])
        EXPECT_NE(text.find(s["name"].get<std::string>()), std::string::npos) << text;
}

}  // namespace
}  // namespace oct
