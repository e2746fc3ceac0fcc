// Scene loading and the grid cloud: real files written to a temporary folder, read back through
// loadScene, and checked against what was written; the radius rule against brute force; the
// grid cloud against an independent derivation of its first cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "tests/core/same_values.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::sameVec;

::testing::AssertionResult triangleIs(const Triangle& t, Vec3 a, Vec3 b, Vec3 c) {
    if (sameVec(t.v0, a) && sameVec(t.v1, b) && sameVec(t.v2, c))
        return ::testing::AssertionSuccess();
    auto s = [](Vec3 v) {
        return "(" + std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z) +
               ")";
    };
    return ::testing::AssertionFailure()
           << "triangle " << s(t.v0) << s(t.v1) << s(t.v2) << " expected " << s(a) << s(b) << s(c);
}

// Little-endian byte writer for the binary formats (x86 and ARM hosts are little-endian).
struct Bytes {
    std::string data;
    Bytes& text(const std::string& s) {
        data += s;
        return *this;
    }
    template <class T>
    Bytes& put(T v) {
        char raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));
        data.append(raw, sizeof(T));
        return *this;
    }
    Bytes& vec(Vec3 v) { return put(v.x).put(v.y).put(v.z); }
};

class SceneFiles : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        std::random_device rd;
        dir_ = fs::temp_directory_path() /
               ("octrace_scene_test_" + std::to_string(rd()) + "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string write(const std::string& name, const std::string& content) {
        fs::path p = dir_ / name;
        std::ofstream out(p, std::ios::binary);
        out << content;
        return p.string();
    }
    std::string dir() const { return dir_.string(); }
    // The plain OFF file of kOffQuadAndTriangle (a quad and a triangle), loaded.
    Scene plainOff();

    // Loads and expects a SceneError whose message names the path and contains `what`.
    void expectError(const std::string& path, const std::string& what,
                     const LoadOptions& opts = {}) {
        try {
            loadScene(path, opts);
            ADD_FAILURE() << "no SceneError for " << path;
        } catch (const SceneError& e) {
            std::string msg = e.what();
            EXPECT_NE(msg.find(path), std::string::npos) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }

private:
    fs::path dir_;
};

const Vec3 kA{0, 0, 0}, kB{1, 0, 0}, kC{0, 1, 0}, kD{1, 1, 0}, kE{0, 0, 1};

// ---------------------------------------------------------------------------------------------
// Meshes

TEST_F(SceneFiles, ObjTrianglesKeepFileOrderAndCoordinates) {
    std::string path = write("two.obj",
                             "# two triangles\n"
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                             "f 1 2 3\n"
                             "f 4/1/1 -3/2/2 -4/3/3\n");
    Scene s = loadScene(path);
    EXPECT_EQ(s.kind, PrimKind::Triangles);
    EXPECT_EQ(s.name, path);
    EXPECT_EQ(s.report.format, "obj");
    EXPECT_EQ(s.report.verticesRead, 4u);
    EXPECT_EQ(s.report.facesRead, 2u);
    EXPECT_EQ(s.report.totalDropped(), 0u);
    ASSERT_EQ(s.primitiveCount(), 2u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
    EXPECT_TRUE(triangleIs(s.triangles[1], kE, kB, kA));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 1}));
    EXPECT_FALSE(s.domain.has_value());
    EXPECT_EQ(s.gridDepth, -1);
}

TEST_F(SceneFiles, QuadIsFanTriangulatedInOrder) {
    std::string path = write("quad.obj",
                             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                             "f 1 2 5\n"
                             "f 1 2 3 4\n"
                             "f 2 3 5\n");
    Scene s = loadScene(path);
    ASSERT_EQ(s.primitiveCount(), 4u);
    EXPECT_EQ(s.report.polygonsTriangulated, 1u);
    EXPECT_TRUE(triangleIs(s.triangles[1], kA, kB, kD));
    EXPECT_TRUE(triangleIs(s.triangles[2], kA, kD, kC));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 1, 1, 2}));
}

TEST_F(SceneFiles, NonManifoldAndDuplicateFacesAreAllKept) {
    // Three triangles on edge 1-2 (a fin), plus the first face repeated verbatim: an OpenMesh
    // mesh can hold neither, our importer keeps all four in order.
    std::string path = write("fin.obj",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                             "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 3\n");
    Scene s = loadScene(path);
    ASSERT_EQ(s.primitiveCount(), 4u);
    EXPECT_EQ(s.report.totalDropped(), 0u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
    EXPECT_TRUE(triangleIs(s.triangles[1], kB, kA, Vec3{0, -1, 0}));
    EXPECT_TRUE(triangleIs(s.triangles[2], kA, kB, kE));
    EXPECT_TRUE(triangleIs(s.triangles[3], kA, kB, kC));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 1, 2, 3}));
}

