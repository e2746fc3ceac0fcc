// Scene loading. Meshes go through OpenMesh's readers into RawMeshImporter, which records what
// the reader hands over without building a halfedge mesh (an OpenMesh mesh would reject
// non-manifold faces). Because OpenMesh's readers silently skip or misread some input before any
// importer sees it, each format is first surveyed here: the survey counts the file's faces,
// predicts which of them the reader will hand over (so sourceFace stays a file face index and
// the skipped ones are counted), and refuses, with a SceneError, input that a reader would
// silently misread (an unparsable number in an ASCII PLY/OFF/STL file, a NaN in a binary STL),
// hang on (a PLY header token its number parser rejects), crash or abort on (a PLY property
// before any element, an OBJ corner without a vertex), or size from an impossible header count
// (every declared count is checked against the file's bytes first, by division, so nothing
// overflows and nothing is allocated from it). docs/ROBUSTNESS.md lists the cases;
// tests/data/bad/ holds one file for each, and fuzz/ fuzzes this whole path.
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
    // A FIFO would block the read forever and a device such as /dev/zero never ends.
    if (!fs::is_regular_file(status))
        throw SceneError("cannot load " + inQuotes(path) +
                         ": it is not a regular file (a pipe, socket or device); copy the scene "
                         "into a file first");
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

uint64_t fileSize(const std::string& path) {
    std::error_code ec;
    uint64_t size = fs::file_size(path, ec);
    if (ec) throw SceneError("cannot read " + inQuotes(path) + ": " + ec.message());
    return size;
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
    uint64_t skippedInvalidIndex = 0;  // faces the reader skipped: an index beyond int range
    // OBJ: per handed-over face, whether the reader silently left out a corner whose index
    // does not fit an int (it hands over the rest): such a face is dropped as an invalid index.
    std::vector<bool> lostCorner;
    // OBJ: OpenMesh drops a "v" line whose coordinates do not parse (nan, inf, overflow, garbage)
    // while face indices still count it, so later vertices shift. One flag per "v" line lets the
    // file's vertex numbers be mapped back to the reader's.
    bool isObj = false;
    std::vector<bool> vertexLineOk;
};

// One OBJ "f" line, decided as OpenMesh's OBJ reader decides it: the first component of each
// corner is the vertex (negative = relative to the "v" lines so far); repeated vertices are
// removed; fewer than 3 left and the reader skips the face without a word.
void surveyObjFace(std::istringstream& rest, size_t vertexLinesSoFar, Survey& s,
                   const std::string& path, uint64_t lineNo) {
    const uint32_t face = uint32_t(s.facesInFile++);
    std::vector<long long> corners;
    std::string token;
    bool lostCorner = false;
    while (rest >> token) {
        // A corner without '/' whose number does not parse is skipped; one with '/' is kept
        // with the value operator>> leaves behind (0 on garbage, INT_MAX/INT_MIN on overflow).
        const size_t slash = token.find('/');
        // A corner without a vertex index ("/2", "/2/3") makes Debian's OpenMesh, built with
        // assertions, abort the process (assert(!vhandles.empty()) in its OBJ reader).
        if (slash == 0)
            throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                             " has a face corner " + inQuotes(token) +
                             " without a vertex index; every corner needs one (v, v/vt, v//vn "
                             "or v/vt/vn)");
        std::istringstream number(token.substr(0, slash));
        int value = 0;
        if (!(number >> value) && slash == std::string::npos) {
            // A number that overflows int is an index naming no vertex, not a stray word.
            const std::string digits = token.substr(token[0] == '-' || token[0] == '+' ? 1 : 0);
            lostCorner = lostCorner || (!digits.empty() && digits.find_first_not_of("0123456789") ==
                                                               std::string::npos);
            continue;
        }
        corners.push_back(value < 0 ? (long long)vertexLinesSoFar + value : (long long)value - 1);
    }
    const size_t listed = corners.size();
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    if (corners.size() > 2) {
        s.handedOver.push_back(face);
        s.lostCorner.push_back(lostCorner);
    } else if (lostCorner)
        ++s.skippedInvalidIndex;
    else if (listed < 3)
        ++s.skippedTooFew;
    else
        ++s.skippedDegenerate;
}

// OpenMesh's OBJ reader opens "mtllib NAME" as the OBJ's folder + NAME and reads it line by
// line to its end: a FIFO there blocks forever and a device such as /dev/zero never ends.
void checkMaterialFile(const std::string& path, std::istringstream& rest) {
    std::string name;
    std::getline(rest, name);
    trimLine(name);
    const size_t slash = path.rfind('/');
    const std::string material =
        (slash == std::string::npos ? std::string("./") : path.substr(0, slash + 1)) + name;
    std::error_code ec;
    const fs::file_status status = fs::status(material, ec);
    if (ec || !fs::exists(status) || fs::is_regular_file(status) || fs::is_directory(status))
        return;  // missing or unreadable: OpenMesh warns and goes on; a folder reads as empty
    throw SceneError("cannot load " + inQuotes(path) + ": its material library " +
                     inQuotes(material) +
                     " is not a regular file (a pipe or device would hang the reader); fix or "
                     "remove the 'mtllib' line");
}

