// octrace info: what loading kept and dropped, the octree's shape, and each layout's bytes.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "core/io/output_file.h"
#include "core/scene/load_scene.h"
#include "validation/report/scene_info.h"

namespace oct {
namespace {

struct InfoOptions {
    SceneOptions scene;
    std::string json;  // file, or "-" for stdout; empty: text on stdout
};

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
    std::vector<std::pair<std::string, std::string>> layoutLines;
    const nlohmann::json j = sceneInfo(scene, o.scene.layoutOptions(), &layoutLines);
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