TEST_F(SceneFiles, InvalidIndicesAreDroppedAndCounted) {
    std::string path = write("bad_index.obj",
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                             "f 1 2 9\n"   // past the end
                             "f 1 2 -7\n"  // relative index before the first vertex
                             "f 0 1 2\n"   // OBJ counts from 1: 0 names nothing
                             "f 1 2 3\n");
    Scene s = loadScene(path);
    EXPECT_EQ(s.report.facesRead, 4u);
    EXPECT_EQ(s.report.droppedInvalidIndex, 3u);
    ASSERT_EQ(s.primitiveCount(), 1u);
    EXPECT_EQ(s.sourceFace[0], 3u);
}

TEST_F(SceneFiles, DegenerateTrianglesAreDroppedAndCounted) {
    std::string path = write("degenerate.obj",
                             "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n"
                             "f 1 2 3\n"  // collinear: zero area
                             "f 1 1 4\n"  // repeated vertex: OpenMesh skips it before we see it
                             "f 1 2\n"    // too few vertices: also skipped inside OpenMesh
                             "f 1 2 4\n");
    Scene s = loadScene(path);
    EXPECT_EQ(s.report.facesRead, 4u);
    EXPECT_EQ(s.report.droppedDegenerate, 2u);
    EXPECT_EQ(s.report.droppedTooFewVertices, 1u);
    ASSERT_EQ(s.primitiveCount(), 1u);
    EXPECT_EQ(s.sourceFace[0], 3u);  // still the file's face index
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
}

TEST_F(SceneFiles, ObjNonFiniteVertexIsCountedWithoutShiftingLaterVertices) {
    // OpenMesh's OBJ reader silently skips "v" lines it cannot parse, which would shift every
    // later vertex by one; the loader maps file vertex numbers back.
    std::string path = write("nan.obj",
                             "v 0 0 0\nv nan 0 0\nv 1 0 0\nv 0 1 0\nv 1e39 0 0\n"
                             "f 1 2 3\nf 1 3 4\nf 5 3 4\n");
    Scene s = loadScene(path);
    EXPECT_EQ(s.report.verticesRead, 5u);
    EXPECT_EQ(s.report.droppedNonFinite, 2u);
    ASSERT_EQ(s.primitiveCount(), 1u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
    EXPECT_EQ(s.sourceFace[0], 1u);
}

const char* kPlyHeader =
    "ply\nformat %s 1.0\ncomment written by scene_test\nelement vertex 5\nproperty float x\n"
    "property float y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\n"
    "end_header\n";

std::string plyHeader(const std::string& format) {
    std::string h = kPlyHeader;
    return h.replace(h.find("%s"), 2, format);
}

void expectPlyMesh(const Scene& s) {
    EXPECT_EQ(s.report.format, "ply");
    EXPECT_EQ(s.report.verticesRead, 5u);
    EXPECT_EQ(s.report.facesRead, 3u);
    EXPECT_EQ(s.report.droppedInvalidIndex, 1u);
    EXPECT_EQ(s.report.polygonsTriangulated, 1u);
    ASSERT_EQ(s.primitiveCount(), 3u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kD));
    EXPECT_TRUE(triangleIs(s.triangles[1], kA, kD, kC));
    EXPECT_TRUE(triangleIs(s.triangles[2], kE, kB, kC));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 0, 2}));
}

TEST_F(SceneFiles, PlyAscii) {
    std::string path = write("mesh.ply", plyHeader("ascii") +
                                             "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                             "4 0 1 2 3\n3 0 1 99\n3 4 1 3\n");
    expectPlyMesh(loadScene(path));
}

TEST_F(SceneFiles, PlyBinaryLittleEndian) {
    Bytes b;
    b.text(plyHeader("binary_little_endian"));
    for (Vec3 v : {kA, kB, kD, kC, kE}) b.vec(v);
    b.put<uint8_t>(4).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2).put<int32_t>(3);
    b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(99);
    b.put<uint8_t>(3).put<int32_t>(4).put<int32_t>(1).put<int32_t>(3);
    expectPlyMesh(loadScene(write("mesh_binary.ply", b.data)));
}

