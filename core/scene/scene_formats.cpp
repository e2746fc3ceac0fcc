// The table of scene formats (scene_formats.h).
#include "core/scene/scene_formats.h"

#include "core/scene/loader_detail.h"
#include "core/scene/scene_generators.h"

namespace oct {

const std::vector<SceneFormat>& sceneFormats() {
    using namespace scene_detail;
    static const std::vector<SceneFormat> kFormats = {
        {"obj", "Wavefront OBJ mesh", true, false, loadObj},
        {"ply", "PLY mesh, or point cloud without faces", true, true, loadPly},
        {"off", "OFF mesh", true, false, loadOff},
        {"stl", "STL mesh", true, false, loadStl},
        {"xyz", "point cloud, x y z per line", false, true, loadXyz},
    };
    return kFormats;
}

const SceneFormat* findSceneFormat(const std::string& path) {
    const std::string ext = scene_detail::lowerExtension(path);
    for (const SceneFormat& f : sceneFormats())
        if (ext == f.extension) return &f;
    return nullptr;
}

std::string sceneExtensionList(const std::string& lastJoin) {
    std::vector<std::string> extensions;
    for (const SceneFormat& f : sceneFormats())
        extensions.push_back(std::string(".") + f.extension);
    return scene_detail::joinList(extensions, lastJoin);
}

std::string sceneFormatsHelp() {
    std::string out = "Scene file:";
    for (const SceneFormat& f : sceneFormats())
        out += std::string(" .") + f.extension + " (" + f.description + "),";
    out += " or a generated scene:";
    const std::vector<SceneGenerator>& gens = sceneGenerators();
    for (size_t i = 0; i < gens.size(); ++i)
        out += std::string(" ") + gens[i].usage + " (" + gens[i].description + ")" +
               (i + 1 < gens.size() ? "," : "");
    return out;
}

}  // namespace oct
