// Scene loading. Meshes go through OpenMesh's readers into RawMeshImporter, which records what
// the reader hands over without building a halfedge mesh (an OpenMesh mesh would reject
// non-manifold faces). Because OpenMesh's readers silently skip or misread some input before any
// importer sees it, each format is first surveyed here: the survey counts the file's faces,
// predicts which of them the reader will hand over (so sourceFace stays a file face index and
// the skipped ones are counted), and refuses, with a SceneError, input that a reader would
// silently misread (an unparsable number in an ASCII PLY/OFF/STL file, a NaN in a binary STL).
#include "core/scene/load_scene.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "core/scene/grid_cloud.h"

namespace oct {
namespace {

namespace fs = std::filesystem;
using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

std::string inQuotes(const std::string& s) { return "'" + s + "'"; }

std::string toLower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    return toLower(ext.empty() ? ext : ext.substr(1));
}

// ---------------------------------------------------------------------------------------------
// File checks

void checkReadableFile(const std::string& path) {
    std::error_code ec;
    fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found)
        throw SceneError("cannot open " + inQuotes(path) +
                         ": No such file or directory; check the path");
    if (ec) throw SceneError("cannot open " + inQuotes(path) + ": " + ec.message());
    if (fs::is_directory(status))
        throw SceneError("cannot load " + inQuotes(path) +
                         ": it is a directory; give a .obj, .ply, .off, .stl or .xyz file");
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
        throw SceneError("cannot open " + inQuotes(path) + ": " + std::strerror(errno) +
                         "; check the file's permissions");
}

std::ifstream openOrThrow(const std::string& path, std::ios::openmode mode = std::ios::in) {
    std::ifstream in(path, mode);
    if (!in) throw SceneError("cannot open " + inQuotes(path) + ": " + std::strerror(errno));
    return in;
}

void trimLine(std::string& s) {  // the same trim as OpenMesh's OBJ/STL readers
    size_t begin = s.find_first_not_of(" \t\r\n");
    size_t end = s.find_last_not_of(" \t\r\n");
    s = begin == std::string::npos ? std::string() : s.substr(begin, end - begin + 1);
}

// ---------------------------------------------------------------------------------------------
// What OpenMesh's reader hands over, recorded without interpretation.

struct RawMesh {
    std::vector<Vec3> vertices;
    std::vector<int> faceIndices;         // all faces' vertex indices, as the reader gave them
    std::vector<size_t> faceStart = {0};  // face f is faceIndices[faceStart[f], faceStart[f+1])
    size_t faceCount() const { return faceStart.size() - 1; }
};

// Readers call add_face and may then use the returned handle for per-face attributes, so a valid
// handle is returned and every attribute callback accepts any handle and does nothing.
class RawMeshImporter final : public OpenMesh::IO::BaseImporter {
public:
    RawMesh mesh;

    VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return push({p[0], p[1], p[2]}); }
    VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
        return push({float(p[0]), float(p[1]), float(p[2])});
    }
    VertexHandle add_vertex() override { return push({0.0f, 0.0f, 0.0f}); }
    void set_point(VertexHandle vh, const OpenMesh::Vec3f& p) override {
        if (vh.idx() >= 0 && size_t(vh.idx()) < mesh.vertices.size())
            mesh.vertices[size_t(vh.idx())] = {p[0], p[1], p[2]};
    }
    FaceHandle add_face(const VHandles& corners) override {
        for (VertexHandle vh : corners) mesh.faceIndices.push_back(vh.idx());
        mesh.faceStart.push_back(mesh.faceIndices.size());
        return FaceHandle(int(mesh.faceCount() - 1));
    }
    // Only OpenMesh's own .om reader builds faces from halfedges; .om is not dispatched here.
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }

    size_t n_vertices() const override { return mesh.vertices.size(); }
    size_t n_faces() const override { return mesh.faceCount(); }
    size_t n_edges() const override { return 0; }

    void add_face_texcoords(FaceHandle, VertexHandle,
                            const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(FaceHandle, VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
    void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
    void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
    void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
    void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec3f&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec4f&) override {}
    void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
    void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}

private:
    VertexHandle push(Vec3 p) {
        mesh.vertices.push_back(p);
        return VertexHandle(int(mesh.vertices.size() - 1));
    }
};

// OpenMesh's readers talk on omerr()/omlog() (std::cerr/std::clog) and sometimes on std::cerr
// directly. During a read both go into a buffer, so a failure's reason ends up in our SceneError
// and nothing reaches the terminal as the only report of a problem.
class ReaderOutputCapture {
public:
    ReaderOutputCapture()
        : oldErr_(std::cerr.rdbuf(&buffer_)), oldLog_(std::clog.rdbuf(&buffer_)) {}
    ~ReaderOutputCapture() {
        flushOpenMeshStreams();
        std::cerr.rdbuf(oldErr_);
        std::clog.rdbuf(oldLog_);
    }
    ReaderOutputCapture(const ReaderOutputCapture&) = delete;
    ReaderOutputCapture& operator=(const ReaderOutputCapture&) = delete;