TEST_F(SceneFiles, PlyBinaryNonFiniteVertexIsCounted) {
    Bytes b;
    b.text(plyHeader("binary_little_endian"));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (Vec3 v : {kA, kB, Vec3{nan, 0, 0}, kC, Vec3{0, inf, 0}}) b.vec(v);
    b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
    b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(3);
    b.put<uint8_t>(3).put<int32_t>(4).put<int32_t>(1).put<int32_t>(3);
    Scene s = loadScene(write("nan.ply", b.data));
    EXPECT_EQ(s.report.droppedNonFinite, 2u);
    ASSERT_EQ(s.primitiveCount(), 1u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
    EXPECT_EQ(s.sourceFace[0], 1u);
}

TEST_F(SceneFiles, AsciiPlyWithUnparsableNumberIsRefused) {
    // OpenMesh's ASCII reader would leave its stream failed and read stale values from here on.
    std::string path = write("nan_ascii.ply", plyHeader("ascii") +
                                                  "0 0 0\n1 0 0\nnan 1 0\n0 1 0\n0 0 1\n"
                                                  "3 0 1 2\n3 0 1 3\n3 4 1 3\n");
    expectError(path, "line 13");
}

TEST_F(SceneFiles, TruncatedFilesAreRefused) {
    // OpenMesh's ASCII readers do not notice a short face list: they repeat the last face.
    std::string path = write("short.ply", plyHeader("ascii") + "0 0 0\n1 0 0\n1 1 0\n");
    expectError(path, "truncated");
    std::string noFaces = write("short_faces.ply", plyHeader("ascii") +
                                                       "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                                       "3 0 1 2\n3 0 1 3\n");
    expectError(noFaces, "truncated");
    std::string off = write("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n");
    expectError(off, "truncated");
    Bytes b;  // the binary reader notices the early end itself
    b.text(plyHeader("binary_little_endian")).vec(kA).vec(kB);
    expectError(write("short_binary.ply", b.data), "truncated");
}

TEST_F(SceneFiles, Off) {
    std::string path = write("mesh.off",
                             "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                             "4 0 1 2 3\n3 0 1 99\n3 4 1 3\n");
    Scene s = loadScene(path);
    EXPECT_EQ(s.report.format, "off");
    EXPECT_EQ(s.report.verticesRead, 5u);
    EXPECT_EQ(s.report.facesRead, 3u);
    EXPECT_EQ(s.report.droppedInvalidIndex, 1u);
    ASSERT_EQ(s.primitiveCount(), 3u);
    EXPECT_TRUE(triangleIs(s.triangles[1], kA, kD, kC));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 0, 2}));
}

std::string asciiFacet(Vec3 a, Vec3 b, Vec3 c) {
    std::ostringstream out;
    out << "  facet normal 0 0 1\n    outer loop\n";
    for (Vec3 v : {a, b, c}) out << "      vertex " << v.x << " " << v.y << " " << v.z << "\n";
    out << "    endloop\n  endfacet\n";
    return out.str();
}

void expectStlMesh(const Scene& s) {
    EXPECT_EQ(s.report.format, "stl");
    EXPECT_EQ(s.report.facesRead, 3u);
    EXPECT_EQ(s.report.verticesRead, 5u);  // OpenMesh merges equal vertices in STL
    EXPECT_EQ(s.report.droppedDegenerate, 1u);
    ASSERT_EQ(s.primitiveCount(), 2u);
    EXPECT_TRUE(triangleIs(s.triangles[0], kA, kB, kC));
    EXPECT_TRUE(triangleIs(s.triangles[1], kB, kD, kE));
    EXPECT_EQ(s.sourceFace, (std::vector<uint32_t>{0, 2}));
}

TEST_F(SceneFiles, StlAscii) {
    std::string path =
        write("mesh.stl", "solid test\n" + asciiFacet(kA, kB, kC) + asciiFacet(kA, kB, kA) +
                              asciiFacet(kB, kD, kE) + "endsolid test\n");
    expectStlMesh(loadScene(path));
}

TEST_F(SceneFiles, StlBinary) {
    Bytes b;
    b.text(std::string(80, ' ')).put<uint32_t>(3);
    const Vec3 facets[3][3] = {{kA, kB, kC}, {kA, kB, kA}, {kB, kD, kE}};
    for (const auto& f : facets) b.vec({0, 0, 1}).vec(f[0]).vec(f[1]).vec(f[2]).put<uint16_t>(0);
    expectStlMesh(loadScene(write("mesh_binary.stl", b.data)));
}

TEST_F(SceneFiles, ExtensionIsCaseInsensitive) {
    Scene s = loadScene(write("UPPER.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_EQ(s.primitiveCount(), 1u);
}

// Two loads of the same scene: the same primitives in the same order, the same report.
void expectSameScene(const Scene& a, const Scene& b) {
    ASSERT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.report.format, b.report.format);
    EXPECT_EQ(a.report.verticesRead, b.report.verticesRead);
    EXPECT_EQ(a.report.facesRead, b.report.facesRead);
    EXPECT_EQ(a.report.totalDropped(), b.report.totalDropped());
    ASSERT_EQ(a.primitiveCount(), b.primitiveCount());
    for (size_t i = 0; i < a.triangles.size(); ++i)
        EXPECT_TRUE(
            triangleIs(a.triangles[i], b.triangles[i].v0, b.triangles[i].v1, b.triangles[i].v2))
            << "triangle " << i;
    EXPECT_EQ(a.sourceFace, b.sourceFace);
    for (size_t i = 0; i < a.spheres.size(); ++i) {
        EXPECT_TRUE(sameVec(a.spheres[i].center, b.spheres[i].center)) << "sphere " << i;
        EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius) << "sphere " << i;
    }
}

