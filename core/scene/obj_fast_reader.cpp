// The fast OBJ reader (loader_detail.h, readObjFast): the whole file parsed once, in
// line-aligned chunks on all cores, into exactly the RawMesh and Survey that the reference
// path (surveyObj, then OpenMesh's OBJ reader; format_obj.cpp) produces for the same file.
//
// It takes the part of the format real meshes use: "v x y z" with plain decimal numbers,
// "f" lines whose corners are "v", "v/vt", "v//vn" or "v/vt/vn" with an integer vertex index
// (negative = relative to the "v" lines so far, as Wavefront's OBJ specification says), "vt"
// lines with two plain numbers, "mtllib" (its file checked as before), comments, blank and
// CRLF lines, a UTF-8 byte-order mark, and every other statement ignored, as OpenMesh ignores
// it. Anything else (a line continued with '\', a coordinate that is not a plain finite float,
// a corner that is not an integer, an index beyond int) makes it return false, and the file
// goes to the reference path, which reads such input the way docs/ROBUSTNESS.md describes.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/scene/loader_detail.h"
#include "core/scene/text_chunks.h"

namespace oct::scene_detail {
namespace {

// What one chunk's lines hold, before the "v" lines of earlier chunks are known.
struct ObjChunk {
    bool plain = true;  // every line is in the part of the format this reader takes
    std::vector<Vec3> vertices;
    std::vector<int> corners;                    // vertex indices as written in the file
    std::vector<size_t> faceStart = {0};         // face f is corners[faceStart[f], faceStart[f+1])
    std::vector<size_t> verticesBefore;          // per face: this chunk's "v" lines above it
    std::vector<std::string> materialLibraries;  // "mtllib" names, in order
    // Filled once the chunk's place in the file is known (resolve()):
    std::vector<int> handedIndices;       // the handed-over faces' indices, OpenMesh's order
    std::vector<uint32_t> handedSizes;    // their corner counts
    std::vector<uint32_t> handedFaces;    // their file face numbers
    uint64_t tooFew = 0, degenerate = 0;  // faces OpenMesh's reader skips
};

// One line [p, end) without its '\n'; false when it is outside the part this reader takes.
bool parseLine(const char* p, const char* end, ObjChunk& c) {
    while (p < end && isTrimmed(*p)) ++p;
    const char* last = end;
    while (last > p && isTrimmed(last[-1])) --last;
    if (p == last || *p == '#') return true;  // blank, or a comment (never continued)
    if (last[-1] == '\\') return false;       // a continued statement: the reference path joins
    // '\v' or '\f' first: OpenMesh skips the line while the survey reads it; the reference
    // path settles that disagreement (VertexResolver).
    if (isBlank(*p)) return false;
    const std::string_view keyword = nextToken(p, last);
    if (keyword == "v") {
        float xyz[3];
        for (float& x : xyz)
            if (!plainFloat(nextToken(p, last), x)) return false;
        c.vertices.push_back({xyz[0], xyz[1], xyz[2]});
    } else if (keyword == "f") {
        c.verticesBefore.push_back(c.vertices.size());
        for (std::string_view corner = nextToken(p, last); !corner.empty();
             corner = nextToken(p, last)) {
            // OpenMesh reads a corner's first component as the vertex; with default options
            // it reads texture and normal indices without using them.
            int index = 0;
            if (!plainInt(corner.substr(0, corner.find('/')), index)) return false;
            c.corners.push_back(index);
        }
        c.faceStart.push_back(c.corners.size());
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vc") {
        // Unused here, but OpenMesh's reader fails the whole file on a "vt" line it cannot
        // parse: such lines, and the other attributes' for safety, go to the reference path.
        float value;
        for (int i = keyword == "vt" ? 2 : 3; i > 0; --i)
            if (!plainFloat(nextToken(p, last), value)) return false;
    } else if (keyword == "mtllib") {
        std::string name(p, last);  // the rest of the line, as getline after the keyword
        trimLine(name);
        c.materialLibraries.push_back(name);
    }
    return true;
}

void parseChunk(std::string_view text, ObjChunk& c) {
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end && c.plain) {
        const char* eol = static_cast<const char*>(memchr(p, '\n', size_t(end - p)));
        if (!eol) eol = end;
        c.plain = parseLine(p, eol, c);
        p = eol + 1;
    }
}

// The faces of chunk c as OpenMesh's reader hands them over, and the survey's count of the
// ones it skips (surveyObjFace): an index resolved against the "v" lines above it, repeated
// vertices removed keeping the first, fewer than 3 left and the face is skipped.
void resolve(ObjChunk& c, int64_t verticesAbove, uint32_t firstFace) {
    std::vector<int> face;
    for (size_t f = 0; f + 1 < c.faceStart.size(); ++f) {
        face.clear();
        const int64_t before = verticesAbove + int64_t(c.verticesBefore[f]);
        for (size_t k = c.faceStart[f]; k < c.faceStart[f + 1]; ++k) {
            const int v = c.corners[k];
            // OpenMesh: value = nCurrentPositions + value + 1, then the handle value - 1.
            const int index = int(v < 0 ? before + v : int64_t(v) - 1);
            if (std::find(face.begin(), face.end(), index) == face.end()) face.push_back(index);
        }
        const size_t listed = c.faceStart[f + 1] - c.faceStart[f];
        if (face.size() > 2) {
            c.handedIndices.insert(c.handedIndices.end(), face.begin(), face.end());
            c.handedSizes.push_back(uint32_t(face.size()));
            c.handedFaces.push_back(firstFace + uint32_t(f));
        } else if (listed < 3) {
            ++c.tooFew;
        } else {
            ++c.degenerate;
        }
    }
    c.corners = {};
}

}  // namespace

