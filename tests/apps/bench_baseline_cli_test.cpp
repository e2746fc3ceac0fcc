// `octrace bench --baseline FILE` end to end, on a configuration that runs in well under a
// second (300 points and the unit cube at 32x32). Only what does not depend on timing is
// asserted: the file's format, the counts, the exit statuses of a bad file, a missing case, an
// option that differs, a backend not here. Where a run must pass, --max-slowdown 1e9 takes the
// time out of its verdict; the time check itself fails here only against a ratio edited a
// million times too small (the threshold's own tests, on synthetic rows:
// tests/apps/bench_baseline_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "backends/backend_list.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using octtest::RunResult;
using octtest::show;

const std::string kTiny = "--clouds 300 --meshes '" + octtest::kCube +
                          "' --accel all --size 32x32 --repeats 1 --warmup 0 --no-progress";
// The time is not judged where a run must pass (see the top of the file).
const std::string kNoTime = " --max-slowdown 1e9";

class BenchBaselineCli : public ::testing::Test {
protected:
    BenchBaselineCli() : dir_("bench_baseline") {}

    RunResult bench(const std::string& args) {
        return octtest::runOctrace("bench --out '" + dir_.str("out") + "' " + args,
                                   dir_.path() / "capture");
    }
    std::string file() const { return dir_.str("baseline.json"); }
    // Makes the baseline of the tiny configuration.
    void update() {
        const RunResult r = bench("--baseline '" + file() + "' --update " + kTiny);
        ASSERT_EQ(r.status, 0) << show(r);
    }
    RunResult check(const std::string& extra = kNoTime) {
        return bench("--baseline '" + file() + "' --no-progress" + extra);
    }
    json readFile() const { return octtest::readJson<json>(file()); }
    void writeFile(const json& j) const { ASSERT_TRUE(octtest::writeFile(file(), j.dump(2))); }

    octtest::TempDir dir_;
};

// A verdict: `status` and one line on stderr, the bench baseline's.
::testing::AssertionResult isVerdict(const RunResult& r, int status) {
    if (r.status != status)
        return ::testing::AssertionFailure() << "exit " << r.status << ", not " << status << "\n"
                                             << show(r);
    if (std::count(r.err.begin(), r.err.end(), '\n') != 1 ||
        r.err.rfind("octrace: bench baseline ", 0) != 0)
        return ::testing::AssertionFailure() << "not one verdict line on stderr\n" << show(r);
    return ::testing::AssertionSuccess();
}

TEST_F(BenchBaselineCli, UpdateWritesTheFileAndACheckOfItPasses) {
    update();
    const json j = readFile();
    EXPECT_EQ(j["format"], "octrace-bench-baseline");
    EXPECT_EQ(j["version"], 1);
    EXPECT_TRUE(j["octrace"].is_string());
    EXPECT_TRUE(j["machine"].contains("cpu_model"));
    const json& o = j["options"];
    EXPECT_EQ(o["size"], "32x32");
    EXPECT_EQ(o["repeats"], 1);
    EXPECT_EQ(o["threads"], 1) << "one thread unless asked";
    EXPECT_EQ(o["clouds"], json::array({300}));
    EXPECT_EQ(o["meshes"], json::array({octtest::kCube}));
    EXPECT_EQ(o["layouts"].size(), oct::layouts().size());
    // Every layout on each of the two scenes, on the host backend (Embree is the reference).
    ASSERT_EQ(j["cases"].size(), 2 * oct::layouts().size());
    const json bench1 = octtest::readJson<json>(dir_.path() / "out" / "bench.json");
    EXPECT_EQ(bench1["config"]["paired_reference"], true);

    const RunResult r = check();
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("bench baseline PASS: " + std::to_string(j["cases"].size()) + " cases"),
              std::string::npos)
        << show(r);
    // The counts are the traversal's: the same in the second run, bit for bit.
    const json bench2 = octtest::readJson<json>(dir_.path() / "out" / "bench.json");
    for (const json& c : j["cases"]) {
        bool found = false;
        for (const json& row : bench2["results"]) {
            if (row["scene"] != c["scene"] || row["layout"] != c["layout"] ||
                row["backend"] != c["backend"])
                continue;
            found = true;
            EXPECT_EQ(row["boxes_per_pixel"], c["nodes_per_pixel"]) << c.dump();  // results v2
            EXPECT_EQ(row["prims_per_pixel"], c["prims_per_pixel"]) << c.dump();
        }
        EXPECT_TRUE(found) << c.dump();
    }
}