    // The captured messages on one line, at most 200 characters.
    std::string oneLine() {
        flushOpenMeshStreams();
        std::string text = buffer_.str();
        std::replace(text.begin(), text.end(), '\n', ' ');
        trimLine(text);
        return text.size() > 200 ? text.substr(0, 200) + "..." : text;
    }

private:
    static void flushOpenMeshStreams() {
        ::omerr().flush();
        ::omlog().flush();
    }
    std::stringbuf buffer_;  // declared first: the rdbuf swaps above point at it
    std::streambuf* oldErr_;
    std::streambuf* oldLog_;
};

// OpenMesh's readers are process-wide singletons with per-read state, and the capture above
// swaps process-wide stream buffers: one read at a time.
std::mutex& openMeshMutex() {
    static std::mutex mutex;
    return mutex;
}

RawMesh readWithOpenMesh(const std::string& path, const std::string& format) {
    std::lock_guard<std::mutex> lock(openMeshMutex());
    RawMeshImporter importer;
    ReaderOutputCapture capture;
    // Default options suffice: the PLY and OFF headers and the STL file size select binary mode.
    OpenMesh::IO::Options options;
    bool ok = false;
    try {
        ok = OpenMesh::IO::IOManager().read(path, importer, options);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw SceneError("cannot read " + inQuotes(path) + " as " + format +
                         ": OpenMesh's reader threw '" + e.what() + "'; check the file");
    }
    if (!ok) {
        std::string why = capture.oneLine();
        throw SceneError("cannot read " + inQuotes(path) + " as " + format +
                         ": OpenMesh's reader failed" + (why.empty() ? "" : " (" + why + ")") +
                         "; check that it is a valid " + format + " file");
    }
    return std::move(importer.mesh);
}

// ---------------------------------------------------------------------------------------------
// Surveys: what the file holds and which faces OpenMesh's reader will hand over.

struct Survey {
    bool surveyed = false;  // facesInFile and handedOver are known (OBJ, STL); PLY and OFF
                            // readers hand over every face, which the header count checks
    uint64_t facesInFile = 0;
    std::vector<uint32_t> handedOver;  // file face index of each face the reader hands over
    uint64_t skippedTooFew = 0;        // faces the reader skipped: fewer than 3 vertices
    uint64_t skippedDegenerate = 0;    // faces the reader skipped: repeated vertices
    // OBJ: OpenMesh drops a "v" line whose coordinates do not parse (nan, inf, overflow, garbage)
    // while face indices still count it, so later vertices shift. One flag per "v" line lets the
    // file's vertex numbers be mapped back to the reader's.
    bool isObj = false;
    std::vector<bool> vertexLineOk;
};

// One OBJ "f" line, decided as OpenMesh's OBJ reader decides it: the first component of each
// corner is the vertex (negative = relative to the "v" lines so far); repeated vertices are
// removed; fewer than 3 left and the reader skips the face without a word.
void surveyObjFace(std::istringstream& rest, size_t vertexLinesSoFar, Survey& s) {
    const uint32_t face = uint32_t(s.facesInFile++);
    std::vector<long long> corners;
    std::string token;
    while (rest >> token) {
        std::istringstream number(token.substr(0, token.find('/')));
        int value = 0;
        if (!(number >> value)) continue;
        corners.push_back(value < 0 ? (long long)vertexLinesSoFar + value : (long long)value - 1);
    }
    const size_t listed = corners.size();
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    if (corners.size() > 2)
        s.handedOver.push_back(face);
    else if (listed < 3)
        ++s.skippedTooFew;
    else
        ++s.skippedDegenerate;
}

Survey surveyObj(const std::string& path) {
    std::ifstream in = openOrThrow(path);
    Survey s;
    s.isObj = true;
    s.surveyed = true;
    std::string line, keyword;
    while (std::getline(in, line)) {
        trimLine(line);
        if (line.empty() || line[0] == '#') continue;
        std::istringstream stream(line);
        stream >> keyword;
        if (keyword == "v") {
            float x, y, z;  // parsed exactly as OpenMesh parses them: operator>> into float
            stream >> x >> y >> z;
            s.vertexLineOk.push_back(!stream.fail());
        } else if (keyword == "f") {
            surveyObjFace(stream, s.vertexLineOk.size(), s);
        }
    }
    return s;
}

// OpenMesh's STL reader merges vertices whose coordinates all differ by at most FLT_MIN and
// skips a facet whose merged corners repeat. This is its comparator's equivalence.
bool stlMerged(const Vec3& a, const Vec3& b) {
    const float eps = FLT_MIN;
    return std::fabs(a.x - b.x) <= eps && std::fabs(a.y - b.y) <= eps && !(a.z < b.z - eps) &&
           !(b.z < a.z - eps);
}