const char* kOffQuadAndTriangle =
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
    "4 0 1 2 3\n3 4 1 3\n";

Scene SceneFiles::plainOff() {
    return loadScene(write("plain.off", std::string("OFF\n5 2 0\n") + kOffQuadAndTriangle));
}

TEST_F(SceneFiles, OffCommentsAreSkipped) {
    // Geomview's OFF: '#' starts a comment that runs to the end of the line.
    Scene s = loadScene(write("comments.off",
                              "OFF\n# made by hand\n5 2 0\n# vertices\n0 0 0\n1 0 0 # B\n"
                              "1 1 0\n\n0 1 0\n0 0 1\n# faces\n4 0 1 2 3 # a quad\n"
                              "# a triangle\n3 4 1 3\n# the end\n"));
    ASSERT_EQ(s.primitiveCount(), 3u);
    expectSameScene(s, plainOff());
}

TEST_F(SceneFiles, OffCountsOnTheKeywordLine) {
    Scene s = loadScene(write("keyword.off", std::string("OFF 5 2 0\n") + kOffQuadAndTriangle));
    ASSERT_EQ(s.primitiveCount(), 3u);
    EXPECT_TRUE(triangleIs(s.triangles[2], kE, kB, kC));
    expectSameScene(s, plainOff());
}

TEST_F(SceneFiles, OffFaceColoursWithoutTheCPrefix) {
    // A face line may end in a colour (Geomview's OFF): a colour-map index, RGB or RGBA.
    for (const char* colours : {"255 0 0|0.5 0.5 0.5 1", "7|2", "0 0 255 255|"}) {
        const std::string c = colours;
        const std::string first = c.substr(0, c.find('|')), second = c.substr(c.find('|') + 1);
        Scene s = loadScene(write("colours.off",
                                  "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                  "4 0 1 2 3 " +
                                      first + "\n3 4 1 3 " + second + "\n"));
        SCOPED_TRACE(colours);
        expectSameScene(s, plainOff());
    }
    // Anything else after the indices is not a colour: the vertex count is probably wrong.
    expectError(write("two.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 5 6\n"), "line 6");
    expectError(write("word.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 red\n"), "red");
}

TEST_F(SceneFiles, ByteOrderMarkIsIgnoredInEveryTextFormat) {
    const std::string bom = "\xEF\xBB\xBF";
    const std::vector<std::pair<std::string, std::string>> files = {
        {"obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 5 2 4\n"},
        {"off", std::string("OFF\n5 2 0\n") + kOffQuadAndTriangle},
        {"ply",
         "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
         "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
         "end_header\n" +
             std::string(kOffQuadAndTriangle)},
        {"stl", "solid t\n" + asciiFacet(kA, kB, kD) + asciiFacet(kE, kB, kC) + "endsolid t\n"},
        {"xyz", "0 0 0\n1 0 0\n1 1 0\n"}};
    for (const auto& [ext, text] : files) {
        SCOPED_TRACE(ext);
        Scene plain = loadScene(write("plain." + ext, text));
        std::string path = write("bom." + ext, bom + text);
        try {
            expectSameScene(loadScene(path), plain);
        } catch (const SceneError& e) {
            ADD_FAILURE() << e.what();
        }
    }
}

TEST_F(SceneFiles, ObjLineContinuation) {
    // Wavefront OBJ: a line ending in a backslash continues on the next one. A comment is
    // never continued, so a path in it cannot swallow the next statement.
    Scene s = loadScene(write("cont.obj",
                              "# C:\\models\\\nv 0 0 0\nv 1 \\\n 0 0\nv 1 1 0\nv 0 1 0\n"
                              "v 0 0 1\nf 1 2 \\\r\n3 4\nf 5 \\\n2 \\\n4\n"));
    Scene plain = loadScene(
        write("plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 5 2 4\n"));
    ASSERT_EQ(s.primitiveCount(), 3u);
    expectSameScene(s, plain);
}

