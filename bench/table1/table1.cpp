#include "bench/table1/table1.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/scene/load_scene.h"
#include "core/scene/scene_formats.h"

namespace oct {
namespace {

// Files of a mesh format of the scene format table (a .ply may also be a point cloud).
bool isMesh(const std::filesystem::path& p) {
    const SceneFormat* format = findSceneFormat(p.string());
    return format && format->mesh;
}

std::vector<std::string> meshesIn(const std::filesystem::path& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) return out;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.is_regular_file() && isMesh(e.path())) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

std::vector<std::string> table1Meshes(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw std::runtime_error("--meshes '" + dir +
                                 "' is not a directory: run from the repository root or pass "
                                 "--meshes PATH/TO/meshes");
    std::vector<std::string> out = meshesIn(dir);
    std::vector<std::string> cached = meshesIn(std::filesystem::path(dir) / "cache");
    out.insert(out.end(), cached.begin(), cached.end());
    return out;
}

Table1Row table1Row(const std::string& path, const BuildParams& params) {
    Scene scene = loadScene(path);
    Octree tree = buildOctree(scene, params);
    Table1Row r;
    r.name = std::filesystem::path(path).filename().string();
    r.path = path;
    r.vertices = scene.report.verticesRead;
    r.faces = scene.primitiveCount();
    r.octreeFaces = tree.referenceCount();
    r.depth = tree.depth;
    r.nodes = tree.nodes.size();
    r.buildSeconds = tree.buildSeconds;
    return r;
}

nlohmann::json toJson(const std::vector<Table1Row>& rows) {
    nlohmann::json a = nlohmann::json::array();
    for (const Table1Row& t : rows)
        a.push_back({{"name", t.name},
                     {"path", t.path},
                     {"vertices", t.vertices},
                     {"faces", t.faces},
                     {"octree_faces", t.octreeFaces},
                     {"depth", t.depth},
                     {"nodes", t.nodes},
                     {"build_seconds", t.buildSeconds}});
    return a;
}

std::string humanTable1(const std::vector<Table1Row>& rows) {
    char line[256];
    std::snprintf(line, sizeof line, "%-24s %10s %10s %13s %8s %6s %9s\n", "model", "vertices",
                  "faces", "octree faces", "ratio", "depth", "build s");
    std::string s = line;
    for (const Table1Row& t : rows) {
        std::snprintf(line, sizeof line, "%-24s %10llu %10llu %13llu %8.3f %6d %9.2f\n",
                      t.name.c_str(), (unsigned long long)t.vertices, (unsigned long long)t.faces,
                      (unsigned long long)t.octreeFaces,
                      t.faces ? double(t.octreeFaces) / double(t.faces) : 0.0, t.depth,
                      t.buildSeconds);
        s += line;
    }
    return s;
}

}  // namespace oct
