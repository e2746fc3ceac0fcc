// The performance baseline's rule in process (bench/sweep/baseline.h): a stored baseline and a
// measured run built here as result rows, so every verdict is deterministic. The time threshold
// is tested on these synthetic rows only; tests/apps/bench_baseline_cli_test.cpp runs the
// command and checks what does not depend on timing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "bench/sweep/baseline.h"
#include "core/io/output_file.h"
#include "validation/regression/cost_baseline.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

const std::string kFile = "cpu.json";

// A measured row of ours as the sweep makes it ("ok", a ratio, counts per pixel).
Row measured(const std::string& scene, const std::string& layout, double ratio, double nodes,
             double prims) {
    Row r;
    r.scene = scene;
    r.layout = layout;
    r.backend = hostBackend().name;
    r.ratioToEmbree = ratio;
    r.nodesPerPixel = nodes;
    r.primsPerPixel = prims;
    return r;
}

BaselineCase stored(const std::string& scene, const std::string& layout, double ratio, double nodes,
                    double prims) {
    return {scene, layout, hostBackend().name, ratio, nodes, prims};
}

// The stored baseline of these tests: two cases on the teapot.
std::vector<BaselineCase> teapotBaseline() {
    return {stored("teapot.obj", "linear", 3.0, 22.0, 4.5),
            stored("teapot.obj", "compact", 2.5, 12.0, 2.0)};
}

BaselineReport judge(const std::vector<Row>& rows, const NotRun& notRun = {}) {
    return compareBaseline(kFile, teapotBaseline(), rows, notRun);
}

const CaseComparison& caseOf(const BaselineReport& r, const std::string& layout) {
    for (const CaseComparison& c : r.cases)
        if (c.layout == layout) return c;
    throw std::runtime_error("no case for " + layout);
}

TEST(BenchBaseline, TimeRatioDoubledAtTheSameCountsFailsOnTimeAlone) {
    const BaselineReport r = judge({measured("teapot.obj", "linear", 6.0, 22.0, 4.5),
                                    measured("teapot.obj", "compact", 2.5, 12.0, 2.0)});
    EXPECT_TRUE(r.fails());
    EXPECT_EQ(r.slower(), 1u);
    EXPECT_EQ(r.costlier(), 0u);
    const CaseComparison& c = caseOf(r, "linear");
    EXPECT_EQ(c.time, Change::Worse);
    EXPECT_EQ(c.counts, Change::Same);
    EXPECT_DOUBLE_EQ(c.timeFactor, 2.0);
    EXPECT_EQ(caseOf(r, "compact").time, Change::Same);
    EXPECT_NE(r.failureText().find("slower (time"), std::string::npos) << r.failureText();
    EXPECT_EQ(r.failureText().find("counts"), std::string::npos) << r.failureText();
    // The failing case comes first in the report, named with its factor.
    EXPECT_EQ(r.cases.front().layout, "linear");
    EXPECT_NE(humanSummary(r).find("FAIL time x2.00"), std::string::npos) << humanSummary(r);
}

TEST(BenchBaseline, NodesPerPixelDoubledFailsOnCountsAndOnTheCostCheck) {
    const BaselineReport r = judge({measured("teapot.obj", "linear", 3.0, 44.0, 4.5),
                                    measured("teapot.obj", "compact", 2.5, 12.0, 2.0)});
    EXPECT_TRUE(r.fails());
    EXPECT_EQ(r.slower(), 0u);
    EXPECT_EQ(r.costlier(), 1u);
    const CaseComparison& c = caseOf(r, "linear");
    EXPECT_EQ(c.counts, Change::Worse);
    EXPECT_EQ(c.time, Change::Same);
    EXPECT_DOUBLE_EQ(c.nodesChange, 1.0);
    EXPECT_NE(r.failureText().find("costlier (counts"), std::string::npos) << r.failureText();
    EXPECT_EQ(r.failureText().find("time"), std::string::npos) << r.failureText();
    // validate --cost-baseline judges the same change (totals over the same 16384 pixels) the
    // same way, with the same tolerance.
    EXPECT_DOUBLE_EQ(kBaselineCountTolerance, kCostTolerance);
    const CostRow cost = judgeCost("teapot.obj", "linear", CostTotals{16384, 22 * 16384, 73728},
                                   CostTotals{16384, 44 * 16384, 73728}, kCostTolerance);
    EXPECT_EQ(cost.verdict, CostVerdict::Increased);
}