TEST_F(SceneFiles, PlyFaceListsBesideTheIndicesAreIgnored) {
    const std::string faceProps =
        "property list uchar float texcoord\nproperty list uchar int vertex_indices\n"
        "property int texnumber\nproperty list uchar float texcoord2\n";
    auto header = [&](const std::string& format) {
        return "ply\nformat " + format +
               " 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
               "property float z\nelement face 2\n" +
               faceProps + "end_header\n";
    };
    const std::string ascii = header("ascii") + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n" +
                              "6 0 0 1 0 1 1 4 0 1 2 3 0 0\n6 0 0 1 0 0 1 3 4 1 3 1 2 0.5 0.5\n";
    Bytes binary;
    binary.text(header("binary_little_endian"));
    for (Vec3 v : {kA, kB, kD, kC, kE}) binary.vec(v);
    const std::vector<std::vector<int32_t>> faces = {{0, 1, 2, 3}, {4, 1, 3}};
    for (const auto& face : faces) {
        binary.put<uint8_t>(2).put<float>(0.25f).put<float>(0.75f);
        binary.put<uint8_t>(uint8_t(face.size()));
        for (int32_t i : face) binary.put<int32_t>(i);
        binary.put<int32_t>(9).put<uint8_t>(0);
    }
    Scene plain = plainOff();
    for (const std::string& path :
         {write("lists.ply", ascii), write("lists_bin.ply", binary.data)}) {
        SCOPED_TRACE(path);
        try {
            Scene s = loadScene(path);
            EXPECT_EQ(s.report.format, "ply");
            ASSERT_EQ(s.primitiveCount(), 3u);
            for (size_t i = 0; i < 3; ++i)
                EXPECT_TRUE(triangleIs(s.triangles[i], plain.triangles[i].v0, plain.triangles[i].v1,
                                       plain.triangles[i].v2));
            EXPECT_EQ(s.sourceFace, plain.sourceFace);
        } catch (const SceneError& e) {
            ADD_FAILURE() << e.what();
        }
    }
}

TEST_F(SceneFiles, PlyFaceScalarBeforeTheIndices) {
    // OpenMesh's reader drops the declarations before vertex_indices and then reads the scalar
    // as the list length: "3 4 0 1 2 3" would become the triangle 4 0 1, in silence.
    std::string path = write("before.ply",
                             "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 2\n"
                             "property uchar flags\nproperty list uchar int vertex_indices\n"
                             "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                             "3 4 0 1 2 3\n3 3 4 1 3\n");
    Scene plain = plainOff();
    try {
        Scene s = loadScene(path);
        ASSERT_EQ(s.primitiveCount(), 3u);
        for (size_t i = 0; i < 3; ++i)
            EXPECT_TRUE(triangleIs(s.triangles[i], plain.triangles[i].v0, plain.triangles[i].v1,
                                   plain.triangles[i].v2));
    } catch (const SceneError& e) {
        ADD_FAILURE() << e.what();
    }
}

TEST_F(SceneFiles, BinaryStlStartingWithSolidNamesItsCountAndSize) {
    // Many CAD programs start a binary STL's 80-byte header with "solid". With a wrong facet
    // count the size rule reads it as ASCII, which finds no facet: say what is wrong instead.
    Bytes b;
    b.text("solid part" + std::string(70, ' ')).put<uint32_t>(5);
    for (int f = 0; f < 2; ++f) b.vec({0, 0, 1}).vec(kA).vec(kB).vec(kC).put<uint16_t>(0);
    const std::string path = write("solid_binary.stl", b.data);
    expectError(path, "declares 5 facets");
    expectError(path, std::to_string(b.data.size()));
    // An ASCII STL without facets is still "no faces".
    expectError(write("empty.stl", "solid empty\n" + std::string(100, ' ') + "\nendsolid empty\n"),
                "no faces");
}

TEST_F(SceneFiles, RadiusMessagesAreShortAndHonest) {
    const std::string path = write("r.xyz", "0 0 0\n1 0 0\n");
    for (float radius : {std::nanf(""), -1.0f, -3e38f, -INFINITY, INFINITY}) {
        LoadOptions opts;
        opts.radius = radius;
        try {
            loadScene(path, opts);
            ADD_FAILURE() << "radius " << radius << " accepted";
        } catch (const SceneError& e) {
            const std::string msg = e.what();
            EXPECT_LT(msg.size(), 160u + path.size()) << msg;
            EXPECT_NE(msg.find("radius"), std::string::npos) << msg;
            // 0 selects the default rule in LoadOptions, but the command line refuses it:
            // the message must not advise it.
            EXPECT_EQ(msg.find(" 0 "), std::string::npos) << msg;
            EXPECT_EQ(msg.find("999999"), std::string::npos) << msg;
        }
    }
}

TEST_F(SceneFiles, ReaderMessagesDoNotLeakToStderr) {
    std::string path = write("noisy.ply", plyHeader("ascii") +
                                              "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n"
                                              "3 0 0 1\n3 0 1 99\n3 4 1 3\n");
    // OpenMesh's OBJ reader warns on omerr() about the missing material file.
    std::string obj =
        write("noisy.obj", "mtllib missing.mtl\nusemtl none\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    ::testing::internal::CaptureStderr();
    Scene s = loadScene(path);
    Scene o = loadScene(obj);
    std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, "");
    EXPECT_EQ(s.report.droppedDegenerate, 1u);
    EXPECT_EQ(s.report.droppedInvalidIndex, 1u);
    EXPECT_EQ(o.primitiveCount(), 1u);
}

TEST_F(SceneFiles, Errors) {
    expectError(dir() + "/missing.obj", "No such file or directory");
    expectError(dir(), "directory");
    std::string unknown = write("mesh.abc", "v 0 0 0\n");
    expectError(unknown, "unknown scene format");
    std::string noFaces = write("nofaces.obj", "v 0 0 0\nv 1 0 0\n");
    expectError(noFaces, "no faces");
    std::string allBad = write("allbad.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 2 7\n");
    expectError(allBad, "none of its 2 faces");
    std::string notPly = write("fake.ply", "this is not a ply file\n");
    expectError(notPly, "PLY");
    std::string empty = write("empty.xyz", "# nothing\n\n");
    expectError(empty, "no usable points");
    std::string stlNan = write("nan.stl", Bytes()
                                              .text(std::string(80, ' '))
                                              .put<uint32_t>(1)
                                              .vec({0, 0, 1})
                                              .vec(kA)
                                              .vec({std::nanf(""), 0, 0})
                                              .vec(kC)
                                              .put<uint16_t>(0)
                                              .data);
    expectError(stlNan, "NaN");
    LoadOptions negative;
    negative.radius = -1.0f;
    expectError(write("r.xyz", "0 0 0\n"), "radius", negative);
}

TEST_F(SceneFiles, BoundsCoverAllPrimitives) {
    Scene s = loadScene(write("b.obj", "v -1 0 0\nv 1 2 0\nv 0 0 3\nf 1 2 3\n"));
    Aabb b = s.bounds();
    EXPECT_TRUE(sameVec(b.lo, Vec3{-1, 0, 0}));
    EXPECT_TRUE(sameVec(b.hi, Vec3{1, 2, 3}));
    Scene spheres = loadScene(write("b.xyz", "0 0 0\n4 0 0\n"));  // R = 0.5 x 4 = 2
    Aabb sb = spheres.bounds();
    EXPECT_TRUE(sameVec(sb.lo, Vec3{-2, -2, -2}));
    EXPECT_TRUE(sameVec(sb.hi, Vec3{6, 2, 2}));
}

// ---------------------------------------------------------------------------------------------
// Point clouds

std::vector<Vec3> lattice(int n, float spacing) {
    std::vector<Vec3> points;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) points.push_back({x * spacing, y * spacing, z * spacing});
    return points;
}

