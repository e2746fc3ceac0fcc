// The table of generated scenes (scene_generators.h) and the specs' parsing.
#include "core/scene/scene_generators.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <limits>

#include "core/scene/grid_cloud.h"
#include "core/scene/loader_detail.h"
#include "core/scene/slivers.h"

namespace oct {
namespace {

using scene_detail::inQuotes;

Scene generateGrid(const std::string& spec, const LoadOptions& opts) {
    uint64_t n = 0, seed = kGridCloudDefaultSeed;
    if (!parseCountSpec(spec, std::numeric_limits<uint32_t>::max(), n, seed))
        throw SceneError("bad generator spec " + inQuotes(spec) +
                         "; write grid:N or grid:N:SEED with decimal N (1 .. 4294967295) and SEED");
    if (opts.radius > 0.0f)
        throw SceneError("a sphere radius cannot be given for " + inQuotes(spec) +
                         ": the grid cloud's radius is fixed at 0.4 cell so that no "
                         "sphere straddles two leaves; leave the radius at 0");
    return makeGridCloud(uint32_t(n), seed);
}

Scene generateSlivers(const std::string& spec, const LoadOptions&) {
    uint64_t n = 0, seed = kSliversDefaultSeed;
    if (!parseCountSpec(spec, std::numeric_limits<uint64_t>::max(), n, seed))
        throw SceneError("bad generator spec " + inQuotes(spec) +
                         "; write slivers:N or slivers:N:SEED with decimal N (the number of "
                         "triangles, even, 2 .. " +
                         std::to_string(kSliversMaxTriangles) + ") and SEED");
    return makeSlivers(n, seed);  // a sphere radius does not apply to triangles: ignored
}

}  // namespace

const std::vector<SceneGenerator>& sceneGenerators() {
    static const std::vector<SceneGenerator> kGenerators = {
        {"grid", "grid:N[:SEED]", "the paper's grid cloud of N spheres", generateGrid},
        {"slivers", "slivers:N[:SEED]", "a unit square cut into N sliver triangles",
         generateSlivers},
    };
    return kGenerators;
}

const SceneGenerator* findSceneGenerator(const std::string& spec) {
    const size_t colon = spec.find(':');
    if (colon == std::string::npos) return nullptr;
    const std::string prefix = scene_detail::toLower(spec.substr(0, colon));
    for (const SceneGenerator& g : sceneGenerators())
        if (prefix == g.prefix) return &g;
    return nullptr;
}

std::string sceneGeneratorList(const std::string& lastJoin) {
    std::vector<std::string> usages;
    for (const SceneGenerator& g : sceneGenerators()) usages.push_back(g.usage);
    return scene_detail::joinList(usages, lastJoin);
}

bool parseCountSpec(const std::string& spec, uint64_t maxCount, uint64_t& n, uint64_t& seed) {
    const size_t prefixEnd = spec.find(':');
    if (prefixEnd == std::string::npos) return false;
    const std::string rest = spec.substr(prefixEnd + 1);
    const size_t colon = rest.find(':');
    auto number = [](const std::string& text, uint64_t max, uint64_t& out) {
        if (text.empty() || text.size() > 20 ||
            !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return false;
        errno = 0;
        unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
        out = v;
        return errno == 0 && v <= max;
    };
    uint64_t count = 0, s = seed;
    const bool ok = number(rest.substr(0, colon), maxCount, count) &&
                    (colon == std::string::npos ||
                     number(rest.substr(colon + 1), std::numeric_limits<uint64_t>::max(), s));
    if (!ok) return false;
    n = count;
    seed = s;
    return true;
}

}  // namespace oct