Survey surveyObj(const std::string& path) {
    std::ifstream in = openOrThrow(path);
    Survey s;
    s.isObj = true;
    s.surveyed = true;
    std::string line, keyword;
    uint64_t lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        trimLine(line);
        if (line.empty() || line[0] == '#') continue;
        std::istringstream stream(line);
        stream >> keyword;
        if (keyword == "v") {
            float x, y, z;  // parsed exactly as OpenMesh parses them: operator>> into float
            stream >> x >> y >> z;
            s.vertexLineOk.push_back(!stream.fail());
        } else if (keyword == "f") {
            surveyObjFace(stream, s.vertexLineOk.size(), s, path, lineNo);
        } else if (keyword == "mtllib") {
            checkMaterialFile(path, stream);
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

// True when the file's first non-blank characters are "solid", as an ASCII STL must begin.
bool stlLooksAscii(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    char head[512];
    in.read(head, sizeof head);
    std::string text(head, size_t(in.gcount()));
    size_t begin = text.find_first_not_of(" \t\r\n");
    return begin != std::string::npos && toLower(text.substr(begin, 5)) == "solid";
}

Survey surveyStl(const std::string& path) {
    uint32_t facetCount = 0;
    if (stlIsBinary(path, facetCount)) return surveyBinaryStl(path, facetCount);
    // OpenMesh reads every file whose size is not exactly that of a binary STL as ASCII, so a
    // truncated or padded binary STL, or any other bytes, would load as an empty mesh.
    if (!stlLooksAscii(path)) {
        const uint64_t size = fileSize(path);
        throw SceneError("cannot load " + inQuotes(path) +
                         ": it is neither an ASCII STL (which starts with "
                         "'solid') nor a binary STL of the size its header declares" +
                         (size >= 84 ? " (" + std::to_string(facetCount) + " facets need " +
                                           std::to_string(84 + 50 * uint64_t(facetCount)) +
                                           " bytes, the file has " + std::to_string(size) + ")"
                                     : " (the file has " + std::to_string(size) +
                                           " bytes, fewer than a binary "
                                           "STL's 84-byte header)") +
                         "; the file is truncated, padded or not an STL file");
    }
    return surveyAsciiStl(path);
}

// ---------------------------------------------------------------------------------------------
// Declared counts against the file's bytes. Every count a header declares is checked against
// what the rest of the file could possibly hold before any reader runs (and so before anything
// is sized from it): an element that needs at least `minBytes` bytes cannot occur more than
// `available / minBytes` times. Overflow-safe: it divides instead of multiplying.

[[noreturn]] void refuseCount(const std::string& path, uint64_t count, const std::string& what,
                              uint64_t available, uint64_t minBytes) {
    throw SceneError("cannot load " + inQuotes(path) + ": its header declares " +
                     std::to_string(count) + " " + what + ", but the " + std::to_string(available) +
                     " bytes after the header hold at most " +
                     std::to_string(minBytes ? available / minBytes : 0) +
                     "; the file is truncated or its header is wrong");
}

void checkCountFits(const std::string& path, uint64_t count, const std::string& what,
                    uint64_t& available, uint64_t minBytes) {
    if (minBytes == 0 || count == 0) return;
    if (count > available / minBytes) refuseCount(path, count, what, available, minBytes);
    available -= count * minBytes;
}

// Buffered forward reader over a binary body; read() and skip() return false at the end.
class ByteReader {
public:
    ByteReader(const std::string& path, uint64_t start)
        : in_(openOrThrow(path, std::ios::in | std::ios::binary)), pos_(start) {
        in_.seekg(std::streamoff(start));
    }
    bool read(void* out, size_t n) {
        if (!fill(n)) return false;
        std::memcpy(out, buffer_.data() + head_, n);
        head_ += n;
        pos_ += n;
        return true;
    }
    bool skip(uint64_t n) {
        uint64_t buffered = buffer_.size() - head_;
        if (n <= buffered) {
            head_ += size_t(n);
            pos_ += n;
            return true;
        }
        n -= buffered;
        pos_ += buffered;
        buffer_.clear();
        head_ = 0;
        in_.clear();
        in_.seekg(std::streamoff(n), std::ios::cur);
        char probe;  // seeking past the end succeeds; reading the last skipped byte does not
        in_.seekg(-1, std::ios::cur);
        if (!in_.get(probe)) return false;
        pos_ += n;
        return true;
    }
    uint64_t position() const { return pos_; }

private:
    bool fill(size_t n) {
        if (buffer_.size() - head_ >= n) return true;
        buffer_.erase(buffer_.begin(), buffer_.begin() + std::ptrdiff_t(head_));
        head_ = 0;
        const size_t want = std::max<size_t>(n - buffer_.size(), 1 << 16);
        const size_t old = buffer_.size();
        buffer_.resize(old + want);
        in_.read(buffer_.data() + old, std::streamsize(want));
        buffer_.resize(old + size_t(in_.gcount()));
        return buffer_.size() >= n;
    }

    std::ifstream in_;
    std::vector<char> buffer_;
    size_t head_ = 0;
    uint64_t pos_;
};

// Walks the body of an ASCII PLY or OFF file the way OpenMesh's reader consumes it, and checks
// what that reader does not: every value it parses with operator>> must be a number of the kind
// it reads there (an integer where it reads an int, within 32 bits), and the file must hold
// every declared element. After a token it cannot parse (nan, inf, 1e39, 0x10, a '#' comment),
// or at the end of a short file, its stream fails and every later value silently repeats the
// last one read: a truncated face list ends in copies of its last face. Such files are
// refused, naming the line.
class AsciiBody {
public:
    AsciiBody(std::istream& in, uint64_t linesBefore, const std::string& path,
              const std::string& format)
        : in_(in), lineNo_(linesBefore), path_(path), format_(format) {}

    // A value read with `>> float`: only the characters that parser accepts, all of them
    // consumed, finite and within float range (it fails on overflow).
    double number() {
        std::string token = next();
        char* end = nullptr;
        double value = std::strtod(token.c_str(), &end);
        if (token.find_first_not_of("0123456789+-.eE") != std::string::npos || *end != '\0' ||
            !std::isfinite(value) || std::fabs(value) > FLT_MAX)
            refuse(token, "a finite number");
        return value;
    }
    // A value read with `>> int` (signedInt) or `>> unsigned int`: decimal digits with an
    // optional sign, within what that type's parser accepts.
    long long integer(bool signedInt = false) {
        std::string token = next();
        char* end = nullptr;
        errno = 0;
        long long value = std::strtoll(token.c_str(), &end, 10);
        const long long lo = signedInt ? INT32_MIN : -(long long)UINT32_MAX;
        const long long hi = signedInt ? INT32_MAX : (long long)UINT32_MAX;
        if (token.empty() || *end != '\0' || errno != 0 || value < lo || value > hi)
            refuse(token, signedInt ? "a 32-bit integer" : "a 32-bit unsigned integer");
        return value;
    }
    // A list length read with `>> unsigned int`: OpenMesh would take -1 as about 4 billion.
    uint64_t count() {
        long long value = integer();
        if (value < 0) refuse(std::to_string(value), "a count >= 0");
        return uint64_t(value);
    }
    void anyToken() { next(); }  // read with `>> std::string`: anything goes
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
        std::string shown = token.size() > 40 ? token.substr(0, 40) + "..." : token;
        throw SceneError("cannot load " + inQuotes(path_) + ": line " + std::to_string(lineNo_) +
                         " holds " + inQuotes(shown) + " where OpenMesh's ASCII " + format_ +
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
    uint64_t vertices = 0;
    uint64_t faces = 0;
};

// --- PLY -------------------------------------------------------------------------------------
// OpenMesh's PLY reader parses the header token by token with operator>> and loops until it
// reads "end_header": a header that ends early, or a token its number parser rejects, makes
// that loop spin forever; a "property" before any "element" dereferences an empty vector. It
// then reads each property as its name and type dictate, and a type it cannot read there is
// read as zero bytes, shifting every later value. The header is therefore parsed here exactly
// as that reader parses it (same stream operations on the same bytes), and everything it would
// hang on, crash on or misread is refused before it runs.

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, None };

// OpenMesh's get_property_type: the first of these names found in either token wins.
PlyType plyTypeOf(const std::string& a, const std::string& b) {
    static const std::pair<const char*, PlyType> kNames[] = {
        {"float32", PlyType::Float32}, {"float64", PlyType::Float64}, {"float", PlyType::Float32},
        {"double", PlyType::Float64},  {"int8", PlyType::Int8},       {"uint8", PlyType::UInt8},
        {"char", PlyType::Int8},       {"uchar", PlyType::UInt8},     {"int32", PlyType::Int32},
        {"uint32", PlyType::UInt32},   {"int", PlyType::Int32},       {"uint", PlyType::UInt32},
        {"int16", PlyType::Int16},     {"uint16", PlyType::UInt16},   {"short", PlyType::Int16},
        {"ushort", PlyType::UInt16}};
    for (const auto& [name, type] : kNames)
        if (a == name || b == name) return type;
    return PlyType::None;
}

size_t plyTypeBytes(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
        default:
            return 0;
    }
}

bool plyIsFloat(PlyType t) { return t == PlyType::Float32 || t == PlyType::Float64; }

// How OpenMesh's reader consumes one property.
enum class PlyRead : uint8_t {
    Float,    // coordinates, normals, texture coordinates, float colours: `>> float`/readValue
    Int,      // colours of any other type: `>> int` / readInteger
    Skip,     // everything else: `>> std::string` / skip the type's bytes
    Indices,  // the face's vertex_indices list
};

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::None;       // the value's type (a list's entry type)
    PlyType countType = PlyType::None;  // a list's length type; None when not a list
    PlyRead read = PlyRead::Skip;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    bool ascii = true;
    bool bigEndian = false;
    std::vector<PlyElement> elements;
    uint64_t dataStart = 0;  // byte offset of the body
    uint64_t headerLines = 0;
};

