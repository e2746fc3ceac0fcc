// OFF (Geomview's Object File Format, in its OOGL file formats), ASCII and binary: a polygon
// mesh. Read here, not by OpenMesh's OFF reader, which takes the counts only from the line
// after the keyword (with "OFF 4 1 0" it reads the first vertex as the counts), knows no '#'
// comments, reads a face's colour only with the C prefix (which declares vertex colours) and
// otherwise takes it for the next face, and whose binary mode is state its file check left
// behind. Every value is checked as it is read (body_readers.h) and every count against the
// file's bytes first.
//
// ASCII: the keyword line "[ST][C][N]OFF", optionally followed by the counts; "NV NF NE"; NV
// vertex lines "x y z" (then a normal with N, and colours and texture coordinates, ignored);
// NF faces "n i0 .. i(n-1)" each optionally followed, to the end of its line, by a colour: a
// colour-map index, or 3 or 4 RGB(A) components (ignored). '#' starts a comment that runs to
// the end of the line; blank lines and a UTF-8 byte-order mark are skipped.
#include <algorithm>
#include <climits>
#include <fstream>
#include <vector>

#include "core/scene/body_readers.h"
#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

// Header "[ST][C][N][4][n]OFF[ BINARY]", accepted as OpenMesh's OFF reader accepts it: the
// prefixes in this order, "OFF", then "BINARY" exactly one character after it. ST adds texture
// coordinates and C colours to the rest of each vertex line (ASCII) or 8 and 12 bytes to each
// vertex (binary); N adds a normal after each vertex; 4 and n (other dimensions) are refused.
struct OffHeader {
    bool binary = false;
    bool texCoords = false, colours = false, normals = false;
    size_t keywordEnd = 0;  // where the line goes on after "OFF" (an ASCII file's counts may)
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
    h.keywordEnd = p + 3;
    const size_t rest = n - p >= 4 ? n - p - 4 : 0;
    h.binary = rest >= 6 && line.compare(p + 4, 6, "BINARY") == 0;
    return h;
}

// An index as RawMesh holds it: negative for one that names no vertex of an int-sized mesh.
int vertexIndex(long long value) { return value < 0 || value > INT_MAX ? -1 : int(value); }

// What may follow a face's indices on its line: nothing, or a colour of 1, 3 or 4 numbers.
void checkFaceColour(AsciiBody& body, const std::string& path, uint64_t face, uint64_t corners) {
    const std::vector<std::string> rest = body.restOfLine();
    bool numbers = true;
    std::string shown;
    for (const std::string& token : rest) {
        numbers = numbers && token.find_first_not_of("0123456789+-.eE") == std::string::npos;
        shown += (shown.empty() ? "" : " ") + token;
    }
    if (numbers && (rest.size() == 0 || rest.size() == 1 || rest.size() == 3 || rest.size() == 4))
        return;
    if (shown.size() > 40) shown = shown.substr(0, 40) + "...";
    throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(body.lineNo()) +
                     " ends face " + std::to_string(face) + " (" + std::to_string(corners) +
                     " vertex indices) with " + inQuotes(shown) +
                     ", which is not a colour (1 colour-map index, or 3 or 4 RGB(A) numbers); "
                     "check that face's vertex count");
}

void readOffAscii(AsciiBody& body, const std::string& path, const OffHeader& h,
                  const ElementCounts& counts, RawMesh& raw) {
    raw.vertices.reserve(counts.vertices);
    for (uint64_t v = 0; v < counts.vertices; ++v) {
        Vec3 p;
        p.x = body.number();
        p.y = body.number();
        p.z = body.number();
        raw.vertices.push_back(p);
        if (h.normals)
            for (int k = 0; k < 3; ++k) body.number();
        body.skipRestOfLine();  // colours and texture coordinates
    }
    for (uint64_t f = 0; f < counts.faces; ++f) {
        const uint64_t n = body.count();
        for (uint64_t k = 0; k < n; ++k) raw.faceIndices.push_back(vertexIndex(body.integer()));
        raw.faceStart.push_back(raw.faceIndices.size());
        checkFaceColour(body, path, f, n);
    }
}

// Binary OFF: little-endian uint32 counts nV nF nE, vertices of 3 floats (+ 3 for N, + 3
// int32 colours for C, + 2 floats for ST), then faces as a uint32 length and as many uint32
// indices.
void readOffBinary(const std::string& path, uint64_t start, const OffHeader& h, RawMesh& raw) {
    ByteReader body(path, start);
    uint32_t header[3];
    if (!body.read(header, sizeof header))
        throw SceneError("cannot load " + inQuotes(path) +
                         ": its binary header ends before the 3 counts; the file is truncated");
    const uint64_t vertices = header[0], faces = header[1];
    const uint64_t vertexBytes =
        12 + (h.normals ? 12 : 0) + (h.colours ? 12 : 0) + (h.texCoords ? 8 : 0);
    const uint64_t size = fileSize(path);
    uint64_t available = size - std::min(size, body.position());
    checkCountFits(path, vertices, "vertices", available, vertexBytes);
    checkCountFits(path, faces, "faces", available, 4);
    raw.vertices.resize(vertices);
    for (Vec3& p : raw.vertices) {
        body.read(&p, 12);  // the counts fit: checked above
        body.skip(vertexBytes - 12);
    }
    auto truncated = [&](uint64_t f) {
        throw SceneError("cannot load " + inQuotes(path) + ": its binary body ends in face " +
                         std::to_string(f) + " of the " + std::to_string(faces) +
                         " its header declares; the file is truncated");
    };
    for (uint64_t f = 0; f < faces; ++f) {
        uint32_t n = 0;
        if (!body.read(&n, 4) || uint64_t(n) * 4 > size - std::min(size, body.position()))
            truncated(f);
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t index = 0;
            if (!body.read(&index, 4)) truncated(f);
            raw.faceIndices.push_back(vertexIndex(index));
        }
        raw.faceStart.push_back(raw.faceIndices.size());
    }
}

RawMesh readOff(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    std::string first;
    std::getline(in, first);
    const uint64_t lineBytes = first.size() + 1;
    stripUtf8Bom(first);
    const OffHeader h = parseOffFirstLine(path, first);
    RawMesh raw;
    if (h.binary) {
        readOffBinary(path, lineBytes, h, raw);
        return raw;
    }
    AsciiBody body(in, 1, path, {"an OFF file", "", true});
    body.setRestOfLine(first.substr(h.keywordEnd));
    ElementCounts counts;
    counts.vertices = body.count();
    counts.faces = body.count();
    body.integer();  // edge count, unused
    // Each vertex takes at least "0 0 0\n", each face "0\n".
    const uint64_t size = fileSize(path);
    uint64_t available = size - std::min(size, lineBytes);
    checkCountFits(path, counts.vertices, "vertices", available, 6);
    checkCountFits(path, counts.faces, "faces", available, 2);
    readOffAscii(body, path, h, counts, raw);
    return raw;
}

}  // namespace

Scene loadOff(const std::string& path, const LoadOptions&) {
    return buildMeshScene(path, "off", readOff(path), Survey{});
}

}  // namespace oct::scene_detail
