#include "validation/report/scene_info.h"

#include <map>

#include "core/octree/layout_registry.h"
#include "core/scene/mesh_topology.h"

namespace oct {
namespace {

nlohmann::json loadJson(const Scene& s) {
    const LoadReport& r = s.report;
    return {{"format", r.format},
            {"vertices_read", r.verticesRead},
            {"faces_read", r.facesRead},
            {"polygons_triangulated", r.polygonsTriangulated},
            {"dropped",
             {{"invalid_index", r.droppedInvalidIndex},
              {"non_finite", r.droppedNonFinite},
              {"degenerate", r.droppedDegenerate},
              {"too_few_vertices", r.droppedTooFewVertices},
              {"total", r.totalDropped()}}}};
}

nlohmann::json treeJson(const Octree& t) {
    std::map<std::string, uint64_t> byType;
    std::vector<std::map<std::string, uint64_t>> byDepth(t.depth + 1);
    const char* names[] = {"internal", "leaf", "empty_leaf", "invalid"};
    for (const OctreeNode& n : t.nodes) {
        ++byType[names[n.type]];
        ++byDepth[n.depth][names[n.type]];
    }
    nlohmann::json depth = nlohmann::json::array();
    for (int d = 0; d <= t.depth; ++d) depth.push_back(byDepth[d]);
    return {{"max_depth", t.params.maxDepth},
            {"effective_max_depth", t.effectiveMaxDepth},
            {"max_prims", t.params.maxPrims},
            {"depth", t.depth},
            {"root",
             {{"lo", {t.root.lo.x, t.root.lo.y, t.root.lo.z}},
              {"hi", {t.root.hi.x, t.root.hi.y, t.root.hi.z}}}},
            {"nodes", t.nodes.size()},
            {"nodes_by_type", byType},
            {"nodes_by_depth", depth},
            {"octree_faces", t.referenceCount()},
            {"build_seconds", t.buildSeconds}};
}

// Every layout of the registry over the canonical octree: its facts under its name, and its
// one-line summary for the text form.
nlohmann::json layoutsJson(const Scene& scene, const Octree& t, const LayoutOptions& lo,
                           std::vector<std::pair<std::string, std::string>>& lines) {
    nlohmann::json j;
    for (const LayoutDesc& d : layouts()) {
        LayoutReport r = d.report(scene, t, lo);
        nlohmann::json facts = nlohmann::json::object();
        for (const LayoutFact& f : r.facts) {
            if (f.integer)
                facts[f.key] = f.count;
            else
                facts[f.key] = f.value;
        }
        j[d.name] = facts;
        lines.emplace_back(d.name, r.summary);
    }
    j["leaf_index_bytes"] = t.primIndices.size() * sizeof(uint32_t);
    j["node_record_bytes"] = sizeof(OctreeNode);
    return j;
}

}  // namespace

nlohmann::json sceneInfo(const Scene& scene, const LayoutOptions& lo,
                         std::vector<std::pair<std::string, std::string>>* layoutLines) {
    Octree tree = buildOctree(scene, lo.build);
    bool tris = scene.kind == PrimKind::Triangles;
    nlohmann::json j;
    j["format"] = "octrace-info-report";  // the schema, so a reader can refuse one it does not know
    j["version"] = 1;
    j["scene"] = {{"name", scene.name},
                  {"kind", primKindName(scene.kind)},
                  {"primitives", scene.primitiveCount()},
                  {"primitive_bytes",
                   uint64_t(scene.primitiveCount()) * (tris ? sizeof(Triangle) : sizeof(Sphere))}};
    if (!tris && !scene.spheres.empty()) j["scene"]["radius"] = scene.spheres[0].radius;
    j["load"] = loadJson(scene);
    j["topology"] = nullptr;  // closed: every edge in exactly two triangles (mesh_topology.h)
    if (tris) {
        MeshTopology t = meshTopology(scene);
        j["topology"] = {{"closed", t.closed()},
                         {"vertices", t.vertices.size()},
                         {"edges", t.edges.size()},
                         {"boundary_edges", t.boundaryEdges},
                         {"non_manifold_edges", t.nonManifoldEdges}};
    }
    j["octree"] = treeJson(tree);
    std::vector<std::pair<std::string, std::string>> lines;
    j["layouts"] = layoutsJson(scene, tree, lo, lines);
    if (layoutLines) *layoutLines = std::move(lines);
    return j;
}

}  // namespace oct
