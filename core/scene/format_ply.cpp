// PLY (Greg Turk's polygon file format), ASCII and binary of either byte order: a triangle mesh,
// or a point cloud when it declares no faces. The header is parsed and the body walked here
// (ply_header.h, body_readers.h) before OpenMesh's reader runs; its counts are checked after.
// Plain ASCII files, such as the Stanford scans, are read by octrace's fast reader instead
// (ply_fast_reader.cpp), into the same RawMesh.
// A file OpenMesh would misread as it is (a byte-order mark, face lists beside vertex_indices,
// a face property before them) is handed to it as a rewritten copy that holds of each face only
// its vertex_indices; the copy is written by the same walk that checks the body.
#include <algorithm>
#include <fstream>
#include <sstream>
#include <utility>

#include "core/scene/body_readers.h"
#include "core/scene/loader_detail.h"
#include "core/scene/ply_header.h"

namespace oct::scene_detail {
namespace {

// A list's length as stored, sign and all.
int64_t plyListLength(const char* raw, PlyType type, bool bigEndian) {
    const size_t n = plyTypeBytes(type);
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i)
        v |= uint64_t(uint8_t(raw[bigEndian ? n - 1 - i : i])) << (8 * i);
    const bool isSigned = type == PlyType::Int8 || type == PlyType::Int16 || type == PlyType::Int32;
    if (isSigned && (v >> (8 * n - 1)) != 0) return int64_t(v) - (int64_t(1) << (8 * n));
    return int64_t(v);
}

// The copy OpenMesh reads of a file it would misread as it is (PlyHeader::rewriteForOpenMesh):
// every element as it is up to the faces, and of each face only its vertex_indices list.
bool keptInCopy(const PlyElement& e, const PlyProperty& p) {
    return e.name != "face" || p.read == PlyRead::Indices;
}

// Checks that the binary body holds every declared item and list, writing the copy to *copy.
void walkPlyBinary(const std::string& path, const PlyHeader& h, std::ostream* copy) {
    ByteReader body(path, h.dataStart);
    auto truncated = [&](const PlyElement& e, uint64_t i) {
        throw SceneError("cannot load " + inQuotes(path) + ": its binary body ends in " + e.name +
                         " " + std::to_string(i) + " of the " + std::to_string(e.count) +
                         " its header declares; the file is truncated");
    };
    auto pass = [&](uint64_t bytes, bool kept) {
        return copy && kept ? body.copy(bytes, *copy) : body.skip(bytes);
    };
    for (const PlyElement& e : h.elements) {
        const bool hasList =
            std::any_of(e.properties.begin(), e.properties.end(),
                        [](const PlyProperty& p) { return p.countType != PlyType::None; });
        if (!hasList) {  // not a face (a face has its index list): kept whole
            if (!pass(e.count * plyMinItemBytes(e), true)) truncated(e, 0);  // count fits: checked
        } else {
            char raw[4];
            for (uint64_t i = 0; i < e.count; ++i)
                for (const PlyProperty& p : e.properties) {
                    const bool kept = keptInCopy(e, p);
                    if (p.countType == PlyType::None) {
                        if (!pass(plyTypeBytes(p.type), kept)) truncated(e, i);
                        continue;
                    }
                    const size_t countBytes = plyTypeBytes(p.countType);
                    if (!body.read(raw, countBytes)) truncated(e, i);
                    const int64_t n = plyListLength(raw, p.countType, h.bigEndian);
                    if (n < 0)
                        throw SceneError("cannot load " + inQuotes(path) + ": " + e.name + " " +
                                         std::to_string(i) + " has a list of length " +
                                         std::to_string(n) + "; fix that face");
                    if (copy && kept) copy->write(raw, std::streamsize(countBytes));
                    if (!pass(uint64_t(n) * plyTypeBytes(p.type), kept)) truncated(e, i);
                }
        }
        if (e.name == "face") return;
    }
}

// Checks every value of the ASCII body as OpenMesh's reader will parse it, writing the copy
// (its kept tokens, one item a line) to *copy.
void walkPlyAscii(std::istream& in, const std::string& path, const PlyHeader& h,
                  std::ostream* copy) {
    AsciiBody body(
        in, h.headerLines, path,
        {"OpenMesh's ASCII PLY reader", " (it would silently misread the rest of the file)"});
    for (const PlyElement& e : h.elements) {
        for (uint64_t i = 0; i < e.count; ++i) {
            for (const PlyProperty& p : e.properties) {
                body.echoTo(keptInCopy(e, p) ? copy : nullptr);
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
                    case PlyRead::Other:  // values octrace does not use, but all of them
                        for (uint64_t n = body.count(), k = 0; k < n; ++k)
                            plyIsFloat(p.type) ? void(body.number()) : void(body.integer());
                        break;
                }
            }
            if (copy) *copy << '\n';
        }
        if (e.name == "face") return;  // OpenMesh stops reading after the faces
    }
}