void surveyStlFacet(const Vec3 (&v)[3], Survey& s) {
    const uint32_t face = uint32_t(s.facesInFile++);
    if (stlMerged(v[0], v[1]) || stlMerged(v[0], v[2]) || stlMerged(v[1], v[2]))
        ++s.skippedDegenerate;
    else
        s.handedOver.push_back(face);
}

// OpenMesh's rule: binary when the size is exactly 84 + 50 x (count at byte 80).
bool stlIsBinary(const std::string& path, uint32_t& facetCount) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    char header[84];
    if (!in.read(header, 84)) return false;
    std::memcpy(&facetCount, header + 80, 4);  // little-endian hosts, as the reader assumes
    std::error_code ec;
    return fs::file_size(path, ec) == 84 + 50 * uint64_t(facetCount);
}

Survey surveyBinaryStl(const std::string& path, uint32_t facetCount) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    in.seekg(84);
    Survey s;
    s.surveyed = true;
    char record[50];
    for (uint32_t f = 0; f < facetCount && in.read(record, 50); ++f) {
        Vec3 v[3];
        std::memcpy(v, record + 12, sizeof v);
        // inf compares consistently and is dropped later; NaN breaks the reader's vertex map.
        for (const Vec3& p : v)
            if (std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z))
                throw SceneError("cannot load " + inQuotes(path) + ": facet " + std::to_string(f) +
                                 " has a NaN coordinate, which corrupts OpenMesh's vertex merging "
                                 "for the whole file; remove or repair that facet");
        surveyStlFacet(v, s);
    }
    return s;
}

float parseStlCoordinate(std::istringstream& in, const std::string& path, uint64_t lineNo) {
    float value;
    if (!(in >> value))
        throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                         " needs 'vertex x y z' with finite numbers; OpenMesh's STL reader would "
                         "silently misplace that vertex, so fix it");
    return value;
}

Survey surveyAsciiStl(const std::string& path) {
    std::ifstream in = openOrThrow(path);
    Survey s;
    s.surveyed = true;
    std::string line, keyword;
    uint64_t lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.find("outer") == std::string::npos && line.find("OUTER") == std::string::npos)
            continue;
        Vec3 v[3];
        for (Vec3& corner : v) {  // the reader takes the next three lines as "vertex x y z"
            std::getline(in, line);
            ++lineNo;
            std::istringstream stream(line);
            stream >> keyword;
            corner.x = parseStlCoordinate(stream, path, lineNo);
            corner.y = parseStlCoordinate(stream, path, lineNo);
            corner.z = parseStlCoordinate(stream, path, lineNo);
        }
        surveyStlFacet(v, s);
    }
    return s;
}

Survey surveyStl(const std::string& path) {
    uint32_t facetCount = 0;
    return stlIsBinary(path, facetCount) ? surveyBinaryStl(path, facetCount) : surveyAsciiStl(path);
}

// Walks the body of an ASCII PLY or OFF file the way OpenMesh's reader consumes it, and checks
// what that reader does not: every value it parses with operator>> must be a finite number (an
// integer where it reads one), and the file must hold every declared element. After a token it
// cannot parse (nan, inf, 1e39, a '#' comment), or at the end of a short file, its stream fails
// and every later value silently repeats the last one read: a truncated face list ends in copies
// of its last face. Such files are refused, naming the line.
class AsciiBody {
public:
    AsciiBody(std::istream& in, uint64_t linesBefore, const std::string& path,
              const std::string& format)
        : in_(in), lineNo_(linesBefore), path_(path), format_(format) {}

    double number() {
        std::string token = next();
        char* end = nullptr;
        double value = std::strtod(token.c_str(), &end);
        if (*end != '\0' || !std::isfinite(value) || std::fabs(value) > FLT_MAX)
            refuse(token, "a finite number");
        return value;
    }
    long long integer() {
        std::string token = next();
        char* end = nullptr;
        errno = 0;
        long long value = std::strtoll(token.c_str(), &end, 10);
        if (*end != '\0' || errno != 0) refuse(token, "an integer");
        return value;
    }
    uint64_t count() {  // a list length: OpenMesh would read a negative one as about 4 billion
        long long value = integer();
        if (value < 0) refuse(std::to_string(value), "a count >= 0");
        return uint64_t(value);
    }
    void skipRestOfLine() {
        line_.str(std::string());
        line_.clear();
    }

private:
    std::string next() {
        std::string token;
        while (!(line_ >> token)) {
            std::string text;
            if (!std::getline(in_, text))
                throw SceneError("cannot load " + inQuotes(path_) + ": it ends at line " +
                                 std::to_string(lineNo_) + " before all elements its header " +
                                 "declares; the file is truncated");
            ++lineNo_;
            line_.str(text);
            line_.clear();
        }
        return token;
    }
    [[noreturn]] void refuse(const std::string& token, const char* expected) const {
        throw SceneError("cannot load " + inQuotes(path_) + ": line " + std::to_string(lineNo_) +
                         " holds " + inQuotes(token) + " where OpenMesh's ASCII " + format_ +
                         " reader needs " + expected +
                         " (it would silently misread the rest of the file); fix that value");
    }

