// `octrace bench --rays R.npy --scene MESH` end to end: a small ray file of `octrace rays` on the
// committed teapot, every case as a row of the table and of rays-bench.json/.csv, our layouts
// agreeing on every hit, and bad inputs refused with one line naming the file or the value.
// Timings are never asserted (only that they are there), so the tests hold on a loaded machine.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/io/npy.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using octtest::kTeapot;

struct RayBenchRun : ::testing::Test {
    octtest::TempDir dir{"bench_rays"};

    std::string path(const std::string& name) const { return dir.str(name); }
    octtest::RunResult run(const std::vector<std::string>& args) const {
        return octtest::runOctrace(args, dir.path() / "capture");
    }
    // A few hundred camera rays and the seeded sets (edges, vertices, grazing rays: where
    // tracers disagree if any do) on the teapot.
    void makeRays() const {
        const octtest::RunResult r =
            run({"rays", kTeapot, "--count", "600", "--size", "16x16", "--out", path("R.npy")});
        ASSERT_EQ(r.status, 0) << octtest::show(r);
    }
    std::vector<std::string> bench(const std::vector<std::string>& more) const {
        std::vector<std::string> args = {"bench", "--rays", path("R.npy"), "--scene",
                                         kTeapot, "--out",  path("out"),   "--no-progress"};
        args.insert(args.end(), more.begin(), more.end());
        return args;
    }
};

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// The table's row of a case: the line whose first two words are its layout and backend.
bool hasRow(const std::string& out, const std::string& layout, const std::string& backend) {
    for (const std::string& l : lines(out)) {
        std::istringstream words(l);
        std::string a, b;
        if (words >> a >> b && a == layout && b == backend) return true;
    }
    return false;
}

const json* findCase(const json& rows, const std::string& layout, const std::string& backend) {
    for (const json& r : rows)
        if (r["layout"] == layout && r["backend"] == backend) return &r;
    return nullptr;
}

// The key of a row's ratio to a backend (ray_bench.cpp: '-' spelled '_').
std::string ratioKey(const std::string& backend) {
    std::string k = "ratio_to_" + backend;
    for (char& c : k)
        if (c == '-') c = '_';
    return k;
}