TEST(BenchBaseline, ARunWithinTheMeasuredSpreadPasses) {
    // x1.183: the largest run-to-run change of a ratio measured (bench/README.md), both ways;
    // counts unchanged.
    const BaselineReport r = judge({measured("teapot.obj", "linear", 3.0 * 1.183, 22.0, 4.5),
                                    measured("teapot.obj", "compact", 2.5 / 1.183, 12.0, 2.0)});
    EXPECT_FALSE(r.fails()) << humanSummary(r);
    EXPECT_FALSE(r.incomplete());
    EXPECT_EQ(caseOf(r, "linear").time, Change::Same);
    EXPECT_EQ(caseOf(r, "compact").time, Change::Same);
    EXPECT_EQ(r.count(CaseOutcome::Compared), 2u);
}

TEST(BenchBaseline, TheThresholdsAreWhereTheRuleSays) {
    const double f = kBaselineTimeFactor;
    auto timeOf = [&](double ratio) {
        return caseOf(judge({measured("teapot.obj", "linear", ratio, 22.0, 4.5),
                             measured("teapot.obj", "compact", 2.5, 12.0, 2.0)}),
                      "linear")
            .time;
    };
    EXPECT_EQ(timeOf(3.0 * f * 0.999), Change::Same);
    EXPECT_EQ(timeOf(3.0 * f * 1.001), Change::Worse);
    EXPECT_EQ(timeOf(3.0 / f * 0.999), Change::Better);  // faster: a note, not a failure
    auto countsOf = [&](double nodes) {
        return caseOf(judge({measured("teapot.obj", "linear", 3.0, nodes, 4.5),
                             measured("teapot.obj", "compact", 2.5, 12.0, 2.0)}),
                      "linear")
            .counts;
    };
    EXPECT_EQ(countsOf(22.0 * 1.05), Change::Same);  // +5 % exactly is within
    EXPECT_EQ(countsOf(22.0 * 1.051), Change::Worse);
    EXPECT_EQ(countsOf(22.0 * 0.949), Change::Better);
    // A faster case and fewer nodes pass.
    const BaselineReport better = judge({measured("teapot.obj", "linear", 1.0, 11.0, 4.5),
                                         measured("teapot.obj", "compact", 2.5, 12.0, 2.0)});
    EXPECT_FALSE(better.fails());
    EXPECT_NE(humanSummary(better).find("--update?"), std::string::npos);
}

TEST(BenchBaseline, MissingStaleSkippedAndErrorCases) {
    // compact: not measured, not asked for (stale); linear: measured; hash: not in the file.
    const BaselineReport r = judge({measured("teapot.obj", "linear", 3.0, 22.0, 4.5),
                                    measured("teapot.obj", "hash", 3.5, 22.0, 4.5)});
    EXPECT_EQ(caseOf(r, "hash").outcome, CaseOutcome::Missing);
    EXPECT_EQ(caseOf(r, "compact").outcome, CaseOutcome::Stale);
    EXPECT_TRUE(r.fails());
    EXPECT_NE(r.failureText().find("1 missing"), std::string::npos) << r.failureText();

    // A stale case alone passes.
    const BaselineReport stale = judge({measured("teapot.obj", "linear", 3.0, 22.0, 4.5)});
    EXPECT_FALSE(stale.fails());
    EXPECT_FALSE(stale.incomplete());

    // The sweep skipped compact's row: skipped, the verdict INCOMPLETE.
    Row skipped = measured("teapot.obj", "compact", 0, 0, 0);
    skipped.status = "skipped";
    skipped.reason = "out of memory";
    skipped.ratioToEmbree.reset();
    const BaselineReport sk = judge({measured("teapot.obj", "linear", 3.0, 22.0, 4.5), skipped});
    EXPECT_EQ(caseOf(sk, "compact").outcome, CaseOutcome::Skipped);
    EXPECT_EQ(caseOf(sk, "compact").why, "out of memory");
    EXPECT_FALSE(sk.fails());
    EXPECT_TRUE(sk.incomplete());

    // The same row as an error fails.
    skipped.status = "error";
    const BaselineReport err = judge({measured("teapot.obj", "linear", 3.0, 22.0, 4.5), skipped});
    EXPECT_EQ(caseOf(err, "compact").outcome, CaseOutcome::Error);
    EXPECT_TRUE(err.fails());
}

TEST(BenchBaseline, ABackendOrMeshNotHereIsSkippedNeverPassed) {
    NotRun notRun;
    notRun.scenes["teapot.obj"] = "mesh not found: meshes/teapot.obj";
    const BaselineReport r = judge({}, notRun);
    EXPECT_EQ(r.count(CaseOutcome::Skipped), 2u);
    EXPECT_FALSE(r.fails());
    EXPECT_TRUE(r.incomplete());

    // A backend asked for that cannot run here, with no case in the file: still INCOMPLETE.
    NotRun device;
    device.backends["cuda"] = "backend not available here: no device";
    const BaselineReport d = judge({measured("teapot.obj", "linear", 3.0, 22.0, 4.5),
                                    measured("teapot.obj", "compact", 2.5, 12.0, 2.0)},
                                   device);
    EXPECT_FALSE(d.fails());
    EXPECT_TRUE(d.incomplete());
    EXPECT_NE(humanSummary(d).find("not run: cuda"), std::string::npos) << humanSummary(d);
}

