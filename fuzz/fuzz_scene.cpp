// libFuzzer target over scene loading and octree building (docs/ROBUSTNESS.md).
//
// Input: one selector byte, then a file's bytes. The selector picks the extension from the scene
// format table (core/scene/scene_formats.h: byte % the number of formats); the bytes are written to
// a file of that name in a private temporary folder and loaded with loadScene, exactly as `octrace`
// loads a user's file. When loading succeeds, the canonical octree is built with small parameters
// and converted to the hash and linear layouts (the linear one under a small memory budget).
//
// SceneError and OctreeError are the expected ways to refuse an input. Anything else is a
// finding: a crash, a sanitizer report, another exception (std::terminate), a hang (-timeout)
// or an allocation past -rss_limit_mb / -malloc_limit_mb.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/octree/octree.h"
#include "core/scene/load_scene.h"
#include "core/scene/scene_formats.h"
#include "fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::vector<oct::SceneFormat>& formats = oct::sceneFormats();
    const std::string path =
        fuzz::scratchDir() + "/input." + formats[data[0] % formats.size()].extension;
    fuzz::writeFile(path, data + 1, size - 1);
    try {
        oct::Scene scene = oct::loadScene(path);
        oct::BuildParams params;
        params.maxDepth = 5;
        params.maxPrims = 4;
        oct::Octree tree = oct::buildOctree(scene, params);
        oct::HashOctree hash = oct::buildHash(tree);
        oct::LinearOctree linear = oct::buildLinear(tree, uint64_t(64) << 20);
        // The layouts must hold every node of the canonical tree.
        if (hash.slots.size() < tree.nodes.size() || linear.nodes.size() < tree.nodes.size())
            std::abort();
    } catch (const oct::SceneError&) {
    } catch (const oct::OctreeError&) {
    }
    std::remove(path.c_str());
    return 0;
}
