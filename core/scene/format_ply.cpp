// PLY (Greg Turk's polygon file format), ASCII and binary of either byte order: a triangle mesh,
// or a point cloud when it declares no faces. The header is parsed and the body walked here
// (ply_header.h, body_readers.h) before OpenMesh's reader runs; its counts are checked after.
#include <algorithm>
#include <fstream>
#include <utility>

#include "core/scene/body_readers.h"
#include "core/scene/loader_detail.h"
#include "core/scene/ply_header.h"

namespace oct::scene_detail {
namespace {

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
    AsciiBody body(
        in, h.headerLines, path,
        {"OpenMesh's ASCII PLY reader", " (it would silently misread the rest of the file)"});
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
    const PlyHeader h = parsePlyHeader(path);
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
    if (h.ascii) {
        std::ifstream body = openOrThrow(path, std::ios::in | std::ios::binary);
        body.seekg(std::streamoff(h.dataStart));
        walkPlyAscii(body, path, h);
    } else {
        walkPlyBinary(path, h);
    }
    return counts;
}

}  // namespace

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

}  // namespace oct::scene_detail