TEST(BenchBaseline, OnlyOurBackendsRowsAreCases) {
    Row embree = measured("teapot.obj", "embree-bvh", 1.0, 0, 0);
    embree.backend = referenceBackend().name;
    embree.ratioToEmbree.reset();
    const std::vector<BaselineCase> cases =
        baselineCases({embree, measured("teapot.obj", "linear", 3.0, 22.0, 4.5)});
    ASSERT_EQ(cases.size(), 1u);
    EXPECT_EQ(cases[0].layout, "linear");
    EXPECT_DOUBLE_EQ(cases[0].nodesPerPixel, 22.0);
}

TEST(BenchBaseline, AnOptionThatDiffersIsNamed) {
    nlohmann::ordered_json a = {
        {"size", "64x64"}, {"repeats", 9},   {"threads", 1},         {"warmup", 1},    {"seed", 1},
        {"max_depth", 7},  {"max_prims", 8}, {"cloud_max_prims", 1}, {"hash_slots", 4}};
    nlohmann::ordered_json b = a;
    EXPECT_EQ(optionMismatch(a, b, kFile), "");
    b["layouts"] = {"linear"};  // the lists choose cases, they are not compared
    EXPECT_EQ(optionMismatch(a, b, kFile), "");
    b["size"] = "32x32";
    EXPECT_EQ(optionMismatch(a, b, kFile), "--size 32x32, but cpu.json was made with --size 64x64");
    b = a;
    b["cloud_max_prims"] = 2;
    EXPECT_EQ(optionMismatch(a, b, kFile).rfind("--cloud-max-prims 2, but", 0), 0u);
}

// The file: written and read back; a bad one is refused with one line naming it.
class BenchBaselineFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("octrace_bench_baseline_" +
                std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(dir_ / name) << text;
    }
    std::string errorOf(const std::string& name) const {
        try {
            readBaseline(path(name));
        } catch (const IoError& e) {
            return e.what();
        }
        return "";
    }
    fs::path dir_;
};

TEST_F(BenchBaselineFile, RoundTrip) {
    BaselineFile b;
    b.octrace = "9.9.9";
    b.machine = {{"cpu_model", "test"}};
    b.options = {{"size", "64x64"}, {"warmup", 1},    {"repeats", 9},   {"threads", 1},
                 {"seed", 1},       {"max_depth", 7}, {"max_prims", 8}, {"cloud_max_prims", 1},
                 {"hash_slots", 4}};
    b.cases = teapotBaseline();
    writeBaseline(path("b.json"), b);
    const BaselineFile r = readBaseline(path("b.json"));
    EXPECT_EQ(baselineJson(r), baselineJson(b));
    EXPECT_EQ(baselineJson(r)["format"], kBaselineFormat);
    EXPECT_EQ(baselineJson(r)["version"], 1);
}

TEST_F(BenchBaselineFile, BadFilesAreRefusedNamingTheFile) {
    EXPECT_NE(errorOf("absent.json").find(path("absent.json")), std::string::npos);
    write("bad.json", "{\"format\": ");
    EXPECT_NE(errorOf("bad.json").find("not valid JSON"), std::string::npos) << errorOf("bad.json");
    write("v2.json", R"({"format": "octrace-bench-baseline", "version": 2})");
    EXPECT_NE(errorOf("v2.json").find("version 1"), std::string::npos) << errorOf("v2.json");
    write("other.json", R"({"format": "octrace-cost-baselines", "version": 1})");
    EXPECT_NE(errorOf("other.json").find("not an octrace-bench-baseline"), std::string::npos);
    write("nocases.json",
          R"({"format": "octrace-bench-baseline", "version": 1, "octrace": "0.1.0",
              "machine": {}, "options": {}})");
    EXPECT_NE(errorOf("nocases.json").find("lack 'size'"), std::string::npos)
        << errorOf("nocases.json");
    for (const char* name : {"absent.json", "bad.json", "v2.json", "nocases.json"}) {
        const std::string e = errorOf(name);
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        EXPECT_NE(e.find(path(name)), std::string::npos) << "names the file: " << e;
        EXPECT_NE(e.find("--update"), std::string::npos) << "says what to do: " << e;
    }
}

}  // namespace
}  // namespace oct
