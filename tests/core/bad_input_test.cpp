// The malformed-scene corpus (tests/data/bad/, written by make_corpus.py, listed in
// manifest.txt) through loadScene: every file either fails with a one-line SceneError naming
// the path and the expected reason, or loads with exactly the expected drop report, prints
// nothing on stderr, builds an octree, and takes well under a few seconds. Plus what a corpus
// file cannot hold: a directory, a missing file, a FIFO, a device, an unreadable file, and
// every truncation of valid binary files.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/scene/load_scene.h"
#include "tests/bad_manifest.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::BadFile;
using octtest::kBadDir;
const auto readManifest = octtest::readBadManifest;

TEST(BadCorpus, ManifestListsEveryFileAndEveryFileExists) {
    const std::vector<BadFile> entries = readManifest();
    ASSERT_GE(entries.size(), 50u) << "manifest missing or short: " << kBadDir;
    std::set<std::string> listed;
    for (const BadFile& e : entries) {
        EXPECT_TRUE(listed.insert(e.file).second) << "listed twice: " << e.file;
        EXPECT_TRUE(fs::is_regular_file(kBadDir + "/" + e.file)) << "missing: " << e.file;
    }
    for (const auto& entry : fs::recursive_directory_iterator(kBadDir)) {
        if (!entry.is_regular_file()) continue;
        const std::string rel = fs::relative(entry.path(), kBadDir).string();
        if (rel == "manifest.txt" || rel == "make_corpus.py" || rel == "README.md") continue;
        EXPECT_TRUE(listed.count(rel)) << rel << " is in tests/data/bad but not in manifest.txt";
    }
}

uint64_t dropCount(const LoadReport& r, const std::string& key) {
    if (key == "invalid_index") return r.droppedInvalidIndex;
    if (key == "non_finite") return r.droppedNonFinite;
    if (key == "degenerate") return r.droppedDegenerate;
    if (key == "too_few_vertices") return r.droppedTooFewVertices;
    ADD_FAILURE() << "unknown drop key " << key;
    return 0;
}

// One corpus file: a one-line SceneError with the expected text, or exactly the expected drops.
void checkCorpusFile(const BadFile& e) {
    const std::string path = kBadDir + "/" + e.file;
    const auto start = std::chrono::steady_clock::now();
    ::testing::internal::CaptureStderr();
    std::string error;
    Scene scene;
    bool loaded = false;
    try {
        scene = loadScene(path);
        loaded = true;
    } catch (const SceneError& ex) {
        error = ex.what();
    }
    const std::string stderrText = ::testing::internal::GetCapturedStderr();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 3.0) << "loading took " << seconds << " s";
    EXPECT_EQ(stderrText, "") << "a problem must be reported, not only printed";

    if (e.expectError) {
        ASSERT_FALSE(loaded) << e.file << " loaded " << scene.primitiveCount()
                             << " primitives; expected an error containing '" << e.errorText << "'";
        EXPECT_NE(error.find(path), std::string::npos) << "error must name the path: " << error;
        EXPECT_NE(error.find(e.errorText), std::string::npos) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << "error must be one line: " << error;
        return;
    }
    ASSERT_TRUE(loaded) << error;
    EXPECT_GT(scene.primitiveCount(), 0u);
    uint64_t expectedTotal = 0;
    for (const char* key : {"invalid_index", "non_finite", "degenerate", "too_few_vertices"}) {
        auto it = e.drops.find(key);
        const uint64_t expected = it == e.drops.end() ? 0 : it->second;
        expectedTotal += expected;
        EXPECT_EQ(dropCount(scene.report, key), expected) << key;
    }
    EXPECT_EQ(scene.report.totalDropped(), expectedTotal);
    // What loads must also build: the octree never sees a non-finite or out-of-range value.
    BuildParams params;
    params.maxDepth = 6;
    const Octree tree = buildOctree(scene, params);
    EXPECT_GT(tree.nodes.size(), 0u);
    for (const Triangle& t : scene.triangles)
        EXPECT_TRUE(isFinite(t.v0) && isFinite(t.v1) && isFinite(t.v2));
    for (const Sphere& s : scene.spheres) EXPECT_TRUE(isFinite(s.center));
}

TEST(BadCorpus, EveryFileFailsCleanlyOrReportsEveryDrop) {
    for (const BadFile& e : readManifest()) {
        SCOPED_TRACE(e.file);
        checkCorpusFile(e);
    }
}

// ---------------------------------------------------------------------------------------------
// What the corpus cannot hold

