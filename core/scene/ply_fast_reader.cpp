// The fast ASCII PLY reader (loader_detail.h, readPlyFast): the body parsed once, in
// line-aligned chunks on all cores, into exactly the RawMesh that the reference path (the body
// walk of format_ply.cpp, then OpenMesh's ASCII PLY reader) produces for the same file.
//
// It takes the layout scanners and writers use (Greg Turk's PLY format, as in the Stanford
// models and Blender's files): "element vertex" with scalar properties (x, y, z and others such
// as normals and texture coordinates), then "element face" with only its vertex_indices list,
// each vertex and each face on a line of its own, plain decimal coordinates within float's
// range and indices of existing vertices, at least 3 a face. OpenMesh reads those values with
// `>> float` and `>> int` and hands every face over as listed, which is what this reader
// records. Any other header or line (binary bodies, other
// properties, a value split over lines, a comment, a bad or missing value) makes it return
// false, and the reference path reads, or refuses, the file as docs/ROBUSTNESS.md describes.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene/loader_detail.h"
#include "core/scene/ply_header.h"
#include "core/scene/text_chunks.h"

namespace oct::scene_detail {
namespace {

// One chunk of the body; its vertices and face sizes go straight to their places in the
// RawMesh (a line's number says which item it is), its indices to `indices` until the chunks
// before it are counted.
struct PlyChunk {
    bool plain = true;
    uint64_t firstLine = 0;  // the body line the chunk starts with
    std::vector<int> indices;
};

uint64_t countLines(std::string_view text) {
    if (text.empty()) return 0;
    return uint64_t(std::count(text.begin(), text.end(), '\n')) + (text.back() != '\n');
}

// How each vertex property is read, and which of them are x, y and z.
struct VertexLayout {
    std::vector<PlyRead> reads;
    size_t xyz[3] = {0, 0, 0};
};

// A vertex line: exactly one value a property, each of the kind the reference walk accepts
// there: a plain float where `>> float` reads (the walk refuses a value beyond FLT_MAX in
// double, which from_chars may still round to FLT_MAX: such files go to that path), an int
// where `>> int` reads (integer colours), any word where OpenMesh skips one.
bool parseVertex(const char* p, const char* end, const VertexLayout& layout, Vec3& v) {
    float values[64];
    for (size_t k = 0; k < layout.reads.size(); ++k) {
        const std::string_view token = nextToken(p, end);
        int i = 0;
        switch (layout.reads[k]) {
            case PlyRead::Float:
                if (!plainFloat(token, values[k]) || std::fabs(values[k]) == FLT_MAX) return false;
                break;
            case PlyRead::Int:
                if (!plainInt(token, i)) return false;
                break;
            default:
                if (token.empty()) return false;
        }
    }
    v = {values[layout.xyz[0]], values[layout.xyz[1]], values[layout.xyz[2]]};
    return nextToken(p, end).empty();
}

// A face line: a count of at least 3, then that many indices of existing vertices.
bool parseFace(const char* p, const char* end, uint64_t vertexCount, size_t& size,
               std::vector<int>& indices) {
    int n = 0;
    if (!plainInt(nextToken(p, end), n) || n < 3) return false;
    for (int k = 0; k < n; ++k) {
        int index = 0;
        if (!plainInt(nextToken(p, end), index) || index < 0 || uint64_t(index) >= vertexCount)
            return false;
        indices.push_back(index);
    }
    size = size_t(n);
    return nextToken(p, end).empty();
}

// Fills raw.vertices[line] and, for face f, raw.faceStart[f + 1] with its size.
void parseChunk(std::string_view text, const VertexLayout& layout, uint64_t vertexCount,
                uint64_t faceCount, PlyChunk& c, RawMesh& raw) {
    const char* p = text.data();
    const char* end = p + text.size();
    for (uint64_t line = c.firstLine; p < end && c.plain && line < vertexCount + faceCount;
         ++line) {
        const char* eol = static_cast<const char*>(memchr(p, '\n', size_t(end - p)));
        if (!eol) eol = end;
        c.plain = line < vertexCount ? parseVertex(p, eol, layout, raw.vertices[line])
                                     : parseFace(p, eol, vertexCount,
                                                 raw.faceStart[line - vertexCount + 1], c.indices);
        p = eol + 1;
    }
}

// The layouts this reader takes: "element vertex" with scalar properties only (x, y and z
// among them, as the header parser requires), then "element face" with only vertex_indices.
bool plainLayout(const PlyHeader& h, VertexLayout& layout) {
    if (!h.ascii || h.rewriteForOpenMesh || h.elements.size() < 2) return false;
    const PlyElement& vertex = h.elements[0];
    const PlyElement& face = h.elements[1];
    if (vertex.name != "vertex" || face.name != "face" || vertex.properties.size() > 64 ||
        face.properties.size() != 1 || face.properties[0].read != PlyRead::Indices)
        return false;
    int found = 0;
    for (size_t k = 0; k < vertex.properties.size(); ++k) {
        const PlyProperty& p = vertex.properties[k];
        if (p.countType != PlyType::None) return false;
        layout.reads.push_back(p.read);
        for (size_t axis = 0; axis < 3; ++axis)
            if (p.name == std::string(1, char('x' + axis))) {
                if (p.read != PlyRead::Float) return false;
                layout.xyz[axis] = k;
                ++found;
            }
    }
    // Indices and face sizes are ints on both paths; leave such giants to the reference one.
    return found == 3 && vertex.count < uint64_t(INT32_MAX) &&
           face.count < uint64_t(UINT32_MAX) / 2;
}

}  // namespace

bool readPlyFast(const std::string& path, const PlyHeader& h, RawMesh& raw) {
    VertexLayout layout;
    if (!plainLayout(h, layout)) return false;
    const uint64_t vertexCount = h.elements[0].count, faceCount = h.elements[1].count;
    const FileText file(path);
    const std::string_view text = file.text();
    if (h.dataStart > text.size() || (h.dataStart > 0 && text[h.dataStart - 1] != '\n'))
        return false;
    const auto ranges = lineAlignedChunks(text, size_t(h.dataStart));
    auto chunkText = [&](size_t i) {
        return text.substr(ranges[i].first, ranges[i].second - ranges[i].first);
    };
    std::vector<PlyChunk> chunks(ranges.size());
    std::vector<uint64_t> lines(ranges.size());
    forEachChunk(chunks.size(), [&](size_t i) { lines[i] = countLines(chunkText(i)); });
    uint64_t total = 0;
    for (size_t i = 0; i < chunks.size(); ++i) {
        chunks[i].firstLine = total;
        total += lines[i];
    }
    if (total < vertexCount + faceCount) return false;  // truncated: the reference refuses it
    raw = RawMesh();
    reserveHuge(raw.vertices, vertexCount);
    raw.vertices.resize(vertexCount);
    reserveHuge(raw.faceStart, faceCount + 1);
    raw.faceStart.assign(faceCount + 1, 0);
    for (size_t i = 0; i < chunks.size(); ++i) {  // room for triangles; quads grow it
        const uint64_t first = std::max(chunks[i].firstLine, vertexCount);
        const uint64_t last = std::min(chunks[i].firstLine + lines[i], vertexCount + faceCount);
        if (last > first) reserveHuge(chunks[i].indices, size_t(3 * (last - first)));
    }
    forEachChunk(chunks.size(), [&](size_t i) {
        parseChunk(chunkText(i), layout, vertexCount, faceCount, chunks[i], raw);
    });
    std::vector<size_t> indicesBefore(chunks.size() + 1, 0);
    for (size_t i = 0; i < chunks.size(); ++i) {
        if (!chunks[i].plain) return false;
        indicesBefore[i + 1] = indicesBefore[i] + chunks[i].indices.size();
    }
    for (size_t f = 0; f < faceCount; ++f) raw.faceStart[f + 1] += raw.faceStart[f];
    reserveHuge(raw.faceIndices, indicesBefore.back());
    raw.faceIndices.resize(indicesBefore.back());
    forEachChunk(chunks.size(), [&](size_t i) {
        std::copy(chunks[i].indices.begin(), chunks[i].indices.end(),
                  raw.faceIndices.begin() + std::ptrdiff_t(indicesBefore[i]));
    });
    return raw.faceStart.back() == raw.faceIndices.size();
}

}  // namespace oct::scene_detail