PlyRead plyReadOf(const std::string& element, const std::string& name, PlyType type) {
    static const char* kVertexFloats[] = {"x", "y", "z", "nx", "ny", "nz", "u", "s", "v", "t"};
    static const char* kColours[] = {"red",         "green",         "blue",        "alpha",
                                     "diffuse_red", "diffuse_green", "diffuse_blue"};
    const bool isVertex = element == "vertex", isFace = element == "face";
    if (isVertex)
        for (const char* n : kVertexFloats)
            if (name == n) return PlyRead::Float;
    for (size_t i = 0; i < std::size(kColours); ++i)
        if (name == kColours[i] && (isVertex || (isFace && i < 4)))
            return type == PlyType::Float32 ? PlyRead::Float : PlyRead::Int;
    return PlyRead::Skip;
}

class PlyHeaderParser {
public:
    explicit PlyHeaderParser(const std::string& path)
        : path_(path), in_(openOrThrow(path, std::ios::in | std::ios::binary)) {}

    PlyHeader parse() {
        std::string first;
        std::getline(in_, first);
        trimLine(first);
        if (first != "ply" && first != "PLY")
            refuse("its first line is not 'ply'; check that it is a PLY file");
        PlyHeader h;
        std::string keyword = token("the format line"), format = token("the format line");
        if (keyword != "format")
            refuse(
                "its second line must be 'format ascii|binary_little_endian|"
                "binary_big_endian 1.0'");
        if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
            refuse("format " + inQuotes(format) +
                   " is not ascii, binary_little_endian or binary_big_endian");
        h.ascii = format == "ascii";
        h.bigEndian = format == "binary_big_endian";
        const std::string version = token("the format line");
        if (!isStrictNumber(version))
            refuse("its format version " + inQuotes(version) + " is not a number");
        std::streamoff beforeKeyword = in_.tellg();
        for (keyword = token("an 'end_header' line"); keyword != "end_header";
             keyword = token("an 'end_header' line")) {
            if (keyword == "comment") {
                std::string rest;
                std::getline(in_, rest);
            } else if (keyword == "element") {
                addElement(h);
            } else if (keyword == "property") {
                addProperty(h);
            }  // any other token is skipped alone, as OpenMesh skips it
            beforeKeyword = in_.tellg();
        }
        checkElements(h);
        findBody(h, beforeKeyword);
        return h;
    }

