// What `octrace info --json` reports of a scene: what loading kept and dropped, the mesh's
// topology, the octree's shape, and each layout's facts (bytes, slots) from the registry. The
// command line prints it (or its text form); the Python module's Scene.info() returns it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/octree/layout.h"
#include "core/scene/scene.h"

namespace oct {

// Builds the canonical octree of `scene` with lo.build and reports; `layoutLines`, when given,
// receives each layout's name and one-line summary for the text form.
nlohmann::json sceneInfo(const Scene& scene, const LayoutOptions& lo,
                         std::vector<std::pair<std::string, std::string>>* layoutLines = nullptr);

}  // namespace oct