TEST_F(SceneFiles, XyzPointCloudUsesTheRadiusRule) {
    std::ostringstream text;
    text << "# lattice, spacing 2\n\n";
    for (Vec3 p : lattice(3, 2.0f)) text << "  " << p.x << "\t" << p.y << " " << p.z << " 7 8\n";
    text << "nan 0 0\n";
    Scene s = loadScene(write("cloud.xyz", text.str()));
    EXPECT_EQ(s.kind, PrimKind::Spheres);
    EXPECT_EQ(s.report.format, "xyz");
    EXPECT_EQ(s.report.verticesRead, 28u);
    EXPECT_EQ(s.report.droppedNonFinite, 1u);
    ASSERT_EQ(s.primitiveCount(), 27u);
    EXPECT_TRUE(sameVec(s.spheres[5].center, lattice(3, 2.0f)[5]));
    for (const Sphere& sp : s.spheres) EXPECT_EQ(sp.radius, 1.0f);
}

TEST_F(SceneFiles, XyzRadiusOverride) {
    LoadOptions opts;
    opts.radius = 0.25f;
    Scene s = loadScene(write("cloud.xyz", "0 0 0\n2 0 0\n"), opts);
    ASSERT_EQ(s.primitiveCount(), 2u);
    EXPECT_EQ(s.spheres[0].radius, 0.25f);
    EXPECT_EQ(s.spheres[1].radius, 0.25f);
}

TEST_F(SceneFiles, XyzShortLineNamesTheLine) {
    expectError(write("short.xyz", "0 0 0\n# c\n1 2\n"), "line 3");
    expectError(write("word.xyz", "0 0 zero\n"), "line 1");
}

TEST_F(SceneFiles, VertexOnlyPlyIsAPointCloud) {
    std::ostringstream ascii;
    ascii << "ply\nformat ascii 1.0\nelement vertex 27\nproperty float x\nproperty float y\n"
             "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
             "end_header\n";
    Bytes binary;
    binary.text(
        "ply\nformat binary_little_endian 1.0\nelement vertex 27\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n");
    for (Vec3 p : lattice(3, 2.0f)) {
        ascii << p.x << " " << p.y << " " << p.z << "\n";
        binary.vec(p);
    }
    for (const std::string& path :
         {write("points.ply", ascii.str()), write("points_binary.ply", binary.data)}) {
        Scene s = loadScene(path);
        EXPECT_EQ(s.kind, PrimKind::Spheres) << path;
        EXPECT_EQ(s.report.format, "ply");
        EXPECT_EQ(s.report.facesRead, 0u);
        ASSERT_EQ(s.primitiveCount(), 27u) << path;
        EXPECT_TRUE(sameVec(s.spheres[26].center, Vec3{4, 4, 4}));
        EXPECT_EQ(s.spheres[0].radius, 1.0f);
        LoadOptions opts;
        opts.radius = 3.0f;
        EXPECT_EQ(loadScene(path, opts).spheres[7].radius, 3.0f);
    }
}

