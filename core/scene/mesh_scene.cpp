// Triangle scenes from what a mesh reader handed over: indices resolved to file vertices,
// polygons fan-triangulated in face order, every unusable face dropped and counted
// (loader_detail.h).
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

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

}  // namespace

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
    // Room for every fan triangle at once (no regrowth and copy of the arrays); at most two a
    // face, so that a hostile face of millions of corners cannot make this the allocation
    // that fails.
    size_t fanTriangles = 0;
    for (size_t f = 0; f < raw.faceCount(); ++f)
        fanTriangles += std::max<size_t>(raw.faceStart[f + 1] - raw.faceStart[f], 2) - 2;
    reserveHuge(scene.triangles, std::min(fanTriangles, 2 * raw.faceCount()));
    reserveHuge(scene.sourceFace, scene.triangles.capacity());
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

bool isDegenerate(const Triangle& t) {
    double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y, az = double(t.v1.z) - t.v0.z;
    double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y, bz = double(t.v2.z) - t.v0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

}  // namespace oct::scene_detail