    std::ifstream& stream() { return in_; }

private:
    static bool isStrictNumber(const std::string& s) {
        char* end = nullptr;
        std::strtod(s.c_str(), &end);
        return !s.empty() && s.find_first_not_of("0123456789+-.eE") == std::string::npos &&
               *end == '\0';
    }

    std::string token(const char* what) {
        std::string t;
        if (!(in_ >> t))
            refuse(std::string("the header ends before ") + what +
                   " (OpenMesh's reader would loop forever); check that it is a PLY file");
        return t;
    }

    void addElement(PlyHeader& h) {
        PlyElement e;
        e.name = token("the element's name");
        const std::string count = token("the element's count");
        errno = 0;
        const unsigned long long value = std::strtoull(count.c_str(), nullptr, 10);
        if (count.find_first_not_of("0123456789") != std::string::npos || count.size() > 10 ||
            errno != 0 || value > UINT32_MAX)
            refuse("element " + inQuotes(e.name) + " has count " + inQuotes(count) +
                   ", not a whole number from 0 to 4294967295");
        e.count = value;
        for (const PlyElement& other : h.elements)
            if (other.name == e.name && (e.name == "vertex" || e.name == "face"))
                refuse("it declares element " + inQuotes(e.name) + " twice");
        h.elements.push_back(e);
    }