TEST_F(RayBenchRun, EveryLayoutAndEmbreeIsARowAndTheLayoutsAgree) {
    makeRays();
    const uint64_t rays = oct::readNpy(path("R.npy")).shape[0];
    const std::string own = std::string(oct::referenceBackend().name);
    std::vector<const oct::BackendDesc*> references;  // the backends with their own structure
    for (const oct::BackendDesc& b : oct::backends())
        if (!b.usesLayouts) references.push_back(&b);
    std::string backendList = oct::hostBackend().name;
    for (const oct::BackendDesc* b : references) backendList += std::string(",") + b->name;

    const octtest::RunResult r = run(bench({"--accel", "all", "--backend", backendList, "--repeats",
                                            "2", "--warmup", "0", "--threads", "2"}));
    ASSERT_EQ(r.status, 0) << octtest::show(r);

    const std::string host = oct::hostBackend().name;
    for (const oct::LayoutDesc& l : oct::layouts())
        EXPECT_TRUE(hasRow(r.out, l.name, host)) << l.name << "\n" << r.out;
    for (const oct::BackendDesc* b : references)
        EXPECT_TRUE(hasRow(r.out, b->structure, b->name)) << b->name << "\n" << r.out;

    const json doc = octtest::readJson<json>(dir.path() / "out" / "rays-bench.json");
    EXPECT_EQ(doc["format"], "octrace-rays-bench/1");
    EXPECT_EQ(doc["rays"], rays);
    for (const char* k : {"cpu_model", "omp_threads", "load_average_start", "load_average_end"})
        EXPECT_TRUE(doc["machine"].contains(k)) << k;
    for (const char* k : {"command", "command_line", "rays_file", "scene", "layouts", "backends",
                          "warmup", "repeats", "threads", "max_depth", "max_prims"})
        EXPECT_TRUE(doc["config"].contains(k)) << k;
    EXPECT_EQ(doc["config"]["threads"], 2);
    for (const char* k : {"read_s", "load_s"}) EXPECT_TRUE(doc[k].is_number()) << k;
    // Compared with the first octree layout's case: exhaustive comes first in the list.
    const oct::LayoutDesc& compared = oct::findLayout(doc["compared_with"]["layout"]);
    EXPECT_TRUE(compared.usesOctree);
    EXPECT_EQ(doc["compared_with"]["backend"], host);

    const json& rows = doc["results"];
    ASSERT_EQ(rows.size(), oct::layouts().size() + references.size()) << rows.dump(1);
    const json* first = findCase(rows, compared.name, host);
    ASSERT_NE(first, nullptr);
    for (const json& row : rows) {
        const std::string name =
            row["layout"].get<std::string>() + "/" + row["backend"].get<std::string>();
        for (const char* k :
             {"rays", "hits", "trace_s_median", "trace_s_min", "trace_s_max", "mrays_per_s",
              "tree_build_s", "convert_s", "build_s", "upload_s", "outside_s", "layout_bytes",
              "other_prim", "other_t", "max_relative_dt"})
            EXPECT_TRUE(row[k].is_number()) << name << " " << k;
        for (const oct::BackendDesc* b : references)
            EXPECT_TRUE(row.contains(ratioKey(b->name))) << name << " " << b->name;
        EXPECT_EQ(row["rays"], rays) << name;
        EXPECT_EQ(row["trace_s"].size(), 2u) << name << ": a time per timed round";
        EXPECT_GE(row["outside_s"].get<double>(), row["build_s"].get<double>()) << name;
        if (row["backend"] == host) {
            // The same kernel on the same canonical octree: every hit the same, to the bit.
            EXPECT_EQ(row["other_prim"], 0) << name;
            EXPECT_EQ(row["other_t"], 0) << name;
            EXPECT_EQ(row["hits"], (*first)["hits"]) << name;
        }
    }
    // Embree traces the same rays: a reference's ratio to itself is 1.
    const json* embree = findCase(rows, oct::referenceBackend().structure, own);
    ASSERT_NE(embree, nullptr);
    EXPECT_DOUBLE_EQ((*embree)[ratioKey(own)].get<double>(), 1.0);

    // The CSV: the JSON rows' scalar fields, one line per case.
    const std::vector<std::string> csv =
        lines(octtest::readFile(dir.path() / "out" / "rays-bench.csv"));
    ASSERT_EQ(csv.size(), rows.size() + 1);
    std::string header;
    for (auto it = rows[0].begin(); it != rows[0].end(); ++it)
        if (!it->is_array()) header += (header.empty() ? "" : ",") + it.key();
    EXPECT_EQ(csv[0], header);
}

// Without --accel and --backend: the layouts with an octree on the host kernel, and every
// backend with its own structure (Embree, robust and fast; the scalar binary BVH).
TEST_F(RayBenchRun, DefaultCasesAreTheOctreeLayoutsAndEmbree) {
    makeRays();
    const octtest::RunResult r = run(bench({"--rounds", "1", "--warmup", "0"}));
    ASSERT_EQ(r.status, 0) << octtest::show(r);
    const json doc = octtest::readJson<json>(dir.path() / "out" / "rays-bench.json");
    size_t octreeLayouts = 0, ours = 1, own = 0;
    for (const oct::LayoutDesc& l : oct::layouts()) {
        EXPECT_EQ(l.usesOctree, hasRow(r.out, l.name, oct::hostBackend().name)) << l.name;
        octreeLayouts += l.usesOctree;
    }
    for (const oct::BackendDesc& b : oct::backends()) {
        std::string why;
        if (b.device && b.available(why)) ++ours;  // an accelerator that answers: its cases too
        if (b.usesLayouts) continue;
        EXPECT_TRUE(hasRow(r.out, b.structure, b.name)) << b.name << "\n" << r.out;
        ++own;
    }
    EXPECT_EQ(doc["results"].size(), octreeLayouts * ours + own) << r.out;
    EXPECT_EQ(doc["config"]["repeats"], 1);
    // The command that repeats the run names every choice.
    const std::string command = doc["config"]["command"];
    EXPECT_NE(command.find("--accel "), std::string::npos) << command;
    EXPECT_NE(command.find("--backend "), std::string::npos) << command;
    EXPECT_NE(r.out.find(command), std::string::npos) << r.out;
}

