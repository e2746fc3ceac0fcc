// The fast OBJ and ASCII PLY readers (core/scene/obj_fast_reader.cpp, ply_fast_reader.cpp)
// against the reference path they replace (survey, body walk and OpenMesh's readers): the same
// Scene bit for bit (triangles, source faces, every report count) or the same refusal, word for
// word, on every committed mesh, every corpus file and generated edge cases. The committed
// meshes must also be taken by the fast readers, so that this compares two readers, not one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <vector>

#include "core/scene/load_scene.h"
#include "core/scene/loader_detail.h"
#include "core/scene/ply_header.h"
#include "core/scene/text_chunks.h"

namespace oct {
namespace {

// The two arrays hold the same elements bit for bit. memcmp is not called on an empty vector's
// data(), which may be null (UBSan reports a null argument even for zero bytes).
template <class T>
bool sameElementBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

namespace fs = std::filesystem;
using namespace scene_detail;

// What loading a file gave: the scene, or the refusal's message.
struct Outcome {
    bool loaded = false;
    std::string error;
    Scene scene;
};

template <class Load>
Outcome outcomeOf(Load load) {
    Outcome o;
    try {
        o.scene = load();
        o.loaded = true;
    } catch (const SceneError& e) {
        o.error = e.what();
    }
    return o;
}

void expectSameOutcome(const Outcome& fast, const Outcome& reference) {
    ASSERT_EQ(fast.loaded, reference.loaded)
        << "fast: " << fast.error << " | reference: " << reference.error;
    EXPECT_EQ(fast.error, reference.error);
    if (!fast.loaded) return;
    const Scene& a = fast.scene;
    const Scene& b = reference.scene;
    EXPECT_EQ(a.kind, b.kind);
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    EXPECT_TRUE(sameElementBits(a.triangles, b.triangles)) << "triangles differ in some bit";
    EXPECT_EQ(a.sourceFace, b.sourceFace);
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    EXPECT_TRUE(sameElementBits(a.spheres, b.spheres)) << "spheres differ in some bit";
    const LoadReport &r = a.report, &s = b.report;
    EXPECT_EQ(r.format, s.format);
    EXPECT_EQ(r.verticesRead, s.verticesRead);
    EXPECT_EQ(r.facesRead, s.facesRead);
    EXPECT_EQ(r.polygonsTriangulated, s.polygonsTriangulated);
    EXPECT_EQ(r.droppedInvalidIndex, s.droppedInvalidIndex);
    EXPECT_EQ(r.droppedNonFinite, s.droppedNonFinite);
    EXPECT_EQ(r.droppedDegenerate, s.droppedDegenerate);
    EXPECT_EQ(r.droppedTooFewVertices, s.droppedTooFewVertices);
}

// loadObj / loadPly (fast reader first) against the reference path alone.
void expectSameAsReference(const std::string& path) {
    SCOPED_TRACE(path);
    if (lowerExtension(path) == "obj")
        expectSameOutcome(outcomeOf([&] { return loadObj(path, {}); }),
                          outcomeOf([&] { return loadObjWithOpenMesh(path); }));
    else
        expectSameOutcome(outcomeOf([&] { return loadPly(path, {}); }),
                          outcomeOf([&] { return loadPlyWithOpenMesh(path, {}); }));
}

bool fastReaderTakes(const std::string& path) {
    RawMesh raw;
    if (lowerExtension(path) == "ply") return readPlyFast(path, parsePlyHeader(path), raw);
    Survey survey;
    std::vector<std::string> libraries;
    return readObjFast(path, raw, survey, libraries);
}

std::vector<std::string> filesIn(const std::string& dir) {
    std::vector<std::string> files;
    if (!fs::is_directory(dir)) return files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        const std::string ext = lowerExtension(entry.path().string());
        if (entry.is_regular_file() && (ext == "obj" || ext == "ply"))
            files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

TEST(FastReaders, CommittedMeshesAreReadFastAndAsBefore) {
    const std::vector<std::string> meshes = filesIn(std::string(OCT_SOURCE_DIR) + "/meshes");
    ASSERT_GE(meshes.size(), 5u);
    for (const std::string& path : meshes) {
        const bool cached = path.find("/cache/") != std::string::npos;
        // Binary PLY is left to the reference path (cube_binary.ply).
        if (!cached && path.find("binary") == std::string::npos) {
            EXPECT_TRUE(fastReaderTakes(path)) << path;
        }
        expectSameAsReference(path);
    }
}

TEST(FastReaders, BunnyAndDragonsIfFetched) {
    const std::string cache = std::string(OCT_SOURCE_DIR) + "/meshes/cache/";
    int found = 0;
    for (const char* name :
         {"bunny.obj", "dragon_vrip_res4.ply", "dragon_vrip_res2.ply", "dragon_vrip.ply"}) {
        if (!fs::exists(cache + name)) continue;
        ++found;
        EXPECT_TRUE(fastReaderTakes(cache + name)) << name;
        expectSameAsReference(cache + name);
    }
    if (found == 0) GTEST_SKIP() << cache << " not fetched";
}

// Every malformed and odd corpus file: the same scene or the same one-line refusal.
TEST(FastReaders, CorpusFilesLoadOrFailAsBefore) {
    size_t files = 0;
    for (const char* dir : {"/tests/data/bad", "/tests/data/odd"})
        for (const std::string& path : filesIn(std::string(OCT_SOURCE_DIR) + dir)) {
            ++files;
            expectSameAsReference(path);
        }
    EXPECT_GE(files, 40u);
}

// The chunks cover the text after `from` once, in order, each ending at a line's end, so that
// the lines read chunk by chunk are the lines of the whole text.
TEST(FastReaders, ChunksAreWholeLinesInOrder) {
    std::string text = "\xEF\xBB\xBF";
    for (int i = 0; i < 20000; ++i) text += "line " + std::to_string(i) + (i % 7 ? "\n" : "\r\n");
    text += "last line without a break";
    const auto chunks = lineAlignedChunks(text, 3);
    ASSERT_GT(chunks.size(), 1u);
    size_t next = 3;
    std::string joined;
    for (const auto& [begin, end] : chunks) {
        EXPECT_EQ(begin, next);
        EXPECT_LT(begin, end);
        if (end < text.size()) {
            EXPECT_EQ(text[end - 1], '\n');
        }
        joined += text.substr(begin, end - begin);
        next = end;
    }
    EXPECT_EQ(next, text.size());
    EXPECT_EQ(joined, text.substr(3));
    EXPECT_TRUE(lineAlignedChunks(text, text.size()).empty());
}

// An exception in one chunk reaches the caller after the parallel loop (not std::terminate),
// so that running out of memory while parsing is still loadScene's one-line SceneError.
TEST(FastReaders, AnExceptionInAChunkReachesTheCaller) {
    std::vector<int> ran(64, 0);
    EXPECT_THROW(forEachChunk(ran.size(),
                              [&](size_t i) {
                                  ran[i] = 1;
                                  if (i == 5) throw SceneError("chunk 5");
                              }),
                 SceneError);
    EXPECT_EQ(ran[5], 1);
    EXPECT_THROW(forEachChunk(8,
                              [](size_t i) {
                                  if (i % 2) throw std::bad_alloc();
                              }),
                 std::bad_alloc);
    forEachChunk(ran.size(), [&](size_t i) { ran[i] = 2; });
    EXPECT_EQ(std::count(ran.begin(), ran.end(), 2), 64);
}

class GeneratedFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("octrace_fast_readers_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }

    // Each case is written as `name` holding head + its body; the fast reader must take it
    // exactly when the case says so, and load it as the reference path does.
    void expectCases(const std::string& name, const std::string& head,
                     const std::vector<std::pair<std::string, bool>>& cases) {
        for (const auto& [body, fast] : cases) {
            const std::string path = write(name, head + body);
            SCOPED_TRACE(body);
            EXPECT_EQ(fastReaderTakes(path), fast);
            expectSameAsReference(path);
        }
    }

    fs::path dir_;
};

// A grid of w x h vertices as "v" lines and its quads as "f" lines, written with the corner
// forms in turn and every other row with negative (relative) indices, so that relative indices
// cross the readers' chunk boundaries.
std::string gridObj(int w, int h, const std::string& eol) {
    std::string text = "# grid" + eol;
    std::vector<std::string> forms = {"", "/1", "//1", "/1/1"};
    int written = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x, ++written)
            text += "v " + std::to_string(x * 0.1) + " " + std::to_string(y * 0.37) + " " +
                    std::to_string((x * y) % 7 * 1e-3) + eol;
        if (y == 0) continue;
        for (int x = 0; x + 1 < w; ++x) {
            const int a = (y - 1) * w + x + 1, b = a + 1, c = a + w + 1, d = a + w;
            const std::string& form = forms[size_t(x) % forms.size()];
            auto corner = [&](int i) {
                return (y % 2 ? std::to_string(i) : std::to_string(i - written - 1)) + form;
            };
            text += "f " + corner(a) + " " + corner(b) + " " + corner(c) + " " + corner(d) + eol;
        }
        text += "vt 0.5 0.5" + eol + "g row" + std::to_string(y) + eol;
    }
    return text;
}

TEST_F(GeneratedFiles, ObjGridsInManyChunks) {
    for (const char* eol : {"\n", "\r\n"}) {
        const std::string path = write("grid.obj", gridObj(120, 90, eol));
        EXPECT_TRUE(fastReaderTakes(path)) << "eol " << (eol[1] ? "CRLF" : "LF");
        expectSameAsReference(path);
    }
    const std::string bom = write("bom.obj", std::string(kUtf8Bom) + gridObj(30, 20, "\n"));
    EXPECT_TRUE(fastReaderTakes(bom));
    expectSameAsReference(bom);
}

// Statements the fast reader takes and the ones it leaves to the reference path, each in a
// small mesh with one good triangle so that the file loads.
TEST_F(GeneratedFiles, ObjEdgeCases) {
    const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
    const std::vector<std::pair<std::string, bool>> cases = {
        // {what follows the four vertices, whether the fast reader takes the file}
        {"f 1 2 3\n", true},
        {"f 1 2 3 4\nf -1 -2 -3\n", true},                  // polygon, relative indices
        {"f 1/1/1 2//2 3/3\n", true},                       // corner forms
        {"f 1 2 3\nf 1 2 9\nf 1 2 0\nf -9 1 2\n", true},    // out of range, zero, too relative
        {"f 1 2 3\nf 1 1 2\nf 1 2\nf 1 1 1 2\n", true},     // repeated corners, too few
        {"f 1 2 3\nf 1 2 3 5\n", true},                     // forward reference, out of range
        {"f 1 2 3\nf 1 2 4\nv 5 5 5\nf 1 2 5\n", true},     // vertex after faces
        {"\tf 1 2 3 \r\n  # comment \\\nv 1 1 1\n", true},  // blanks, CRLF, comment with '\'
        {"o thing\ns 1\nusemtl none\nvn 0 0 1\nf 1 2 3\n", true},
        {"mtllib missing.mtl\nf 1 2 3\n", true},
        {"v 1 2 3 0.5 0.5 0.5\nf 1 2 5\n", true},  // colours after the coordinates
        {"f 1 2 3 # comment\n", false},            // a word where a corner goes
        {"f 1 2 \\\n 3\n", false},                 // continued statement
        {"v 1e39 0 0\nf 1 2 5\n", false},          // overflow
        {"v nan 0 0\nf 1 2 5\nf 1 2 3\n", false},
        {"v 1 2\nf 1 2 3\n", false},       // short vertex
        {"v +1 0 0\nf 1 2 3\n", false},    // a sign from_chars refuses
        {"f 1 2 3 99999999999\n", false},  // beyond int
        {"f /1 2 3\n", false},             // corner without a vertex
        {"vt x y\nf 1 2 3\n", false},
        {"\vv 3 3 3\nf 1 2 3\n", false},  // '\v' before the keyword
    };
    expectCases("case.obj", base, cases);
}

std::string gridPly(int w, int h, const std::string& eol, const std::string& extra = "") {
    std::string vertices, faces;
    int faceCount = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            vertices += std::to_string(x * 0.1) + " " + std::to_string(y * 0.37) + " " +
                        std::to_string((x * y) % 7 * 1e-3) + eol;
    for (int y = 0; y + 1 < h; ++y)
        for (int x = 0; x + 1 < w; ++x, ++faceCount) {
            const int a = y * w + x, b = a + 1, c = a + w + 1, d = a + w;
            faces += (x % 3 == 0 ? "4 " + std::to_string(a) + " " + std::to_string(b) + " " +
                                       std::to_string(c) + " " + std::to_string(d)
                                 : "3 " + std::to_string(a) + " " + std::to_string(b) + " " +
                                       std::to_string(c)) +
                     eol;
        }
    return "ply" + eol + "format ascii 1.0" + eol + "comment grid" + eol + "element vertex " +
           std::to_string(w * h) + eol + "property float x" + eol + "property float y" + eol +
           "property float z" + eol + "element face " + std::to_string(faceCount) + eol +
           "property list uchar int vertex_indices" + eol + "end_header" + eol + vertices + faces +
           extra;
}

TEST_F(GeneratedFiles, PlyGridsInManyChunks) {
    for (const char* eol : {"\n", "\r\n"}) {
        const std::string path = write("grid.ply", gridPly(150, 100, eol));
        EXPECT_TRUE(fastReaderTakes(path));
        expectSameAsReference(path);
    }
    // After the faces OpenMesh stops reading; so does the fast reader.
    const std::string tail = write("tail.ply", gridPly(20, 20, "\n", "garbage after faces\n"));
    EXPECT_TRUE(fastReaderTakes(tail));
    expectSameAsReference(tail);
}

TEST_F(GeneratedFiles, PlyEdgeCases) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
    const std::vector<std::pair<std::string, bool>> cases = {
        {vertices + "3 0 1 2\n4 0 1 3 2\n", true},
        {vertices + "3 0 1 2\n3 0 1 2", true},     // no final line break
        {vertices + "3 0 1 2\n3 0 1 9\n", false},  // out of range: dropped there
        {vertices + "3 0 1 2\n2 0 1\n", false},    // too few
        {vertices + "3 0 1 2\n3 0 1 -1\n", false},
        {vertices + "3 0 1 2\n3 0 1\n2\n", false},                    // a face over two lines
        {vertices + "3 0 1 2\n", false},                              // truncated
        {"0 0 0\n1 0 0 1\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n", false},  // a fourth value
        {"0 0 0\n3.4028235e38 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n", false},  // beyond FLT_MAX
        {"0 0 0\n1e39 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n", false},
        {"0 0 0\nnan 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n", false},
    };
    expectCases("case.ply", head, cases);
}

