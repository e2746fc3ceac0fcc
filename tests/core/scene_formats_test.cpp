// The scene-format table (core/scene/scene_formats.h): one complete row per extension, lookups
// that ignore case, and help text and messages that name every format.
#include "core/scene/scene_formats.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/scene/load_scene.h"

namespace oct {
namespace {

TEST(SceneFormats, OneRowPerExtensionAndEveryRowComplete) {
    std::set<std::string> seen;
    for (const SceneFormat& f : sceneFormats()) {
        EXPECT_TRUE(seen.insert(f.extension).second) << "listed twice: " << f.extension;
        EXPECT_NE(std::string(f.description), "") << f.extension;
        EXPECT_TRUE(f.mesh || f.pointCloud) << f.extension;
        EXPECT_NE(f.load, nullptr) << f.extension;
    }
    EXPECT_EQ(seen, (std::set<std::string>{"obj", "ply", "off", "stl", "xyz"}));
}

TEST(SceneFormats, LookupByExtensionIgnoresCase) {
    ASSERT_NE(findSceneFormat("a/b/mesh.OBJ"), nullptr);
    EXPECT_EQ(std::string(findSceneFormat("a/b/mesh.OBJ")->extension), "obj");
    EXPECT_EQ(std::string(findSceneFormat("cloud.Xyz")->extension), "xyz");
    EXPECT_TRUE(findSceneFormat("x.ply")->mesh && findSceneFormat("x.ply")->pointCloud);
    EXPECT_FALSE(findSceneFormat("x.xyz")->mesh);
    EXPECT_EQ(findSceneFormat("mesh.3ds"), nullptr);
    EXPECT_EQ(findSceneFormat("no_extension"), nullptr);
    EXPECT_EQ(findSceneFormat("dir.obj/file"), nullptr);
}

TEST(SceneFormats, HelpAndListsNameEveryFormat) {
    const std::string help = sceneFormatsHelp();
    for (const SceneFormat& f : sceneFormats()) {
        EXPECT_NE(help.find(std::string(".") + f.extension + " ("), std::string::npos) << help;
        EXPECT_NE(help.find(f.description), std::string::npos) << help;
    }
    EXPECT_NE(help.find("grid:N[:SEED]"), std::string::npos) << help;
    EXPECT_EQ(sceneExtensionList(" or "), ".obj, .ply, .off, .stl or .xyz");
    const std::string unknown = (std::filesystem::temp_directory_path() /
                                 ("octrace_formats_" + std::to_string(::getpid()) + ".3ds"))
                                    .string();
    std::ofstream(unknown) << "v 0 0 0\n";
    try {
        loadScene(unknown);
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(sceneExtensionList(", ")), std::string::npos)
            << e.what();
    }
    std::filesystem::remove(unknown);
}

}  // namespace
}  // namespace oct