bool readObjFast(const std::string& path, RawMesh& raw, Survey& survey,
                 std::vector<std::string>& materialLibraries) {
    const FileText file(path);
    const std::string_view text = file.text();
    const size_t bom = text.substr(0, 3) == kUtf8Bom ? 3 : 0;
    const auto ranges = lineAlignedChunks(text, bom);
    std::vector<ObjChunk> chunks(ranges.size());
    forEachChunk(chunks.size(), [&](size_t i) {
        parseChunk(text.substr(ranges[i].first, ranges[i].second - ranges[i].first), chunks[i]);
    });
    // Where each chunk's items go: after those of the chunks before it.
    struct Place {
        uint64_t vertices = 0, faces = 0, handed = 0, indices = 0;
    };
    std::vector<Place> place(chunks.size() + 1);
    for (size_t i = 0; i < chunks.size(); ++i) {
        if (!chunks[i].plain) return false;
        place[i + 1].vertices = place[i].vertices + chunks[i].vertices.size();
        place[i + 1].faces = place[i].faces + chunks[i].faceStart.size() - 1;
    }
    // Indices and face numbers are ints and 32-bit ids on both paths; leave such giants to it.
    if (place.back().vertices >= uint64_t(INT32_MAX) / 2 ||
        place.back().faces >= uint64_t(UINT32_MAX) / 2)
        return false;
    forEachChunk(chunks.size(), [&](size_t i) {
        resolve(chunks[i], int64_t(place[i].vertices), uint32_t(place[i].faces));
    });
    for (size_t i = 0; i < chunks.size(); ++i) {
        place[i + 1].handed = place[i].handed + chunks[i].handedFaces.size();
        place[i + 1].indices = place[i].indices + chunks[i].handedIndices.size();
    }

    raw = RawMesh();
    survey = Survey();
    survey.isObj = survey.surveyed = true;
    survey.facesInFile = place.back().faces;
    survey.vertexLineOk.assign(place.back().vertices, true);
    survey.handedOver.resize(place.back().handed);
    survey.lostCorner.assign(place.back().handed, false);
    raw.vertices.resize(place.back().vertices);
    raw.faceIndices.resize(place.back().indices);
    raw.faceStart.resize(place.back().handed + 1);
    forEachChunk(chunks.size(), [&](size_t i) {
        const ObjChunk& c = chunks[i];
        const Place& at = place[i];
        std::copy(c.vertices.begin(), c.vertices.end(), raw.vertices.begin() + at.vertices);
        std::copy(c.handedIndices.begin(), c.handedIndices.end(),
                  raw.faceIndices.begin() + at.indices);
        std::copy(c.handedFaces.begin(), c.handedFaces.end(),
                  survey.handedOver.begin() + at.handed);
        size_t end = at.indices;
        for (size_t f = 0; f < c.handedSizes.size(); ++f)
            raw.faceStart[at.handed + f + 1] = end += c.handedSizes[f];
    });
    for (const ObjChunk& c : chunks) {
        survey.skippedTooFew += c.tooFew;
        survey.skippedDegenerate += c.degenerate;
        materialLibraries.insert(materialLibraries.end(), c.materialLibraries.begin(),
                                 c.materialLibraries.end());
    }
    return true;
}

}  // namespace oct::scene_detail