    std::istream& in_;
    uint64_t lineNo_;
    std::istringstream line_;
    std::string path_;
    std::string format_;
};

struct ElementCounts {
    bool ascii = true;
    uint64_t vertices = 0;
    uint64_t faces = 0;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<bool> isList;  // per property
    std::vector<bool> isVertexIndices;
};

// OpenMesh reads one token for every property except the face's vertex_indices list, so any
// other list property would shift every later value.
void checkPlyProperty(const std::string& path, const PlyElement& e, const std::string& name,
                      bool list) {
    if (!list || (e.name == "face" && (name == "vertex_indices" || name == "vertex_index"))) return;
    throw SceneError("cannot load " + inQuotes(path) + ": list property " + inQuotes(name) +
                     " of element " + inQuotes(e.name) +
                     " is not supported by OpenMesh's PLY reader; remove it from the file");
}

void walkPlyBody(AsciiBody& body, const std::vector<PlyElement>& elements) {
    for (const PlyElement& e : elements) {
        for (uint64_t i = 0; i < e.count; ++i)
            for (size_t p = 0; p < e.isList.size(); ++p) {
                if (!e.isList[p]) {
                    body.number();
                    continue;
                }
                for (uint64_t n = body.count(), k = 0; k < n; ++k) body.integer();
            }
        if (e.name == "face") return;  // OpenMesh stops reading after the faces
    }
}

ElementCounts readPlyHeader(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    ElementCounts counts;
    std::vector<PlyElement> elements;
    std::string line, word, type, name;
    uint64_t lineNo = 0;
    bool ended = false;
    while (!ended && std::getline(in, line)) {
        ++lineNo;
        std::istringstream stream(line);
        if (!(stream >> word) || word == "comment" || word == "obj_info") continue;
        if (word == "format" && stream >> word) counts.ascii = word == "ascii";
        ended = word == "end_header";
        PlyElement element;
        if (word == "element" && stream >> element.name >> element.count)
            elements.push_back(element);
        if (word == "property" && !elements.empty() && stream >> type) {
            const bool list = type == "list";
            if (list) stream >> type >> type;
            stream >> name;
            checkPlyProperty(path, elements.back(), name, list);
            elements.back().isList.push_back(list);
        }
    }
    if (!ended)
        throw SceneError("cannot read " + inQuotes(path) +
                         " as PLY: no 'end_header' line; check that it is a PLY file");
    for (const PlyElement& e : elements) {
        if (e.name == "vertex") counts.vertices = e.count;
        if (e.name == "face") counts.faces = e.count;
    }
    if (counts.ascii) {
        AsciiBody body(in, lineNo, path, "PLY");
        walkPlyBody(body, elements);
    }
    return counts;
}

// Header "[ST][C][N][4][n]OFF [BINARY]": N adds a normal after each vertex; C adds colours,
// which OpenMesh reads from the rest of the vertex's (and face's) line.
void walkOffBody(AsciiBody& body, const std::string& prefix, ElementCounts& counts) {
    const bool normals = prefix.find('N') != std::string::npos;
    const bool faceColours = prefix.find('C') != std::string::npos;
    counts.vertices = body.count();
    counts.faces = body.count();
    body.integer();  // edge count, unused
    for (uint64_t v = 0; v < counts.vertices; ++v) {
        for (int k = 0; k < (normals ? 6 : 3); ++k) body.number();
        body.skipRestOfLine();
    }
    for (uint64_t f = 0; f < counts.faces; ++f) {
        for (uint64_t n = body.count(), k = 0; k < n; ++k) body.integer();
        if (faceColours) body.skipRestOfLine();
    }
}

ElementCounts readOffHeader(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    ElementCounts counts;
    std::string first;
    std::getline(in, first);
    counts.ascii = first.find("BINARY") == std::string::npos;
    if (counts.ascii) {
        AsciiBody body(in, 1, path, "OFF");
        walkOffBody(body, first.substr(0, first.find("OFF")), counts);
    } else {
        uint32_t header[3] = {0, 0, 0};  // little-endian, as the reader assumes
        in.read(reinterpret_cast<char*>(header), sizeof header);
        counts.vertices = header[0];
        counts.faces = header[1];
    }
    return counts;
}