// On a point cloud the defaults leave out each backend that holds triangles only (the binary
// BVH), saying so; named with --backend, it refuses the cloud with one line naming it.
TEST_F(RayBenchRun, APointCloudLeavesOutTheTriangleOnlyBackends) {
    const std::string cloud = "grid:2000:3";
    octtest::RunResult r =
        run({"rays", cloud, "--count", "300", "--size", "8x8", "--out", path("C.npy")});
    ASSERT_EQ(r.status, 0) << octtest::show(r);
    std::vector<std::string> args = {"bench",    "--rays", path("C.npy"), "--scene",
                                     cloud,      "--out",  path("out"),   "--no-progress",
                                     "--rounds", "1",      "--warmup",    "0"};
    r = run(args);
    ASSERT_EQ(r.status, 0) << octtest::show(r);
    size_t triangleOnly = 0;
    for (const oct::BackendDesc& b : oct::backends()) {
        if (!b.trianglesOnly) continue;
        ++triangleOnly;
        EXPECT_FALSE(hasRow(r.out, b.structure, b.name)) << b.name << "\n" << r.out;
        EXPECT_NE(r.err.find(std::string(b.name) + " left out: it traces triangle meshes only"),
                  std::string::npos)
            << octtest::show(r);
        args.insert(args.end(), {"--backend", b.name});
        const octtest::RunResult named = run(args);
        EXPECT_TRUE(octtest::isOneLineError(named)) << octtest::show(named);
        EXPECT_NE(named.err.find("point cloud"), std::string::npos) << octtest::show(named);
        args.resize(args.size() - 2);
    }
    EXPECT_GT(triangleOnly, 0u) << "no backend of the list holds triangles only";
    EXPECT_TRUE(hasRow(r.out, oct::referenceBackend().structure, oct::referenceBackend().name))
        << r.out;
}

TEST_F(RayBenchRun, BadInputsAreRefusedWithOneLine) {
    makeRays();
    auto refused = [&](const std::vector<std::string>& args, const std::string& text) {
        const octtest::RunResult r = run(args);
        EXPECT_TRUE(octtest::isOneLineError(r));
        EXPECT_NE(r.err.find(text), std::string::npos) << text << "\n" << octtest::show(r);
        EXPECT_FALSE(fs::exists(path("out/rays-bench.json"))) << octtest::show(r);
    };
    // A missing ray file, one of the wrong shape, one with no rows.
    std::vector<std::string> args = bench({});
    args[2] = path("missing.npy");
    refused(args, "--rays: cannot open the ray file '" + path("missing.npy") + "'");
    const std::vector<float> four(12, 1.0f);
    oct::writeNpy(path("four.npy"), "<f4", {3, 4}, four.data(), 4);
    args[2] = path("four.npy");
    refused(args, "shape (N, 8)");
    oct::writeNpy(path("empty.npy"), "<f4", {0, 8}, four.data(), 4);
    args[2] = path("empty.npy");
    refused(args, "holds no rays");
    // An unknown layout or backend; a backend this build or machine cannot run.
    refused(bench({"--accel", "linear,octo"}), "'octo'");
    refused(bench({"--backend", "cpu,optix"}), "'optix'");
    const oct::BackendDesc* cuda = oct::findBackend("cuda");
    std::string why;
    if (!cuda || !cuda->available(why)) refused(bench({"--backend", "cuda"}), "--backend cuda");
    // A missing scene; --rays and --scene without each other; the sweep's options beside --rays.
    args = bench({});
    args[4] = path("missing.obj");
    refused(args, "--scene: cannot open '" + path("missing.obj") + "'");
    refused({"bench", "--rays", path("R.npy"), "--out", path("out")}, "--rays requires --scene");
    refused({"bench", "--scene", kTeapot, "--out", path("out")}, "--scene requires --rays");
    refused(bench({"--clouds", "1k"}), "--clouds excludes --rays");
    refused(bench({"--size", "64x64"}), "--size excludes --rays");
}

}  // namespace
