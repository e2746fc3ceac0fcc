#include "validation/table1.h"

#include <algorithm>
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

}  // namespace oct