// PLY and OFF readers hand over every face; fewer than declared means a truncated file.
void checkDeclaredCounts(const std::string& path, const ElementCounts& declared,
                         const RawMesh& raw) {
    if (declared.vertices == raw.vertices.size() && declared.faces == raw.faceCount()) return;
    throw SceneError("cannot load " + inQuotes(path) + ": its header declares " +
                     std::to_string(declared.vertices) + " vertices and " +
                     std::to_string(declared.faces) + " faces but OpenMesh read " +
                     std::to_string(raw.vertices.size()) + " and " +
                     std::to_string(raw.faceCount()) + "; the file is truncated or malformed");
}

// ---------------------------------------------------------------------------------------------
// Triangles

constexpr int64_t kInvalidVertex = -1;
constexpr int64_t kUnparsedVertex = -2;  // OBJ "v" line OpenMesh could not parse

// Maps the indices a reader hands over to positions in RawMesh::vertices.
class VertexResolver {
public:
    VertexResolver(const Survey& survey, const RawMesh& raw) : count_(raw.vertices.size()) {
        if (!survey.isObj) return;
        int64_t next = 0;
        for (bool ok : survey.vertexLineOk) remap_.push_back(ok ? next++ : kUnparsedVertex);
        if (uint64_t(next) != raw.vertices.size()) remap_.clear();  // survey disagrees: trust OM
    }
    int64_t operator()(int index) const {
        if (index < 0) return kInvalidVertex;
        if (!remap_.empty()) return size_t(index) < remap_.size() ? remap_[index] : kInvalidVertex;
        return size_t(index) < count_ ? index : kInvalidVertex;
    }
    uint64_t verticesInFile() const { return remap_.empty() ? count_ : remap_.size(); }

private:
    size_t count_;
    std::vector<int64_t> remap_;
};

