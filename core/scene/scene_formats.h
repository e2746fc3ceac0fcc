// The scene file formats octrace reads, one row each, chosen by the file's extension
// (case-insensitive). The one list of them: loadScene dispatches on it, Table 1
// (bench/table1/table1.cpp) lists the mesh files it names, the fuzz target (fuzz/fuzz_scene.cpp)
// picks its extension from it, and the command line's help text is made from it. Adding a
// format is its loader (core/scene/format_NAME.cpp) plus one row in scene_formats.cpp.
#pragma once

#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace oct {

struct SceneFormat {
    const char* extension;    // lower case, without the dot: "obj"
    const char* description;  // a few words for the help text: "Wavefront mesh"
    bool mesh;                // may hold a triangle mesh (Table 1 lists such files)
    bool pointCloud;          // may hold a point cloud (spheres)
    // Loads a file of this format; a SceneError for anything wrong with it (load_scene.h).
    Scene (*load)(const std::string& path, const LoadOptions& opts);
};

// Every format, in the order the help text lists them.
const std::vector<SceneFormat>& sceneFormats();

// The format of a path's extension, case-insensitive; nullptr when it has none or another.
const SceneFormat* findSceneFormat(const std::string& path);

// The extensions with their dots, joined: ".obj, .ply, .off, .stl or .xyz" for lastJoin " or ".
std::string sceneExtensionList(const std::string& lastJoin);

// Help text of a command's scene argument: every format with its description, and every
// generated scene of scene_generators.h.
std::string sceneFormatsHelp();

}  // namespace oct
