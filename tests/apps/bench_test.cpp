// Smoke tests of `octrace bench`: the --quick sweep runs, writes bench.csv and bench.json with
// every field, every requested case appears, and limits come back as "skipped" rows with a
// reason. Timings are never asserted (only that they are present), so the tests hold on any
// machine, however loaded.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using oct::LayoutDesc;
using oct::layouts;

using octtest::kMeshes;

// Every field a result row carries, in the order of the CSV header.
const std::vector<std::string> kFields = {
    "scene_type",      "scene",           "path",          "n",
    "primitives",      "vertices",        "faces",         "grid_depth",
    "load_s",          "layout",          "backend",       "status",
    "reason",          "tree_build_s",    "convert_s",     "build_s",
    "frame_s_median",  "frame_s_min",     "frame_s_max",   "upload_s",
    "mrays_per_s",     "ratio_to_embree", "primary_rays",  "shadow_rays",
    "layout_bytes",    "octree_nodes",    "octree_depth",  "octree_faces",
    "boxes_per_pixel", "prims_per_pixel", "boxes_per_ray", "prims_per_ray",
    "width",           "height",          "warmup",        "repeats"};

fs::path freshDir(const std::string& name) {
    fs::path dir = fs::temp_directory_path() /
                   ("octrace_bench_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Runs octrace with the arguments; returns the exit status, stdout and stderr in `log` (also
// written to logFile, for a look after a failure).
int runOctrace(const std::string& args, const fs::path& logFile, std::string& log) {
    octtest::RunResult r = octtest::runOctrace(args, logFile.parent_path() / "capture");
    log = r.out + r.err;
    octtest::writeFile(logFile, log);
    return r.status;
}

std::vector<std::string> readLines(const fs::path& p) {
    std::ifstream in(p);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
    return s;
}

const json* findRow(const json& rows, const std::string& scene, const std::string& layout,
                    const std::string& backend) {
    for (const json& r : rows)
        if (r["scene"] == scene && r["layout"] == layout && r["backend"] == backend) return &r;
    return nullptr;
}

TEST(BenchCommand, QuickSweepWritesEveryFieldAndCase) {
    fs::path dir = freshDir("quick");
    std::string log;
    int rc =
        runOctrace("bench --quick --backends cpu,embree --max-seconds 600 --no-progress --out '" +
                       (dir / "out").string() + "' --meshes-dir '" + kMeshes + "'",
                   dir / "log.txt", log);
    ASSERT_EQ(rc, 0) << log;
    ASSERT_TRUE(fs::exists(dir / "out" / "bench.csv")) << log;
    ASSERT_TRUE(fs::exists(dir / "out" / "bench.json")) << log;

    json doc = octtest::readJson<json>(dir / "out" / "bench.json");
    EXPECT_EQ(doc["format"], "octrace-bench/2");
    EXPECT_EQ(doc["complete"], true);
    for (const char* k :
         {"cpu_model", "logical_cores", "omp_threads", "memory_bytes", "os", "compiler", "build",
          "embree_version", "cuda_device", "date_utc", "load_average_start", "load_average_end"})
        EXPECT_TRUE(doc["machine"].contains(k)) << k;
    for (const char* k : {"quick", "size", "warmup", "repeats", "max_seconds", "backends",
                          "layouts", "scenes", "seed"})
        EXPECT_TRUE(doc["config"].contains(k)) << k;
    EXPECT_EQ(doc["config"]["quick"], true);

    const json& rows = doc["results"];
    ASSERT_TRUE(rows.is_array());
    for (const json& r : rows) {
        std::vector<std::string> keys;
        for (auto it = r.begin(); it != r.end(); ++it) keys.push_back(it.key());
        EXPECT_EQ(keys, kFields);
        EXPECT_TRUE(r["status"] == "ok" || r["status"] == "skipped") << r.dump();
        if (r["status"] == "skipped") {
            EXPECT_FALSE(r["reason"].get<std::string>().empty());
        }
    }

    // The quick sweep: three clouds and two committed meshes, each with Embree and every
    // layout of the registry on the CPU.
    const std::vector<std::string> scenes = {"grid:1000:1", "grid:2000:1", "grid:4000:1",
                                             "cornell_box.obj", "teapot.obj"};
    EXPECT_EQ(rows.size(), scenes.size() * (1 + layouts().size()));
    for (const std::string& s : scenes) {
        const json* e = findRow(rows, s, "embree-bvh", "embree");
        ASSERT_NE(e, nullptr) << s;
        ASSERT_EQ((*e)["status"], "ok") << e->dump();
        for (const LayoutDesc& l : layouts()) {
            const std::string layout = l.name;
            const json* r = findRow(rows, s, layout, "cpu");
            ASSERT_NE(r, nullptr) << s << " " << layout;
            ASSERT_EQ((*r)["status"], "ok") << r->dump();
            for (const char* k :
                 {"build_s", "frame_s_median", "frame_s_min", "frame_s_max", "mrays_per_s",
                  "ratio_to_embree", "boxes_per_pixel", "prims_per_pixel", "layout_bytes"})
                EXPECT_TRUE((*r)[k].is_number()) << s << " " << layout << " " << k;
            EXPECT_EQ((*r)["primary_rays"], (*r)["width"].get<int>() * (*r)["height"].get<int>());
            EXPECT_EQ((*r)["primary_rays"], (*e)["primary_rays"]) << "the same rays as Embree";
            if (l.usesOctree) {
                EXPECT_TRUE((*r)["octree_faces"].is_number());
                EXPECT_GE((*r)["octree_faces"].get<uint64_t>(), (*r)["primitives"].get<uint64_t>())
                    << "every primitive is referenced by at least one leaf";
                EXPECT_GT((*r)["layout_bytes"].get<uint64_t>(), 0u);
            }
        }
    }
    // Grid clouds: one sphere per deepest leaf, so octree faces equal the points.
    const json* lin = findRow(rows, "grid:1000:1", "linear", "cpu");
    EXPECT_EQ((*lin)["octree_faces"], 1000);
    EXPECT_EQ((*lin)["octree_depth"], (*lin)["grid_depth"]);

    // The CSV: the same columns, one line per row.
    std::vector<std::string> lines = readLines(dir / "out" / "bench.csv");
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines[0], joined(kFields));
    EXPECT_EQ(lines.size(), rows.size() + 1);
    fs::remove_all(dir);
}

TEST(BenchCommand, LimitsAreSkippedRowsWithAReason) {
    fs::path dir = freshDir("skips");
    std::string log;
    // A 1 MiB linear budget refuses the depth-5 tree of 32k points; a tiny --max-seconds makes
    // the time guard skip exhaustive tracing.
    int rc = runOctrace(
        "bench --clouds 32k --meshes none --backends cpu "
        "--accels exhaustive,linear,hash --size 32x32 --repeats 1 --warmup 0 "
        "--max-seconds 1e-6 --linear-budget 1 --no-progress --out '" +
            (dir / "out").string() + "'",
        dir / "log.txt", log);
    ASSERT_EQ(rc, 0) << log;
    json doc = octtest::readJson<json>(dir / "out" / "bench.json");
    const json& rows = doc["results"];
    ASSERT_EQ(rows.size(), 3u) << log;
    const json* exh = findRow(rows, "grid:32000:1", "exhaustive", "cpu");
    const json* lin = findRow(rows, "grid:32000:1", "linear", "cpu");
    ASSERT_TRUE(exh && lin);
    EXPECT_EQ((*exh)["status"], "skipped");
    EXPECT_NE((*exh)["reason"].get<std::string>().find("--max-seconds"), std::string::npos);
    EXPECT_TRUE((*exh)["frame_s_median"].is_null());
    EXPECT_EQ((*lin)["status"], "skipped");
    EXPECT_NE((*lin)["reason"].get<std::string>().find("linear octree"), std::string::npos)
        << (*lin)["reason"];
    // The tree was built before the layout was refused: its figures are still reported.
    EXPECT_EQ((*lin)["octree_faces"], 32000);
    fs::remove_all(dir);
}

// --paired-reference (what --baseline measures with): the configuration says so, and every row
// of ours still carries its ratio, now from the pairs. What the ratios are is timing, not
// asserted.
TEST(BenchCommand, PairedReferenceIsRecordedWithEveryRatio) {
    fs::path dir = freshDir("paired");
    for (const bool paired : {false, true}) {
        std::string log;
        const int rc = runOctrace(
            "bench --clouds 1k --meshes none --backends cpu,embree --accels linear,compact "
            "--size 32x32 --repeats 2 --threads 1 --no-progress --out '" +
                (dir / "out").string() + "'" + (paired ? " --paired-reference" : ""),
            dir / "log.txt", log);
        ASSERT_EQ(rc, 0) << log;
        json doc = octtest::readJson<json>(dir / "out" / "bench.json");
        EXPECT_EQ(doc["config"]["paired_reference"], paired);
        for (const char* layout : {"linear", "compact"}) {
            const json* r = findRow(doc["results"], "grid:1000:1", layout, "cpu");
            ASSERT_NE(r, nullptr) << layout << "\n" << log;
            EXPECT_TRUE((*r)["ratio_to_embree"].is_number()) << r->dump();
            EXPECT_EQ((*r)["repeats"], 2) << "the pairs are the timed frames";
        }
    }
    fs::remove_all(dir);
}

TEST(BenchCommand, BadOptionsFailWithOneLine) {
    fs::path dir = freshDir("bad");
    std::string log;
    EXPECT_NE(runOctrace("bench --clouds 0 --out '" + dir.string() + "'", dir / "log.txt", log), 0);
    EXPECT_NE(log.find("--clouds"), std::string::npos) << log;
    EXPECT_NE(
        runOctrace("bench --backends cpu,gpu --out '" + dir.string() + "'", dir / "log.txt", log),
        0);
    EXPECT_NE(log.find("gpu"), std::string::npos) << log;
    EXPECT_NE(runOctrace("bench --meshes /no/such/mesh.obj --out '" + dir.string() + "'",
                         dir / "log.txt", log),
              0);
    EXPECT_NE(log.find("/no/such/mesh.obj"), std::string::npos) << log;
    fs::remove_all(dir);
}

}  // namespace