// Exact zero-area test: the edges' cross product in double is the zero vector.
bool isDegenerate(const Triangle& t) {
    double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y, az = double(t.v1.z) - t.v0.z;
    double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y, bz = double(t.v2.z) - t.v0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

// Collects the corners of face f; false (and the drop counted) when the face is unusable.
bool faceCorners(const RawMesh& raw, const VertexResolver& resolve, size_t f, LoadReport& report,
                 std::vector<Vec3>& corners) {
    const size_t begin = raw.faceStart[f], end = raw.faceStart[f + 1];
    if (end - begin < 3) {
        ++report.droppedTooFewVertices;
        return false;
    }
    corners.clear();
    bool finite = true;
    for (size_t i = begin; i < end; ++i) {
        int64_t v = resolve(raw.faceIndices[i]);
        if (v == kInvalidVertex) {
            ++report.droppedInvalidIndex;
            return false;
        }
        finite = finite && v != kUnparsedVertex && isFinite(raw.vertices[size_t(v)]);
        if (finite) corners.push_back(raw.vertices[size_t(v)]);
    }
    if (!finite) ++report.droppedNonFinite;
    return finite;
}

void addFace(const std::vector<Vec3>& corners, uint32_t source, Scene& scene) {
    if (corners.size() > 3) ++scene.report.polygonsTriangulated;
    for (size_t j = 1; j + 1 < corners.size(); ++j) {
        Triangle t{corners[0], corners[j], corners[j + 1]};
        if (isDegenerate(t)) {
            ++scene.report.droppedDegenerate;
            continue;
        }
        scene.triangles.push_back(t);
        scene.sourceFace.push_back(source);
    }
}

// Without a survey every face is handed over in file order. When a survey's prediction disagrees
// with what the reader handed over, the reader's order is used as is and the difference is still
// counted as skipped faces.
void reconcileSurvey(Survey& s, size_t handedOver) {
    if (!s.surveyed) {
        s.facesInFile = handedOver;
        s.handedOver.resize(handedOver);
        std::iota(s.handedOver.begin(), s.handedOver.end(), 0u);
    }
    if (s.handedOver.size() == handedOver) return;
    uint64_t skipped = s.facesInFile > handedOver ? s.facesInFile - handedOver : 0;
    s.skippedTooFew = std::min(s.skippedTooFew, skipped);
    s.skippedDegenerate = skipped - s.skippedTooFew;
    s.handedOver.resize(handedOver);
    std::iota(s.handedOver.begin(), s.handedOver.end(), 0u);
}

std::string dropSummary(const LoadReport& r) {
    return std::to_string(r.droppedInvalidIndex) + " with an invalid index, " +
           std::to_string(r.droppedNonFinite) + " non-finite, " +
           std::to_string(r.droppedTooFewVertices) + " with fewer than 3 vertices, " +
           std::to_string(r.droppedDegenerate) + " degenerate triangles";
}

Scene buildMeshScene(const std::string& path, const std::string& format, const RawMesh& raw,
                     Survey survey) {
    Scene scene;
    scene.name = path;
    scene.kind = PrimKind::Triangles;
    LoadReport& report = scene.report;
    report.format = format;
    VertexResolver resolve(survey, raw);
    report.verticesRead = resolve.verticesInFile();
    reconcileSurvey(survey, raw.faceCount());
    report.facesRead = survey.facesInFile;
    report.droppedTooFewVertices = survey.skippedTooFew;
    report.droppedDegenerate = survey.skippedDegenerate;
    std::vector<Vec3> corners;
    for (size_t f = 0; f < raw.faceCount(); ++f) {
        if (faceCorners(raw, resolve, f, report, corners))
            addFace(corners, survey.handedOver[f], scene);
    }
    if (!scene.triangles.empty()) return scene;
    if (report.facesRead == 0)
        throw SceneError("cannot load " + inQuotes(path) + ": it has no faces (" +
                         std::to_string(report.verticesRead) +
                         " vertices); give a mesh, or a .xyz or vertex-only .ply point cloud");
    throw SceneError("cannot load " + inQuotes(path) + ": none of its " +
                     std::to_string(report.facesRead) + " faces is usable (" + dropSummary(report) +
                     "); repair the mesh");
}

// ---------------------------------------------------------------------------------------------
// Point clouds

// Uniform hash grid over all points for nearest-neighbour queries (see defaultPointRadius).
class PointGrid {
public:
    PointGrid(const std::vector<Vec3>& points, const Aabb& box, double cell)
        : points_(points), lo_(box.lo), cell_(cell) {
        std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
        for (size_t i = 0; i < points.size(); ++i)
            keyed[i] = {keyOf(cellOf(points[i])), uint32_t(i)};
        std::sort(keyed.begin(), keyed.end());
        order_.resize(keyed.size());
        for (size_t i = 0; i < keyed.size(); ++i) {
            order_[i] = keyed[i].second;
            auto& range = ranges_[keyed[i].first];
            if (range.second == 0) range.first = uint32_t(i);
            range.second = uint32_t(i + 1);
        }
    }

    // Points sharing the cell of point i (the cost of a query near it).
    size_t occupancy(const Vec3& p) const {
        auto it = ranges_.find(keyOf(cellOf(p)));
        return it == ranges_.end() ? 0 : it->second.second - it->second.first;
    }

    // Distance from q to the nearest point at a non-zero distance; infinity when none.
    double nearestDistinct(const Vec3& q) const {
        const Cell c = cellOf(q);
        double best = std::numeric_limits<double>::infinity();
        for (int64_t r = 0;; ++r) {
            // Points in ring r are at least (r - 1) cells away.
            if (double(r - 1) * cell_ >= best || r > kMaxCellsPerAxis) return best;
            const double ringCells = double(2 * r + 1) * double(2 * r + 1) * double(2 * r + 1);
            if (ringCells > 8.0 * double(ranges_.size()) + 64.0) return bruteForce(q, best);
            scanRing(q, c, r, best);
        }
    }

    static constexpr int64_t kMaxCellsPerAxis = int64_t(1) << 20;

private:
    struct Cell {
        int64_t x, y, z;
    };
    Cell cellOf(const Vec3& p) const {
        auto axis = [&](float v, float lo) {
            return std::clamp(int64_t(std::floor((double(v) - lo) / cell_)), int64_t(0),
                              kMaxCellsPerAxis - 1);
        };
        return {axis(p.x, lo_.x), axis(p.y, lo_.y), axis(p.z, lo_.z)};
    }
    static uint64_t keyOf(const Cell& c) {
        return (uint64_t(c.x) << 42) | (uint64_t(c.y) << 21) | uint64_t(c.z);
    }
    static double distance(const Vec3& a, const Vec3& b) {
        double dx = double(a.x) - b.x, dy = double(a.y) - b.y, dz = double(a.z) - b.z;
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    void scanCell(const Vec3& q, const Cell& c, double& best) const {
        if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= kMaxCellsPerAxis || c.y >= kMaxCellsPerAxis ||
            c.z >= kMaxCellsPerAxis)
            return;
        auto it = ranges_.find(keyOf(c));
        if (it == ranges_.end()) return;
        for (uint32_t i = it->second.first; i < it->second.second; ++i) {
            double d = distance(q, points_[order_[i]]);
            if (d > 0.0 && d < best) best = d;
        }
    }
    void scanRing(const Vec3& q, const Cell& c, int64_t r, double& best) const {
        for (int64_t dx = -r; dx <= r; ++dx)
            for (int64_t dy = -r; dy <= r; ++dy) {
                const bool onShell = std::abs(dx) == r || std::abs(dy) == r;
                for (int64_t dz = -r; dz <= r; dz += onShell ? 1 : std::max<int64_t>(2 * r, 1))
                    scanCell(q, {c.x + dx, c.y + dy, c.z + dz}, best);
            }
    }
    double bruteForce(const Vec3& q, double best) const {
        for (const Vec3& p : points_) {
            double d = distance(q, p);
            if (d > 0.0 && d < best) best = d;
        }
        return best;
    }

    const std::vector<Vec3>& points_;
    Vec3 lo_;
    double cell_;
    std::vector<uint32_t> order_;
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges_;
};

constexpr size_t kRadiusSampleSize = 10000;

std::vector<uint32_t> radiusSample(size_t n) {
    std::vector<uint32_t> sample;
    const size_t k = std::min(n, kRadiusSampleSize);
    for (size_t i = 0; i < k; ++i) sample.push_back(uint32_t(uint64_t(i) * n / k));
    return sample;
}

Aabb pointBounds(const std::vector<Vec3>& points) {
    Aabb box = emptyAabb();
    for (const Vec3& p : points) grow(box, p);
    return box;
}

double boxDiagonal(const Aabb& box) {
    double dx = double(box.hi.x) - box.lo.x, dy = double(box.hi.y) - box.lo.y,
           dz = double(box.hi.z) - box.lo.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double meanSampleOccupancy(const PointGrid& grid, const std::vector<Vec3>& points,
                           const std::vector<uint32_t>& sample) {
    double sum = 0.0;
    for (uint32_t i : sample) sum += double(grid.occupancy(points[i]));
    return sum / double(sample.size());
}

// Cell edge: start at diagonal / cbrt(n) (about one point a cell for a filled box), then shrink
// while the sampled points' cells are crowded (flat or clustered clouds), so that a query scans
// few points. Exact duplicates keep a cell crowded, hence the cap on rounds.
double chooseCellSize(const std::vector<Vec3>& points, const Aabb& box,
                      const std::vector<uint32_t>& sample) {
    const double diag = boxDiagonal(box);
    const double minCell = diag / double(PointGrid::kMaxCellsPerAxis / 2);
    double cell = diag / std::cbrt(double(points.size()));
    for (int round = 0; round < 12 && cell > minCell; ++round) {
        double occupancy = meanSampleOccupancy(PointGrid(points, box, cell), points, sample);
        if (occupancy <= 8.0) break;
        cell = std::max(minCell, cell / std::max(2.0, std::cbrt(occupancy / 2.0)));
    }
    return cell;
}

}  // namespace

float defaultPointRadius(const std::vector<Vec3>& points) {
    const Aabb box = pointBounds(points);
    const double diag = points.empty() ? 0.0 : boxDiagonal(box);
    const float fallback = diag > 0.0 ? float(1e-3 * diag) : 1e-3f;
    if (points.size() < 2 || diag == 0.0) return fallback;
    const std::vector<uint32_t> sample = radiusSample(points.size());
    PointGrid grid(points, box, chooseCellSize(points, box, sample));
    std::vector<double> distances;
    for (uint32_t i : sample) {
        double d = grid.nearestDistinct(points[i]);
        if (std::isfinite(d)) distances.push_back(d);
    }
    if (distances.empty()) return fallback;
    auto median = distances.begin() + distances.size() / 2;
    std::nth_element(distances.begin(), median, distances.end());
    return float(0.5 * *median);
}

namespace {

Scene sphereScene(const std::string& path, const std::vector<Vec3>& points, LoadReport report,
                  const LoadOptions& opts) {
    if (points.empty())
        throw SceneError("cannot load " + inQuotes(path) + ": it has no usable points (" +
                         std::to_string(report.verticesRead) + " read, " +
                         std::to_string(report.droppedNonFinite) +
                         " dropped as non-finite); give at least one finite point");
    Scene scene;
    scene.name = path;
    scene.kind = PrimKind::Spheres;
    scene.report = std::move(report);
    const float radius = opts.radius > 0.0f ? opts.radius : defaultPointRadius(points);
    scene.spheres.reserve(points.size());
    for (const Vec3& p : points) scene.spheres.push_back({p, radius});
    return scene;
}

std::vector<Vec3> finitePoints(const std::vector<Vec3>& points, LoadReport& report) {
    std::vector<Vec3> kept;
    kept.reserve(points.size());
    for (const Vec3& p : points) {
        if (isFinite(p))
            kept.push_back(p);
        else
            ++report.droppedNonFinite;
    }
    return kept;
}

// Reads "x y z [more columns]" from one XYZ line; false when it is blank or a comment.
bool parseXyzLine(const std::string& line, uint64_t lineNo, const std::string& path, Vec3& p) {
    const char* s = line.c_str();
    while (std::isspace(static_cast<unsigned char>(*s))) ++s;
    if (*s == '\0' || *s == '#') return false;
    double c[3];
    for (double& v : c) {
        char* end = nullptr;
        v = std::strtod(s, &end);
        if (end == s || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end)))) {
            std::string text = line;
            trimLine(text);
            throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                             " (" + inQuotes(text.substr(0, 60)) +
                             ") does not start with 3 numbers; write x y z on every point line");
        }
        s = end;
    }
    p = {float(c[0]), float(c[1]), float(c[2])};  // beyond float range becomes inf: dropped
    return true;
}

