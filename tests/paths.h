// The committed inputs the tests read, defined once: the test binaries are unity builds (a
// folder's files compiled together, tests/CMakeLists.txt), where a constant defined in two
// files would be defined twice. Files bring the names in with using-declarations.
#pragma once

#include <string>
#include <vector>

namespace octtest {

inline const std::string kRoot = OCT_SOURCE_DIR;  // the repository
inline const std::string kMeshes = kRoot + "/meshes";
inline const std::string kTeapot = kMeshes + "/teapot.obj";
inline const std::string kCube = kMeshes + "/cube_binary.ply";  // the unit cube, 12 triangles

inline std::string meshPath(const std::string& name) { return kMeshes + "/" + name; }

// The committed meshes (meshes/README.md).
inline std::vector<std::string> committedMeshes() {
    return {"cornell_box.obj", "teapot.obj", "spider.obj",      "wuson.obj",           "wuson.off",
            "wuson.ply",       "wuson.stl",  "cube_binary.ply", "sphere_with_hole.stl"};
}

}  // namespace octtest
