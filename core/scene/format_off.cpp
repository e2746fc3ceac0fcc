// OFF (Geomview's Object File Format), ASCII and binary: a polygon mesh. The first line is
// parsed and the body walked here (body_readers.h) before OpenMesh's reader runs; its counts
// are checked after.
#include <algorithm>
#include <fstream>

#include "core/scene/body_readers.h"
#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

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

}  // namespace

Scene loadOff(const std::string& path, const LoadOptions&) {
    const ElementCounts declared = readOffHeader(path);
    RawMesh raw = readWithOpenMesh(path, "OFF");
    checkDeclaredCounts(path, declared, raw);
    return buildMeshScene(path, "off", raw, Survey{});
}

}  // namespace oct::scene_detail