Scene loadXyz(const std::string& path, const LoadOptions& opts) {
    std::ifstream in = openOrThrow(path);
    LoadReport report;
    report.format = "xyz";
    std::vector<Vec3> points;
    std::string line;
    uint64_t lineNo = 0;
    Vec3 p;
    while (std::getline(in, line))
        if (parseXyzLine(line, ++lineNo, path, p)) points.push_back(p);
    if (in.bad()) throw SceneError("cannot read " + inQuotes(path) + ": " + std::strerror(errno));
    report.verticesRead = points.size();
    std::vector<Vec3> kept = finitePoints(points, report);
    return sphereScene(path, kept, std::move(report), opts);
}

Scene loadPly(const std::string& path, const LoadOptions& opts) {
    const ElementCounts declared = readPlyHeader(path);
    RawMesh raw = readWithOpenMesh(path, "PLY");
    checkDeclaredCounts(path, declared, raw);
    if (declared.faces > 0) return buildMeshScene(path, "ply", raw, Survey{});
    LoadReport report;
    report.format = "ply";
    report.verticesRead = raw.vertices.size();
    std::vector<Vec3> kept = finitePoints(raw.vertices, report);
    return sphereScene(path, kept, std::move(report), opts);
}

Scene loadOff(const std::string& path) {
    const ElementCounts declared = readOffHeader(path);
    RawMesh raw = readWithOpenMesh(path, "OFF");
    checkDeclaredCounts(path, declared, raw);
    return buildMeshScene(path, "off", raw, Survey{});
}