class BadPaths : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        dir_ = fs::temp_directory_path() / ("octrace_bad_input_" + std::to_string(::getpid()) +
                                            "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::all, ec);
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::string write(const std::string& name, const std::string& bytes) const {
        std::ofstream(path(name), std::ios::binary) << bytes;
        return path(name);
    }
    static void expectError(const std::string& p, const std::string& what) {
        try {
            loadScene(p);
            ADD_FAILURE() << "no SceneError for " << p;
        } catch (const SceneError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(p), std::string::npos) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
    fs::path dir_;
};

TEST_F(BadPaths, DirectoryMissingUnknownAndSpecialFiles) {
    fs::create_directories(path("looks_like_a_mesh.obj"));
    expectError(path("looks_like_a_mesh.obj"), "directory");
    expectError(path("missing.ply"), "No such file");
    expectError(path("missing_dir/missing.ply"), "No such file");
    expectError(write("mesh.3ds", "x"), "unknown scene format");
    // A FIFO would block a reader forever; /dev/zero never ends.
    ASSERT_EQ(::mkfifo(path("pipe.obj").c_str(), 0600), 0) << std::strerror(errno);
    expectError(path("pipe.obj"), "not a regular file");
    fs::create_symlink("/dev/zero", path("zero.xyz"));
    expectError(path("zero.xyz"), "not a regular file");
    // A symlink to a good file is fine.
    write("good.xyz", "0 0 0\n1 0 0\n");
    fs::create_symlink(path("good.xyz"), path("link.xyz"));
    EXPECT_EQ(loadScene(path("link.xyz")).primitiveCount(), 2u);
}

TEST_F(BadPaths, UnreadableFile) {
    const std::string p = write("secret.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::permissions(p, fs::perms::none);
    if (std::ifstream(p).good()) GTEST_SKIP() << "running as root: permissions are not enforced";
    expectError(p, "Permission denied");
}

// Every proper prefix of a valid binary file is a truncated file; none may load, crash or hang.
TEST_F(BadPaths, EveryTruncationOfBinaryFilesIsRefused) {
    auto f32 = [](std::string& out, std::initializer_list<float> values) {
        for (float v : values) out.append(reinterpret_cast<const char*>(&v), 4);
    };
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty "
        "float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "end_header\n";
    f32(ply, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
    for (int f = 0; f < 2; ++f) {
        ply += char(3);
        const int32_t idx[3] = {0, 1, 2 + f};
        ply.append(reinterpret_cast<const char*>(idx), sizeof idx);
    }
    std::string stl(80, ' ');
    const uint32_t facets = 2;
    stl.append(reinterpret_cast<const char*>(&facets), 4);
    for (int f = 0; f < 2; ++f) {
        f32(stl, {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, float(f)});
        stl.append(2, '\0');
    }
    std::string off = "OFF BINARY\n";
    const uint32_t counts[3] = {3, 1, 0}, face[4] = {3, 0, 1, 2};
    off.append(reinterpret_cast<const char*>(counts), sizeof counts);
    f32(off, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    off.append(reinterpret_cast<const char*>(face), sizeof face);

    for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
             {"t.ply", ply}, {"t.stl", stl}, {"t.off", off}}) {
        ASSERT_GT(loadScene(write(name, bytes)).primitiveCount(), 0u) << name;
        for (size_t n = 0; n < bytes.size(); ++n) {
            const std::string p = write(name, bytes.substr(0, n));
            EXPECT_THROW(loadScene(p), SceneError) << name << " cut to " << n << " bytes";
        }
    }
}

// Random bytes and random single-byte corruptions of valid ASCII files: a SceneError or a
// scene, nothing else (the fuzzer in fuzz/ does this at scale; this is its seeded smoke test).
TEST_F(BadPaths, CorruptedFilesFailOnlyWithSceneError) {
    const std::vector<std::pair<std::string, std::string>> valid = {
        {"c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\n"},
        {"c.ply",
         "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty "
         "float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 "
         "0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"},
        {"c.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"},
        {"c.stl",
         "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\nendsolid t\n"},
        {"c.xyz", "0 0 0\n1 0 0\n0 1 0\n"}};
    std::mt19937 rng(20260507u);
    const std::string alphabet = "0123456789 -+.eE\n\r/#nafiOFFvxyz\t";
    for (const auto& [name, text] : valid) {
        for (int trial = 0; trial < 60; ++trial) {
            std::string bytes = text;
            const int edits = 1 + int(rng() % 3);
            for (int k = 0; k < edits; ++k) {
                const size_t at = rng() % bytes.size();
                switch (rng() % 3) {
                    case 0:
                        bytes[at] = alphabet[rng() % alphabet.size()];
                        break;
                    case 1:
                        bytes.erase(at, 1 + rng() % 4);
                        break;
                    default:
                        bytes.insert(at, 1, char(rng() % 256));
                }
                if (bytes.empty()) bytes = "x";
            }
            const std::string p = write(name, bytes);
            try {
                Scene s = loadScene(p);
                EXPECT_GT(s.primitiveCount(), 0u);
            } catch (const SceneError&) {
            } catch (const std::exception& e) {
                ADD_FAILURE() << name << " trial " << trial << ": " << e.what();
            }
        }
    }
}

}  // namespace
}  // namespace oct