    void addProperty(PlyHeader& h) {
        if (h.elements.empty())
            refuse("a 'property' comes before any 'element' (OpenMesh's reader would crash)");
        PlyElement& e = h.elements.back();
        PlyProperty p;
        const std::string first = token("the property's type");
        if (first == "list") {
            const std::string countType = token("the list's count type");
            const std::string entryType = token("the list's entry type");
            p.name = token("the list's name");
            if (!(e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index")))
                refuse("list property " + inQuotes(p.name) + " of element " + inQuotes(e.name) +
                       " is not supported by OpenMesh's PLY reader; remove it from the file");
            if (countType != "uint8" && countType != "uchar" && countType != "uint16" &&
                countType != "int")
                refuse("the count type " + inQuotes(countType) + " of list " + inQuotes(p.name) +
                       " is not one OpenMesh reads (uchar, uint8, uint16, int)");
            p.countType = plyTypeOf(countType, countType);
            p.type = plyTypeOf(entryType, entryType);
            if (p.type == PlyType::None || plyIsFloat(p.type))
                refuse("the entry type " + inQuotes(entryType) + " of list " + inQuotes(p.name) +
                       " is not an integer type");
            p.read = PlyRead::Indices;
            for (const PlyProperty& other : e.properties)
                if (other.read == PlyRead::Indices) refuse("element 'face' has two index lists");
        } else {
            const std::string second = token("the property's name");
            p.type = plyTypeOf(first, second);
            if (p.type == PlyType::None)
                refuse("property " + inQuotes(first + " " + second) + " of element " +
                       inQuotes(e.name) + " has no type OpenMesh knows (e.g. float, uchar, int)");
            p.name = plyTypeOf(first, first) != PlyType::None ? second : first;
            p.read = plyReadOf(e.name, p.name, p.type);
        }
        e.properties.push_back(p);
    }

    void checkElements(const PlyHeader& h) {
        const PlyElement* vertex = nullptr;
        for (const PlyElement& e : h.elements) {
            if (e.name == "vertex") vertex = &e;
            if (e.count > 0 && e.properties.empty())
                refuse("element " + inQuotes(e.name) + " declares " + std::to_string(e.count) +
                       " items but no properties");
            if (e.name == "face" && e.count > 0 &&
                std::none_of(e.properties.begin(), e.properties.end(),
                             [](const PlyProperty& p) { return p.read == PlyRead::Indices; }))
                refuse("element 'face' has no 'vertex_indices' list");
            if (e.name == "face") break;  // OpenMesh reads nothing after the faces
        }
        int axes[3] = {0, 0, 0};
        if (vertex)
            for (const PlyProperty& p : vertex->properties)
                for (int a = 0; a < 3; ++a) axes[a] += p.name == std::string(1, char('x' + a));
        if (!vertex || axes[0] != 1 || axes[1] != 1 || axes[2] != 1)
            refuse(
                "it needs an 'element vertex', before any 'element face', with one each of "
                "the properties x, y and z");
        if (h.ascii) return;
        // Binary bodies: OpenMesh reads these properties only from the types named here and
        // reads any other type as zero bytes.
        for (const PlyElement& e : h.elements)
            for (const PlyProperty& p : e.properties) {
                const bool ok = p.read == PlyRead::Float ? plyIsFloat(p.type)
                                : p.read == PlyRead::Int ? !plyIsFloat(p.type)
                                                         : true;
                if (!ok)
                    refuse("property " + inQuotes(p.name) + " of element " + inQuotes(e.name) +
                           " has a type OpenMesh's binary reader cannot read there (it would "
                           "misread every later value); use " +
                           (p.read == PlyRead::Float ? "float or double" : "an integer type"));
            }
    }

    // OpenMesh starts a binary body 12 bytes (14 after "\r\n") past the end of the token
    // before "end_header", which is right only when exactly one line break separates them
    // and one line break follows end_header. A comment line or trailing blanks before it put
    // every value a few bytes off.
    void findBody(PlyHeader& h, std::streamoff beforeKeyword) {
        std::streamoff afterKeyword = in_.tellg();
        if (afterKeyword < 0) {  // "end_header" is the file's last token
            in_.clear();
            afterKeyword = std::streamoff(fileSize(path_));
        }
        std::string rest;
        std::getline(in_, rest);
        const std::streamoff nextLine = in_.tellg();
        h.dataStart = nextLine < 0 ? fileSize(path_) : uint64_t(nextLine);
        in_.clear();
        std::string headerText(size_t(afterKeyword), '\0');
        in_.seekg(0);
        in_.read(headerText.data(), afterKeyword);
        h.headerLines = uint64_t(std::count(headerText.begin(), headerText.end(), '\n')) + 1;
        if (h.ascii) {
            trimLine(rest);
            if (!rest.empty()) refuse("values follow 'end_header' on its line");
            in_.clear();
            in_.seekg(std::streamoff(h.dataStart));
            return;
        }
        const char c1 = headerText[size_t(beforeKeyword)];
        const char c2 = size_t(beforeKeyword) + 1 < headerText.size()
                            ? headerText[size_t(beforeKeyword) + 1]
                            : '\0';
        const uint64_t openMeshStart =
            uint64_t(beforeKeyword) + (c1 == '\r' && c2 == '\n' ? 14 : 12);
        if ((rest != "" && rest != "\r") || openMeshStart != h.dataStart)
            refuse("OpenMesh's binary PLY reader would start reading the data at byte " +
                   std::to_string(openMeshStart) + " instead of " + std::to_string(h.dataStart) +
                   " (a comment or blanks just before 'end_header', or after it); put "
                   "'end_header' on its own line right after the last property");
    }

    [[noreturn]] void refuse(const std::string& why) const {
        throw SceneError("cannot read " + inQuotes(path_) + " as PLY: " + why);
    }

    std::string path_;
    std::ifstream in_;
};

// Bytes of one item of an element without lists (the face's index list counted as its length).
uint64_t plyMinItemBytes(const PlyElement& e) {
    uint64_t bytes = 0;
    for (const PlyProperty& p : e.properties)
        bytes += plyTypeBytes(p.read == PlyRead::Indices ? p.countType : p.type);
    return bytes;
}

uint64_t plyListLength(const char* raw, PlyType type, bool bigEndian, bool& negative) {
    unsigned char b[4] = {0, 0, 0, 0};
    const size_t n = plyTypeBytes(type);
    for (size_t i = 0; i < n; ++i) b[i] = uint8_t(raw[bigEndian ? n - 1 - i : i]);
    const uint32_t v =
        uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    negative = type == PlyType::Int32 && int32_t(v) < 0;
    return v;
}

void walkPlyBinary(const std::string& path, const PlyHeader& h) {
    ByteReader body(path, h.dataStart);
    auto truncated = [&](const PlyElement& e, uint64_t i) {
        throw SceneError("cannot load " + inQuotes(path) + ": its binary body ends in " + e.name +
                         " " + std::to_string(i) + " of the " + std::to_string(e.count) +
                         " its header declares; the file is truncated");
    };
    for (const PlyElement& e : h.elements) {
        const bool hasList =
            std::any_of(e.properties.begin(), e.properties.end(),
                        [](const PlyProperty& p) { return p.countType != PlyType::None; });
        if (!hasList) {
            if (!body.skip(e.count * plyMinItemBytes(e))) truncated(e, 0);  // count fits: checked
        } else {
            char raw[4];
            for (uint64_t i = 0; i < e.count; ++i)
                for (const PlyProperty& p : e.properties) {
                    if (p.countType == PlyType::None) {
                        if (!body.skip(plyTypeBytes(p.type))) truncated(e, i);
                        continue;
                    }
                    bool negative = false;
                    if (!body.read(raw, plyTypeBytes(p.countType))) truncated(e, i);
                    const uint64_t n = plyListLength(raw, p.countType, h.bigEndian, negative);
                    if (negative)
                        throw SceneError("cannot load " + inQuotes(path) + ": " + e.name + " " +
                                         std::to_string(i) + " has a list of length " +
                                         std::to_string(int32_t(n)) + "; fix that face");
                    if (!body.skip(n * plyTypeBytes(p.type))) truncated(e, i);
                }
        }
        if (e.name == "face") return;
    }
}

void walkPlyAscii(std::istream& in, const std::string& path, const PlyHeader& h) {
    AsciiBody body(in, h.headerLines, path, "PLY");
    for (const PlyElement& e : h.elements) {
        for (uint64_t i = 0; i < e.count; ++i)
            for (const PlyProperty& p : e.properties) {
                if (e.name != "vertex" && e.name != "face") {
                    body.anyToken();
                    continue;
                }
                switch (p.read) {
                    case PlyRead::Float:
                        body.number();
                        break;
                    case PlyRead::Int:
                        body.integer(true);
                        break;
                    case PlyRead::Skip:
                        body.anyToken();
                        break;
                    case PlyRead::Indices:
                        for (uint64_t n = body.count(), k = 0; k < n; ++k) body.integer();
                        break;
                }
            }
        if (e.name == "face") return;  // OpenMesh stops reading after the faces
    }
}

ElementCounts readPlyHeader(const std::string& path) {
    PlyHeaderParser parser(path);
    const PlyHeader h = parser.parse();
    ElementCounts counts;
    uint64_t available = fileSize(path) - std::min(fileSize(path), h.dataStart);
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") counts.vertices = e.count;
        if (e.name == "face") counts.faces = e.count;
        // An ASCII value takes at least a character and a separator.
        const uint64_t minBytes = h.ascii ? 2 * uint64_t(e.properties.size()) : plyMinItemBytes(e);
        const std::string what = e.name == "vertex" ? "vertices"
                                 : e.name == "face" ? "faces"
                                                    : inQuotes(e.name) + " items";
        checkCountFits(path, e.count, what, available, minBytes);
        if (e.name == "face") break;
    }
    if (h.ascii)
        walkPlyAscii(parser.stream(), path, h);
    else
        walkPlyBinary(path, h);
    return counts;
}

// --- OFF -------------------------------------------------------------------------------------
// Header "[ST][C][N][4][n]OFF[ BINARY]", parsed as OpenMesh's can_u_read parses it: the
// prefixes in this order, "OFF", then "BINARY" exactly one character after it. ST adds texture
// coordinates and C colours to the rest of each vertex line (ASCII) or 8 and 12 bytes to each
// vertex (binary); N adds a normal after each vertex; 4 and n are refused by OpenMesh.
struct OffHeader {
    bool binary = false;
    bool texCoords = false, colours = false, normals = false;
};

OffHeader parseOffFirstLine(const std::string& path, const std::string& line) {
    OffHeader h;
    size_t p = 0;
    // OpenMesh counts the line's terminator among the characters it may look at.
    const size_t n = line.size() + 1;
    if (n > 1 && line.compare(0, 2, "ST") == 0) h.texCoords = true, p += 2;
    if (p < n && line[p] == 'C') h.colours = true, ++p;
    if (p < n && line[p] == 'N') h.normals = true, ++p;
    const bool fourD = (p < n && line[p] == '4') ? (++p, true) : false;
    const bool nD = (p < n && line[p] == 'n') ? (++p, true) : false;
    if (n - p < 3 || line.compare(p, 3, "OFF") != 0)
        throw SceneError("cannot read " + inQuotes(path) +
                         " as OFF: its first line must be [ST][C][N]OFF or the same with "
                         "' BINARY'; check that it is an OFF file");
    if (fourD || nD)
        throw SceneError("cannot read " + inQuotes(path) +
                         " as OFF: 4OFF and nOFF (other than 3 dimensions) are not supported");
    const size_t rest = n - p >= 4 ? n - p - 4 : 0;
    h.binary = rest >= 6 && line.compare(p + 4, 6, "BINARY") == 0;
    return h;
}

void walkOffBody(AsciiBody& body, const OffHeader& h, ElementCounts& counts) {
    for (uint64_t v = 0; v < counts.vertices; ++v) {
        for (int k = 0; k < (h.normals ? 6 : 3); ++k) body.number();
        body.skipRestOfLine();  // colours and texture coordinates: read from the rest alone
    }
    for (uint64_t f = 0; f < counts.faces; ++f) {
        for (uint64_t n = body.count(), k = 0; k < n; ++k) body.integer();
        if (h.colours) body.skipRestOfLine();
    }
}

// Binary OFF: little-endian uint32 counts nV nF nE, vertices of 3 floats (+ 3 for N, + 3
// int32 colours for C, + 2 floats for ST), then faces as a uint32 length and as many uint32
// indices; OpenMesh's reader checks neither count against the file, nor the end of the file.
void walkOffBinary(const std::string& path, uint64_t start, const OffHeader& h,
                   ElementCounts& counts) {
    ByteReader body(path, start);
    uint32_t header[3];
    if (!body.read(header, sizeof header))
        throw SceneError("cannot load " + inQuotes(path) +
                         ": its binary header ends before the 3 counts; the file is truncated");
    counts.vertices = header[0];
    counts.faces = header[1];
    const uint64_t vertexBytes =
        12 + (h.normals ? 12 : 0) + (h.colours ? 12 : 0) + (h.texCoords ? 8 : 0);
    uint64_t available = fileSize(path) - std::min(fileSize(path), body.position());
    checkCountFits(path, counts.vertices, "vertices", available, vertexBytes);
    checkCountFits(path, counts.faces, "faces", available, 4);
    body.skip(counts.vertices * vertexBytes);
    for (uint64_t f = 0; f < counts.faces; ++f) {
        uint32_t n = 0;
        if (!body.read(&n, 4) || !body.skip(uint64_t(n) * 4))
            throw SceneError("cannot load " + inQuotes(path) + ": its binary body ends in face " +
                             std::to_string(f) + " of the " + std::to_string(counts.faces) +
                             " its header declares; the file is truncated");
    }
}

ElementCounts readOffHeader(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    ElementCounts counts;
    std::string first;
    std::getline(in, first);
    const OffHeader h = parseOffFirstLine(path, first);
    if (h.binary) {
        walkOffBinary(path, uint64_t(first.size()) + 1, h, counts);
        return counts;
    }
    AsciiBody body(in, 1, path, "OFF");
    counts.vertices = body.count();
    counts.faces = body.count();
    body.integer();  // edge count, unused
    // Each vertex takes at least "0 0 0\n", each face "0\n".
    uint64_t available = fileSize(path) - std::min<uint64_t>(fileSize(path), first.size());
    checkCountFits(path, counts.vertices, "vertices", available, 6);
    checkCountFits(path, counts.faces, "faces", available, 2);
    walkOffBody(body, h, counts);
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
    s.lostCorner.resize(s.handedOver.size(), false);
    if (s.handedOver.size() == handedOver) return;
    uint64_t skipped = s.facesInFile > handedOver ? s.facesInFile - handedOver : 0;
    s.skippedTooFew = std::min(s.skippedTooFew, skipped);
    s.skippedInvalidIndex = std::min(s.skippedInvalidIndex, skipped - s.skippedTooFew);
    s.skippedDegenerate = skipped - s.skippedTooFew - s.skippedInvalidIndex;
    s.lostCorner.assign(handedOver, false);
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
    report.droppedInvalidIndex = survey.skippedInvalidIndex;
    std::vector<Vec3> corners;
    for (size_t f = 0; f < raw.faceCount(); ++f) {
        if (survey.lostCorner[f]) {
            ++report.droppedInvalidIndex;
            continue;
        }
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
    // The search runs over the distinct points: exact duplicates are at distance zero and
    // ignored anyway, and a cloud of many copies of a few points would otherwise make every
    // query scan all copies in its cell (seconds to minutes for a million copies).
    std::vector<Vec3> distinct(points);
    auto less = [](const Vec3& a, const Vec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(distinct.begin(), distinct.end(), less);
    distinct.erase(std::unique(distinct.begin(), distinct.end(),
                               [](const Vec3& a, const Vec3& b) {
                                   return a.x == b.x && a.y == b.y && a.z == b.z;
                               }),
                   distinct.end());
    PointGrid grid(distinct, box, chooseCellSize(distinct, box, radiusSample(distinct.size())));
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
    if (line.find('\0') != std::string::npos)
        throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                         " holds a NUL byte; an .xyz file is text, x y z on every point line");
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

// Largest |coordinate| (sphere centres plus the radius) of the scene's primitives.
double largestCoordinate(const Scene& scene) {
    double m = 0.0;
    auto take = [&](const Vec3& v, double pad) {
        m = std::max({m, std::fabs(double(v.x)) + pad, std::fabs(double(v.y)) + pad,
                      std::fabs(double(v.z)) + pad});
    };
    for (const Triangle& t : scene.triangles) {
        take(t.v0, 0.0);
        take(t.v1, 0.0);
        take(t.v2, 0.0);
    }
    for (const Sphere& s : scene.spheres) take(s.center, double(s.radius));
    return m;
}

std::string shortNumber(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

// The numeric range of core/geometry/numeric_range.h (load_scene.h says why).
void checkSceneRange(const Scene& scene) {
    if (uint64_t(scene.triangles.size()) + scene.spheres.size() >= UINT32_MAX)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": it has more than 2^32 - 2 " +
                         "primitives, beyond octrace's 32-bit primitive ids; split the scene");
    const std::string where =
        " (docs/ROBUSTNESS.md, numeric range: float32 ray tests, ours and Embree's, are only "
        "correct inside it); rescale the scene";
    const double largest = largestCoordinate(scene);
    if (largest > kMaxSceneCoordinate)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": its coordinates reach " +
                         shortNumber(largest) + ", beyond +-" + shortNumber(kMaxSceneCoordinate) +
                         where);
    const Vec3 e = scene.bounds().extent();
    const double extent = std::max({double(e.x), double(e.y), double(e.z)});
    if (extent < double(float(kMinSceneExtent)))  // as float: "1e-6" in a file is accepted
        throw SceneError("cannot load " + inQuotes(scene.name) + ": its extent " +
                         shortNumber(extent) + " is below " + shortNumber(kMinSceneExtent) + where);
    uint64_t tiny = 0;
    double smallest = INFINITY;
    for (const Triangle& t : scene.triangles) {
        const double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y,
                     az = double(t.v1.z) - t.v0.z;
        const double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y,
                     bz = double(t.v2.z) - t.v0.z;
        const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
        const double twiceArea = std::sqrt(cx * cx + cy * cy + cz * cz);
        if (twiceArea < kMinTriangleArea2) {
            ++tiny;
            smallest = std::min(smallest, twiceArea);
        }
    }
    if (tiny > 0)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": " + std::to_string(tiny) +
                         " of its triangles have an area below " +
                         shortNumber(kMinTriangleArea2 / 2) + " (the smallest " +
                         shortNumber(smallest / 2) +
                         "), too small for a float32 ray test ever to hit" + where);
    double smallestRadius = INFINITY;
    for (const Sphere& s : scene.spheres)
        smallestRadius = std::min(smallestRadius, double(s.radius));
    if (smallestRadius < kMinSphereRadius)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": a sphere radius of " +
                         shortNumber(smallestRadius) + " is below " +
                         shortNumber(kMinSphereRadius) + where + " or give a larger --radius");
}

Scene loadFileUnchecked(const std::string& path, const std::string& ext, const LoadOptions& opts) {
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

Scene loadFile(const std::string& path, const std::string& ext, const LoadOptions& opts) {
    Scene scene = loadFileUnchecked(path, ext, opts);
    checkSceneRange(scene);
    return scene;
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