// Vertex properties beside x, y and z, as Blender and scanners write them: normals (read as
// floats), integer colours (ints), unknown ones (any word), in any order.
TEST_F(GeneratedFiles, PlyVertexPropertiesBesideXyz) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float nx\nproperty float z\n"
        "property uchar red\nproperty float x\nproperty float confidence\nproperty float y\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const std::vector<std::pair<std::string, bool>> cases = {
        {"0 0.5 255 0 w 0\n1 0 0 1 1 0\n0 0 0 0 1 1\n1 0 0 1 1 1\n3 0 1 2\n4 0 1 3 2\n", true},
        {"0 0.5 0.5 0 w 0\n1 0 0 1 1 0\n0 0 0 0 1 1\n1 0 0 1 1 1\n3 0 1 2\n3 0 1 3\n", false},
        {"nan 0.5 2 0 w 0\n1 0 0 1 1 0\n0 0 0 0 1 1\n1 0 0 1 1 1\n3 0 1 2\n3 0 1 3\n", false},
        {"0 0.5 2 0 w\n1 0 0 1 1 0\n0 0 0 0 1 1\n1 0 0 1 1 1\n3 0 1 2\n3 0 1 3\n", false},
    };
    expectCases("props.ply", head, cases);
}

}  // namespace
}  // namespace oct