// The header of the copy: without the byte-order mark, and without the declarations of the
// face properties the copy leaves out.
void writeCopyHeader(const std::string& path, const PlyHeader& h, std::ostream& copy) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    std::string text(size_t(h.dataStart), '\0');
    in.read(text.data(), std::streamsize(text.size()));
    for (auto e = h.elements.rbegin(); e != h.elements.rend(); ++e)
        for (auto p = e->properties.rbegin(); p != e->properties.rend(); ++p)
            if (!keptInCopy(*e, *p))
                text.erase(size_t(p->declarationStart),
                           size_t(p->declarationEnd - p->declarationStart));
    copy << text.substr(size_t(h.bomBytes));
}

// Every declared count against the file's bytes, before anything is read or sized from them.
ElementCounts checkPlyCounts(const std::string& path, const PlyHeader& h) {
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
    return counts;
}

// The reference path: the whole body walked and checked, then read by OpenMesh, from a
// rewritten copy (written by the same walk) when the header asks for one.
RawMesh readPlyWithOpenMesh(const std::string& path, const PlyHeader& h) {
    std::stringstream copy(std::ios::in | std::ios::out | std::ios::binary);
    std::ostream* out = h.rewriteForOpenMesh ? &copy : nullptr;
    if (out) writeCopyHeader(path, h, copy);
    if (h.ascii) {
        std::ifstream body = openOrThrow(path, std::ios::in | std::ios::binary);
        body.seekg(std::streamoff(h.dataStart));
        walkPlyAscii(body, path, h, out);
    } else {
        walkPlyBinary(path, h, out);
    }
    return out ? readWithOpenMesh(copy, "ply", path, "PLY") : readWithOpenMesh(path, "PLY");
}

Scene loadPlyWith(const std::string& path, const LoadOptions& opts, bool fastReader) {
    const PlyHeader header = parsePlyHeader(path);
    const ElementCounts declared = checkPlyCounts(path, header);
    RawMesh raw;
    if (!fastReader || !readPlyFast(path, header, raw)) raw = readPlyWithOpenMesh(path, header);
    checkDeclaredCounts(path, declared, raw);
    if (declared.faces > 0) return buildMeshScene(path, "ply", raw, Survey{});
    LoadReport report;
    report.format = "ply";
    report.verticesRead = raw.vertices.size();
    std::vector<Vec3> kept = finitePoints(raw.vertices, report);
    return sphereScene(path, kept, std::move(report), opts);
}

}  // namespace

// The fast reader takes the plain ASCII files it reads exactly as the reference path would
// (ply_fast_reader.cpp); everything else goes to that path.
Scene loadPly(const std::string& path, const LoadOptions& opts) {
    return loadPlyWith(path, opts, true);
}

Scene loadPlyWithOpenMesh(const std::string& path, const LoadOptions& opts) {
    return loadPlyWith(path, opts, false);
}

}  // namespace oct::scene_detail