TEST_F(BenchBaselineCli, MoreNodesFailOnCountsAlone) {
    update();
    json j = readFile();
    j["cases"][0]["nodes_per_pixel"] = j["cases"][0]["nodes_per_pixel"].get<double>() / 2;
    j["cases"][0]["prims_per_pixel"] = j["cases"][0]["prims_per_pixel"].get<double>() / 2;
    writeFile(j);
    const RunResult r = check();
    ASSERT_TRUE(isVerdict(r, 1));
    EXPECT_NE(r.err.find("1 costlier (counts"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("slower"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("FAIL counts"), std::string::npos) << r.out;
}

TEST_F(BenchBaselineCli, ARatioFarAboveTheFilesFailsOnTimeAlone) {
    update();
    json j = readFile();
    j["cases"][0]["ratio_to_embree"] = 1e-6;
    writeFile(j);
    const RunResult r = check("");  // the default threshold
    ASSERT_TRUE(isVerdict(r, 1));
    // Other cases may be slower too (one 32x32 frame is noise); this one is, by 1e6 at least.
    EXPECT_NE(r.err.find(" slower (time"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("counts"), std::string::npos) << r.err;
    const std::string scene = j["cases"][0]["scene"], layout = j["cases"][0]["layout"];
    bool failedOnTime = false;
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind(scene.substr(0, 18), 0) == 0 &&
            line.find(" " + layout + " ") != std::string::npos)
            failedOnTime = line.find("FAIL time x") != std::string::npos &&
                           line.find("FAIL counts") == std::string::npos;
    EXPECT_TRUE(failedOnTime) << r.out;
}

TEST_F(BenchBaselineCli, ACaseMissingFromTheFileFailsUntilUpdated) {
    update();
    json j = readFile();
    const json gone = j["cases"][0];
    j["cases"].erase(0);
    writeFile(j);
    const RunResult r = check();
    ASSERT_TRUE(isVerdict(r, 1));
    EXPECT_NE(r.err.find("1 missing from the file"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("FAIL missing"), std::string::npos) << r.out;
    // --update takes the file's options and puts the case back.
    const RunResult u = bench("--baseline '" + file() + "' --update --no-progress");
    ASSERT_EQ(u.status, 0) << show(u);
    EXPECT_EQ(readFile()["cases"].size(), j["cases"].size() + 1);
    EXPECT_EQ(readFile()["options"], j["options"]);
    ASSERT_EQ(check().status, 0);
}

TEST_F(BenchBaselineCli, ACaseNotAskedForIsStaleAndPasses) {
    update();
    const std::string one = oct::layouts().back().name;
    const RunResult r = check(kNoTime + " --accel " + one);
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("stale: in the file, not run"), std::string::npos) << r.out;
}

TEST_F(BenchBaselineCli, AnotherSizeOrRepeatCountIsRefusedNamingTheOption) {
    update();
    for (const std::string option : {"--size 16x16", "--repeats 2", "--threads 2"}) {
        const RunResult r = check(kNoTime + " " + option);
        ASSERT_TRUE(octtest::isOneLineError(r)) << option;
        EXPECT_EQ(r.status, 2);
        EXPECT_NE(r.err.find(option + ", but " + file() + " was made with"), std::string::npos)
            << r.err;
    }
}

TEST_F(BenchBaselineCli, ABadFileIsAnErrorNamingIt) {
    const RunResult missing = check();
    ASSERT_TRUE(octtest::isOneLineError(missing));
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.err.find(file()), std::string::npos) << missing.err;
    EXPECT_NE(missing.err.find("--update"), std::string::npos) << missing.err;

    ASSERT_TRUE(octtest::writeFile(file(), "{\"format\": \"octrace-bench-baseline\", "));
    const RunResult malformed = check();
    ASSERT_TRUE(octtest::isOneLineError(malformed));
    EXPECT_EQ(malformed.status, 2);
    EXPECT_NE(malformed.err.find("not valid JSON"), std::string::npos) << malformed.err;

    fs::remove(file());
    update();
    json j = readFile();
    j["version"] = 2;
    writeFile(j);
    const RunResult version = check();
    ASSERT_TRUE(octtest::isOneLineError(version));
    EXPECT_EQ(version.status, 2);
    EXPECT_NE(version.err.find("version 1"), std::string::npos) << version.err;
    // --update refuses to overwrite a file it cannot read.
    const RunResult u = bench("--baseline '" + file() + "' --update " + kTiny);
    ASSERT_TRUE(octtest::isOneLineError(u));
    EXPECT_EQ(readFile()["version"], 2);

    const RunResult alone = bench("--update " + kTiny);
    ASSERT_TRUE(octtest::isOneLineError(alone));
    EXPECT_NE(alone.err.find("--baseline"), std::string::npos) << alone.err;
}

TEST_F(BenchBaselineCli, ABackendNotHereIsSkippedAndTheVerdictIncomplete) {
    const oct::BackendDesc* absent = nullptr;
    for (const oct::BackendDesc& b : oct::backends()) {
        std::string why;
        if (!b.available(why)) absent = &b;
    }
    if (!absent) GTEST_SKIP() << "every backend runs here";
    update();
    const RunResult r = check(kNoTime + " --backend " + oct::hostBackend().name + "," +
                              oct::referenceBackend().name + "," + absent->name);
    EXPECT_EQ(r.status, 3) << show(r);
    EXPECT_NE(r.out.find(std::string("not run: ") + absent->name), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("bench baseline INCOMPLETE"), std::string::npos) << r.err;
}

TEST_F(BenchBaselineCli, AMeshOfTheFileNotHereIsSkipped) {
    update();
    json j = readFile();
    const std::string gone = dir_.str("gone.obj");
    j["options"]["meshes"].push_back(gone);
    json c = j["cases"][0];
    c["scene"] = "gone.obj";
    j["cases"].push_back(c);
    writeFile(j);
    const RunResult r = check();
    EXPECT_EQ(r.status, 3) << show(r);
    EXPECT_NE(r.out.find("SKIPPED: mesh not found: " + gone), std::string::npos) << r.out;
    EXPECT_NE(r.err.find(gone + " not found"), std::string::npos) << r.err;
}

}  // namespace
