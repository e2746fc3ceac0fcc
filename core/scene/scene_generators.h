// The generated scenes octrace makes from a spec instead of reading a file, one row each, chosen
// by the spec's prefix (case-insensitive, before the first ':'). The one list of them: loadScene
// dispatches on it, the command line's help text and loadScene's messages are made from it, and
// the regression files (validation/regression/) tell a generated scene from a path by it.
// Adding a generator is its scene (core/scene/NAME.{h,cpp}) plus one row in
// scene_generators.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace oct {

struct SceneGenerator {
    const char* prefix;       // lower case, without the colon: "grid"
    const char* usage;        // the spec's form: "grid:N[:SEED]"
    const char* description;  // a few words for the help text: "grid cloud of N spheres"
    // Makes the scene of a spec with this prefix; a SceneError for a malformed spec, a value out
    // of range or an option that does not apply (one line, naming the spec).
    Scene (*generate)(const std::string& spec, const LoadOptions& opts);
};

// Every generator, in the order the help text lists them.
const std::vector<SceneGenerator>& sceneGenerators();

// The generator of a spec ("PREFIX:..." for a prefix of the table); nullptr for anything else.
const SceneGenerator* findSceneGenerator(const std::string& spec);

// The usages joined: "grid:N[:SEED] or slivers:N[:SEED]" for lastJoin " or ".
std::string sceneGeneratorList(const std::string& lastJoin);

// "PREFIX:N" or "PREFIX:N:SEED" with decimal N <= maxCount and SEED (digits only, nothing else);
// false for any other text after the prefix. `seed` keeps its value when no seed is given.
bool parseCountSpec(const std::string& spec, uint64_t maxCount, uint64_t& n, uint64_t& seed);

}  // namespace oct