Scene loadFile(const std::string& path, const std::string& ext, const LoadOptions& opts) {
    if (ext == "xyz") return loadXyz(path, opts);
    if (ext == "ply") return loadPly(path, opts);
    if (ext == "off") return loadOff(path);
    if (ext == "obj") {
        Survey survey = surveyObj(path);
        return buildMeshScene(path, "obj", readWithOpenMesh(path, "OBJ"), std::move(survey));
    }
    Survey survey = surveyStl(path);
    return buildMeshScene(path, "stl", readWithOpenMesh(path, "STL"), std::move(survey));
}

// "grid:N" or "grid:N:SEED", decimal, nothing else.
bool parseGridSpec(const std::string& spec, uint32_t& n, uint64_t& seed) {
    if (toLower(spec.substr(0, 5)) != "grid:") return false;
    std::string rest = spec.substr(5);
    size_t colon = rest.find(':');
    auto number = [&](const std::string& text, uint64_t max, uint64_t& out) {
        if (text.empty() || text.size() > 20 ||
            !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return false;
        errno = 0;
        unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
        out = v;
        return errno == 0 && v <= max;
    };
    uint64_t count = 0;
    seed = kGridCloudDefaultSeed;
    bool ok = number(rest.substr(0, colon), std::numeric_limits<uint32_t>::max(), count) &&
              (colon == std::string::npos ||
               number(rest.substr(colon + 1), std::numeric_limits<uint64_t>::max(), seed));
    if (!ok)
        throw SceneError("bad generator spec " + inQuotes(spec) +
                         "; write grid:N or grid:N:SEED with decimal N (1 .. 4294967295) and SEED");
    n = uint32_t(count);
    return true;
}

void checkRadiusOption(const std::string& path, const LoadOptions& opts) {
    if (std::isfinite(opts.radius) && opts.radius >= 0.0f) return;
    throw SceneError("invalid sphere radius " + std::to_string(opts.radius) + " for " +
                     inQuotes(path) + "; give a radius > 0, or 0 for the default rule");
}

}  // namespace

Scene loadScene(const std::string& path, const LoadOptions& opts) {
    checkRadiusOption(path, opts);
    try {
        uint32_t n = 0;
        uint64_t seed = 0;
        if (parseGridSpec(path, n, seed)) {
            if (opts.radius > 0.0f)
                throw SceneError("a sphere radius cannot be given for " + inQuotes(path) +
                                 ": the grid cloud's radius is fixed at 0.4 cell so that no "
                                 "sphere straddles two leaves; leave the radius at 0");
            return makeGridCloud(n, seed);
        }
        checkReadableFile(path);
        const std::string ext = lowerExtension(path);
        if (ext != "obj" && ext != "ply" && ext != "off" && ext != "stl" && ext != "xyz")
            throw SceneError(
                "unknown scene format " + (ext.empty() ? "(no extension)" : inQuotes("." + ext)) +
                " of " + inQuotes(path) + "; use .obj, .ply, .off, .stl, .xyz or grid:N[:SEED]");
        return loadFile(path, ext, opts);
    } catch (const SceneError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw SceneError("out of memory while loading " + inQuotes(path) +
                         "; use a smaller scene or a machine with more memory");
    } catch (const std::exception& e) {
        throw SceneError("cannot load " + inQuotes(path) + ": " + e.what());
    }
}

}  // namespace oct