// Independent reference: O(n * sample) brute force over the same sample.
float bruteForceRadius(const std::vector<Vec3>& pts) {
    size_t k = std::min<size_t>(pts.size(), 10000);
    std::vector<double> d;
    for (size_t i = 0; i < k; ++i) {
        const Vec3& q = pts[uint64_t(i) * pts.size() / k];
        double best = std::numeric_limits<double>::infinity();
        for (const Vec3& p : pts) {
            double dx = double(p.x) - q.x, dy = double(p.y) - q.y, dz = double(p.z) - q.z;
            double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
            if (dist > 0 && dist < best) best = dist;
        }
        if (std::isfinite(best)) d.push_back(best);
    }
    std::sort(d.begin(), d.end());
    return float(0.5 * d[d.size() / 2]);
}

TEST(DefaultPointRadius, SpecialCases) {
    EXPECT_EQ(defaultPointRadius({}), 1e-3f);
    EXPECT_EQ(defaultPointRadius({{5, 5, 5}}), 1e-3f);
    EXPECT_EQ(defaultPointRadius({{5, 5, 5}, {5, 5, 5}, {5, 5, 5}}), 1e-3f);
    EXPECT_EQ(defaultPointRadius({{0, 0, 0}, {0, 4, 0}}), 2.0f);
    std::vector<Vec3> doubled = lattice(4, 2.0f);
    std::vector<Vec3> copy = doubled;
    doubled.insert(doubled.end(), copy.begin(), copy.end());  // exact duplicates are ignored
    EXPECT_EQ(defaultPointRadius(doubled), 1.0f);
}

TEST(DefaultPointRadius, MatchesBruteForceOnRandomClouds) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<float> u(-3.0f, 5.0f);
    std::vector<Vec3> box(3000), plane(3000), clustered;
    for (Vec3& p : box) p = {u(rng), u(rng), u(rng)};
    for (Vec3& p : plane) p = {u(rng), 0.5f, u(rng)};
    for (int i = 0; i < 3000; ++i) clustered.push_back({u(rng) * 1e-3f, u(rng) * 1e-3f, 0.0f});
    clustered.push_back({1e4f, -1e4f, 3e3f});  // a far outlier stretches the box
    for (const auto* cloud : {&box, &plane, &clustered})
        EXPECT_EQ(defaultPointRadius(*cloud), bruteForceRadius(*cloud));
}

TEST(DefaultPointRadius, SamplesLargeCloudsDeterministically) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Vec3> cloud(12000);
    for (Vec3& p : cloud) p = {u(rng), u(rng), u(rng)};
    EXPECT_EQ(defaultPointRadius(cloud), bruteForceRadius(cloud));
}

// ---------------------------------------------------------------------------------------------
// Grid cloud

TEST(GridCloud, DepthRule) {
    EXPECT_EQ(gridCloudDepth(1), 1);
    EXPECT_EQ(gridCloudDepth(8), 1);
    EXPECT_EQ(gridCloudDepth(9), 2);
    EXPECT_EQ(gridCloudDepth(1000), 4);
    EXPECT_EQ(gridCloudDepth(4096), 4);
    EXPECT_EQ(gridCloudDepth(4097), 5);
    EXPECT_EQ(gridCloudDepth(1u << 30), 10);
    EXPECT_THROW(gridCloudDepth((1u << 30) + 1), SceneError);
    EXPECT_THROW(gridCloudDepth(0), SceneError);
    EXPECT_THROW(makeGridCloud(0, 1), SceneError);
}

TEST(GridCloud, EngineIsTheStandardOne) {
    std::mt19937_64 engine;  // [rand.predef]: the 10000th output for the default seed
    engine.discard(9999);
    EXPECT_EQ(engine(), 9981545732273789042ull);
}

TEST(GridCloud, GoldenFirstCells) {
    // From a separate implementation of MT19937-64 (Matsumoto & Nishimura's reference
    // algorithm, checked against the 10000th output above): seed 1 gives
    // 2469588189546311528, 2516265689700432462, 8323445853463659930. With 8^4 = 4096 cells:
    // 2469588189546311528 mod 4096 = 3944; slot 1 + (2516265689700432462 mod 4095) = 2068;
    // slot 2 + (8323445853463659930 mod 4094) = 600; none hit an already-swapped slot.
    std::vector<uint32_t> cells = chooseGridCells(1000, 4, 1);
    ASSERT_EQ(cells.size(), 1000u);
    EXPECT_EQ(cells[0], 3944u);
    EXPECT_EQ(cells[1], 2068u);
    EXPECT_EQ(cells[2], 600u);
    // Cell 3944 = x 8, y 6, z 15 at depth 4 (edge 1/16).
    Scene s = makeGridCloud(1000, 1);
    EXPECT_TRUE(sameVec(s.spheres[0].center, Vec3{8.5f / 16, 6.5f / 16, 15.5f / 16}));
    EXPECT_EQ(s.spheres[0].radius, 0.4f / 16);
}

