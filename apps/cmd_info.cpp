// octrace info: what loading kept and dropped, the octree's shape, and each layout's bytes.
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "core/io/output_file.h"
#include "core/scene/load_scene.h"
#include "core/scene/mesh_topology.h"

namespace oct {
namespace {

struct InfoOptions {
    SceneOptions scene;
    std::string json;  // file, or "-" for stdout; empty: text on stdout
};

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

void printHuman(const nlohmann::json& j,
                const std::vector<std::pair<std::string, std::string>>& layoutLines) {
    const auto& s = j["scene"];
    const auto& l = j["load"];
    const auto& t = j["octree"];
    std::printf("scene        %s\n", s["name"].get<std::string>().c_str());
    std::printf("primitives   %llu %s (format %s, %llu vertices, %llu faces read)\n",
                (unsigned long long)s["primitives"], s["kind"].get<std::string>().c_str(),
                l["format"].get<std::string>().c_str(), (unsigned long long)l["vertices_read"],
                (unsigned long long)l["faces_read"]);
    const auto& d = l["dropped"];
    std::printf(
        "dropped      %llu (invalid index %llu, non-finite %llu, degenerate %llu, "
        "<3 vertices %llu); polygons triangulated %llu\n",
        (unsigned long long)d["total"], (unsigned long long)d["invalid_index"],
        (unsigned long long)d["non_finite"], (unsigned long long)d["degenerate"],
        (unsigned long long)d["too_few_vertices"], (unsigned long long)l["polygons_triangulated"]);
    if (j.contains("topology") && !j["topology"].is_null()) {
        const auto& tp = j["topology"];
        std::printf(
            "closed       %s (%llu boundary edges, %llu non-manifold edges; vertices "
            "welded by position)\n",
            tp["closed"].get<bool>() ? "yes" : "no", (unsigned long long)tp["boundary_edges"],
            (unsigned long long)tp["non_manifold_edges"]);
    }
    std::printf("octree       depth %d (max %d, max-prims %u), %llu nodes, built in %.3f s\n",
                t["depth"].get<int>(), t["effective_max_depth"].get<int>(),
                t["max_prims"].get<unsigned>(), (unsigned long long)t["nodes"],
                t["build_seconds"].get<double>());
    std::printf("  by type    ");
    for (auto& [k, v] : t["nodes_by_type"].items())
        std::printf("%s %llu  ", k.c_str(), (unsigned long long)v);
    std::printf("\n  by depth   depth: internal/leaf/empty\n");
    int depth = 0;
    for (const auto& lvl : t["nodes_by_depth"]) {
        std::printf("             %2d: %llu/%llu/%llu\n", depth++,
                    (unsigned long long)lvl.value("internal", 0ull),
                    (unsigned long long)lvl.value("leaf", 0ull),
                    (unsigned long long)lvl.value("empty_leaf", 0ull));
    }
    std::printf(
        "octree faces %llu (primitive references in leaves; %.2f per primitive)\n",
        (unsigned long long)t["octree_faces"],
        double(t["octree_faces"].get<uint64_t>()) / double(s["primitives"].get<uint64_t>()));
    for (const auto& [name, summary] : layoutLines)
        std::printf("%-12s %s\n", name.c_str(), summary.c_str());
}

void runInfo(const InfoOptions& o) {
    if (!o.json.empty() && o.json != "-") checkOutputPaths({o.json}, {o.scene.path});
    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    LayoutOptions lo = o.scene.layoutOptions();
    Octree tree = buildOctree(scene, lo.build);
    bool tris = scene.kind == PrimKind::Triangles;
    nlohmann::json j;
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
    std::vector<std::pair<std::string, std::string>> layoutLines;
    j["layouts"] = layoutsJson(scene, tree, lo, layoutLines);
    if (o.json.empty())
        printHuman(j, layoutLines);
    else
        writeTextOutput(o.json, j.dump(2) + "\n");
}

}  // namespace

void registerInfo(CLI::App& app) {
    auto opts = std::make_shared<InfoOptions>();
    CLI::App* cmd = app.add_subcommand(
        "info", "Load a scene, build its octree and report nodes, octree faces and layout bytes");
    addSceneOptions(*cmd, opts->scene);
    addJsonOption(*cmd, opts->json, "the report (instead of text on stdout)");
    cmd->callback([opts] { runInfo(*opts); });
}

}  // namespace oct
