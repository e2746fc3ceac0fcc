#include "validation/regression/regression_render.h"

#include <filesystem>
#include <memory>

#include "backends/backend_list.h"
#include "core/io/input_file.h"
#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/scene/load_scene.h"
#include "core/scene/scene_generators.h"

namespace oct {
namespace {

using nlohmann::json;
using regression_detail::field;

bool isGenerated(const std::string& scene) { return findSceneGenerator(scene) != nullptr; }

}  // namespace

json readRegressionJson(const std::string& path, const char* what) {
    // Through the one input rule: a FIFO, device or directory is refused unread, a file above
    // kMaxRegressionJsonBytes unread too.
    const std::string text =
        readSmallInput(path, std::string("the ") + what, kMaxRegressionJsonBytes,
                       "docs/VALIDATION.md describes it; restore it from git");
    try {
        return json::parse(text);
    } catch (const json::exception& e) {
        throw IoError(path + ": not valid JSON (" + e.what() + "); restore it from git");
    }
}

void regression_detail::badField(const std::string& file, const char* name, bool missing) {
    throw IoError(file + ": " + (missing ? "missing field '" : "field '") + name +
                  (missing ? "'" : "' has the wrong type") + "; restore the file from git");
}

RegressionRender regressionRenderFromJson(const json& j, const std::string& file) {
    RegressionRender r;
    r.width = field<int>(j, "width", file);
    r.height = field<int>(j, "height", file);
    if (field<std::string>(j, "camera", file) != "default")
        throw IoError(file + ": render.camera must be \"default\" (the framing of makeFrame)");
    r.build.maxDepth = field<int>(j, "max_depth", file);
    r.build.maxPrims = field<uint32_t>(j, "max_prims", file);
    r.radius = field<float>(j, "radius", file);
    return r;
}

json toJson(const RegressionRender& r) {
    return {{"width", r.width},
            {"height", r.height},
            {"camera", "default"},
            {"max_depth", r.build.maxDepth},
            {"max_prims", r.build.maxPrims},
            {"radius", r.radius}};
}

std::vector<TracedFrame> renderRegressionFrames(const std::string& sceneName,
                                                const std::string& root,
                                                const RegressionRender& render, bool embree,
                                                const std::string& file,
                                                const std::vector<const BackendDesc*>& backends) {
    std::string path = sceneName;
    if (!isGenerated(sceneName)) {
        path = (std::filesystem::path(root) / sceneName).string();
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw IoError(file + " names scene '" + sceneName + "', which is not under '" + root +
                          "': run octrace validate from the repository root");
    }
    LoadOptions lo;
    lo.radius = render.radius;
    const Scene scene = loadScene(path, lo);
    CameraOptions cam;
    cam.width = render.width;
    cam.height = render.height;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    LayoutOptions opts;
    opts.build = render.build;
    std::shared_ptr<const Octree> tree = buildSharedOctree(scene, render.build);
    std::vector<const BackendDesc*> ours = backends;
    if (ours.empty()) ours.push_back(&hostBackend());
    std::vector<TracedFrame> out;
    for (const LayoutDesc& l : layouts()) {
        // Converted once, rendered on every backend.
        const BuiltScene built = convertLayout(scene, l.usesOctree ? tree : nullptr, l, opts);
        for (const BackendDesc* b : ours) {
            TracedFrame f;
            f.tracer = l.name;
            f.backend = b->name;
            renderWith(*b, built, frame, f.film);
            out.push_back(std::move(f));
        }
    }
    if (embree) {
        TracedFrame f;
        f.tracer = referenceBackend().name;
        f.backend = referenceBackend().name;
        f.usesLayouts = false;
        renderWith(referenceBackend(), bareScene(scene), frame, f.film);
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace oct