TEST(GridCloud, ReproducibleAndSeedDependent) {
    Scene a = makeGridCloud(1000, 1), b = makeGridCloud(1000, 1), c = makeGridCloud(1000, 2);
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    bool same = true, sameAsC = true;
    for (size_t i = 0; i < a.spheres.size(); ++i) {
        same = same && sameVec(a.spheres[i].center, b.spheres[i].center);
        sameAsC = sameAsC && sameVec(a.spheres[i].center, c.spheres[i].center);
    }
    EXPECT_TRUE(same);
    EXPECT_FALSE(sameAsC);
    EXPECT_EQ(a.name, "grid:1000:1");
    EXPECT_EQ(a.report.format, "grid");
}

TEST(GridCloud, DistinctCellsAndNoSphereStraddlesACell) {
    for (uint32_t n : {1u, 8u, 1000u, 4096u, 4097u}) {
        Scene s = makeGridCloud(n, 99);
        const int depth = gridCloudDepth(n);
        ASSERT_EQ(s.primitiveCount(), n);
        ASSERT_TRUE(s.domain.has_value());
        EXPECT_TRUE(sameVec(s.domain->lo, Vec3{0, 0, 0}));
        EXPECT_TRUE(sameVec(s.domain->hi, Vec3{1, 1, 1}));
        EXPECT_EQ(s.gridDepth, depth);
        const double cells = double(1 << depth), edge = 1.0 / cells;
        std::set<uint64_t> seen;
        for (const Sphere& sp : s.spheres) {
            uint64_t key = 0;
            for (int a = 0; a < 3; ++a) {
                double c = sp.center[a];
                double cell = std::floor(c * cells);
                double lo = cell * edge, hi = lo + edge;
                // Gap of 0.1 cell to both faces (float radius: within a few ulps).
                EXPECT_GE(c - sp.radius - lo, 0.1 * edge * (1 - 1e-5));
                EXPECT_GE(hi - (c + sp.radius), 0.1 * edge * (1 - 1e-5));
                EXPECT_GE(c - sp.radius, 0.0);
                EXPECT_LE(c + sp.radius, 1.0);
                key = key * uint64_t(cells) + uint64_t(cell);
            }
            seen.insert(key);
        }
        EXPECT_EQ(seen.size(), n);
    }
}

TEST(GridCloud, SpecThroughLoadScene) {
    Scene s = loadScene("grid:1000:1");
    Scene direct = makeGridCloud(1000, 1);
    ASSERT_EQ(s.spheres.size(), direct.spheres.size());
    EXPECT_TRUE(sameVec(s.spheres[999].center, direct.spheres[999].center));
    EXPECT_EQ(loadScene("grid:64").name, "grid:64:1");  // default seed 1
    EXPECT_EQ(loadScene("grid:64").gridDepth, 2);
    for (const char* bad :
         {"grid:", "grid:0", "grid:x", "grid:10:", "grid:10:-1", "grid:-5", "grid:4294967296"})
        EXPECT_THROW(loadScene(bad), SceneError) << bad;
    LoadOptions opts;
    opts.radius = 0.1f;
    EXPECT_THROW(loadScene("grid:10", opts), SceneError);
}

// ---------------------------------------------------------------------------------------------
// The project's meshes: the face count against an independent count of OBJ "f" lines.

class ProjectMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(ProjectMesh, FaceCountMatchesFLines) {
    const std::string path = std::string(OCT_SOURCE_DIR) + "/meshes/" + GetParam();
    if (!fs::exists(path)) {
        GTEST_SKIP() << path << " is not present";
    }
    std::ifstream in(path);
    std::string line, word;
    uint64_t faces = 0, fanTriangles = 0;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        if (!(s >> word) || word != "f") continue;
        ++faces;
        uint64_t corners = 0;
        while (s >> word) ++corners;
        fanTriangles += corners >= 3 ? corners - 2 : 0;
    }
    Scene scene = loadScene(path);
    EXPECT_EQ(scene.report.facesRead, faces);
    EXPECT_GT(scene.primitiveCount(), 0u);
    const LoadReport& r = scene.report;
    if (r.droppedInvalidIndex + r.droppedNonFinite + r.droppedTooFewVertices == 0) {
        EXPECT_EQ(scene.primitiveCount() + r.droppedDegenerate, fanTriangles);
    }
}

INSTANTIATE_TEST_SUITE_P(Meshes, ProjectMesh,
                         ::testing::Values("cornell_box.obj", "teapot.obj", "spider.obj"),
                         [](const auto& info) {
                             std::string name = info.param;
                             return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace oct
