// The odd-but-valid scene corpus (tests/data/odd/, written by make_corpus.py, listed in
// manifest.txt): every file loads with the listed primitive count, nothing dropped, nothing
// printed, and exactly the primitives of its plain twin in tests/data/odd/plain/ (same
// coordinates, same order), so an odd spelling can never change the scene in silence.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/scene/load_scene.h"
#include "tests/core/same_values.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

const std::string kOddDir = std::string(OCT_SOURCE_DIR) + "/tests/data/odd";

struct OddFile {
    std::string file;
    uint32_t primitives = 0;
    std::string reference;
    std::string why;
};

// "FILE PRIMITIVES REFERENCE WHY..."; a malformed line becomes an entry no file matches.
std::vector<OddFile> readOddManifest() {
    std::vector<OddFile> entries;
    std::ifstream in(kOddDir + "/manifest.txt");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        OddFile e;
        if (!(fields >> e.file >> e.primitives >> e.reference)) e.file = "<bad line: " + line + ">";
        std::getline(fields, e.why);
        entries.push_back(e);
    }
    return entries;
}

using octtest::sameVec;

TEST(OddCorpus, ManifestListsEveryFileAndEveryFileExists) {
    const std::vector<OddFile> entries = readOddManifest();
    ASSERT_GE(entries.size(), 10u) << "manifest missing or short: " << kOddDir;
    std::set<std::string> listed;
    for (const OddFile& e : entries) {
        EXPECT_TRUE(listed.insert(e.file).second) << "listed twice: " << e.file;
        EXPECT_TRUE(fs::is_regular_file(kOddDir + "/" + e.file)) << "missing: " << e.file;
        EXPECT_TRUE(fs::is_regular_file(kOddDir + "/" + e.reference)) << "missing: " << e.reference;
        EXPECT_FALSE(e.why.empty()) << e.file << " does not say why it is valid";
    }
    for (const auto& entry : fs::directory_iterator(kOddDir)) {
        if (!entry.is_regular_file()) continue;
        const std::string name = entry.path().filename().string();
        if (name == "manifest.txt" || name == "make_corpus.py") continue;
        EXPECT_TRUE(listed.count(name)) << name << " is in tests/data/odd but not in manifest.txt";
    }
}

TEST(OddCorpus, EveryFileLoadsAsItsPlainTwin) {
    for (const OddFile& e : readOddManifest()) {
        SCOPED_TRACE(e.file + " (" + e.why + ")");
        ::testing::internal::CaptureStderr();
        Scene odd, plain;
        try {
            plain = loadScene(kOddDir + "/" + e.reference);
            odd = loadScene(kOddDir + "/" + e.file);
        } catch (const SceneError& error) {
            ::testing::internal::GetCapturedStderr();
            ADD_FAILURE() << error.what();
            continue;
        }
        EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
        EXPECT_EQ(plain.primitiveCount(), e.primitives) << "the reference itself";
        EXPECT_EQ(odd.primitiveCount(), e.primitives);
        EXPECT_EQ(odd.kind, plain.kind);
        EXPECT_EQ(odd.report.totalDropped(), 0u);
        EXPECT_EQ(odd.report.verticesRead, plain.report.verticesRead);
        EXPECT_EQ(odd.report.facesRead, plain.report.facesRead);
        if (odd.primitiveCount() != plain.primitiveCount()) continue;
        for (size_t i = 0; i < odd.triangles.size(); ++i) {
            const Triangle &a = odd.triangles[i], &b = plain.triangles[i];
            EXPECT_TRUE(sameVec(a.v0, b.v0) && sameVec(a.v1, b.v1) && sameVec(a.v2, b.v2))
                << "triangle " << i << " differs from the plain file's";
        }
        EXPECT_EQ(odd.sourceFace, plain.sourceFace);
        for (size_t i = 0; i < odd.spheres.size(); ++i) {
            EXPECT_TRUE(sameVec(odd.spheres[i].center, plain.spheres[i].center)) << "point " << i;
            EXPECT_EQ(odd.spheres[i].radius, plain.spheres[i].radius) << "point " << i;
        }
    }
}

// The same on the project's own meshes: each text mesh, and the binary PLY (whose header is
// text), given a byte-order mark, loads exactly as the original. For PLY this exercises the
// rewritten copy OpenMesh reads on meshes with normals, texture coordinates and comments.
TEST(OddCorpus, ProjectMeshesWithAByteOrderMarkLoadTheSame) {
    const fs::path dir = fs::temp_directory_path() / ("octrace_odd_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    for (const char* name : {"wuson.obj", "wuson.ply", "cube_binary.ply", "wuson.off",
                             "sphere_with_hole.stl", "cornell_box.obj"}) {
        SCOPED_TRACE(name);
        const std::string original = std::string(OCT_SOURCE_DIR) + "/meshes/" + name;
        const std::string copy = (dir / name).string();
        {
            std::ifstream in(original, std::ios::binary);
            std::ofstream out(copy, std::ios::binary);
            out << "\xEF\xBB\xBF" << in.rdbuf();
        }
        try {
            const Scene a = loadScene(original), b = loadScene(copy);
            ASSERT_EQ(a.primitiveCount(), b.primitiveCount());
            EXPECT_GT(a.primitiveCount(), 0u);
            EXPECT_EQ(a.report.totalDropped(), b.report.totalDropped());
            EXPECT_EQ(a.sourceFace, b.sourceFace);
            size_t differing = 0;
            for (size_t i = 0; i < a.triangles.size(); ++i) {
                const Triangle &p = a.triangles[i], &q = b.triangles[i];
                differing += !(sameVec(p.v0, q.v0) && sameVec(p.v1, q.v1) && sameVec(p.v2, q.v2));
            }
            EXPECT_EQ(differing, 0u);
        } catch (const SceneError& e) {
            ADD_FAILURE() << e.what();
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace oct
