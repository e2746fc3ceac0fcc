#include "validation/regression/regression_render.h"

#include <algorithm>
#include <filesystem>
#include <memory>

#include "backends/backend_list.h"
#include "core/io/input_file.h"
#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/scene/load_scene.h"
#include "core/scene/scene_generators.h"
#include "validation/validate.h"

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

json toJson(const RegressionRender& r) {
    return {{"width", r.width},
            {"height", r.height},
            {"camera", "default"},
            {"max_depth", r.build.maxDepth},
            {"max_prims", r.build.maxPrims},
            {"radius", r.radius},
            {"scale", r.scale}};
}

CameraOptions viewCamera(const std::string& view, const Scene& scene, int width, int height) {
    CameraOptions cam;
    cam.width = width;
    cam.height = height;
    if (view == "inside") return insideViewCamera(scene, cam);
    if (view == "default") return cam;
    const float sign = view[0] == '-' ? -1.0f : 1.0f;
    switch (view.size() == 2 ? view[1] : '?') {
        case 'x':
            cam.from = {sign, 0.0f, 0.0f};
            return cam;
        case 'y':  // looking along the up vector: up is the side of -z (from +y) or +z
            cam.from = {0.0f, sign, 0.0f};
            cam.up = Vec3{0.0f, 0.0f, -sign};
            return cam;
        case 'z':
            cam.from = {0.0f, 0.0f, sign};
            return cam;
        default:
            throw std::runtime_error("no regression view called '" + view + "'");
    }
}

Scene loadRegressionScene(const std::string& sceneName, const std::string& root,
                          const RegressionRender& render, const std::string& file) {
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
    Scene scene = loadScene(path, lo);
    if (render.scale == 1.0) return scene;
    if (scene.kind != PrimKind::Triangles)
        throw IoError(file + ": scene '" + sceneName +
                      "' is a point cloud; 'scale' applies to triangle meshes only");
    // Through the array rule (sceneFromTriangles): a scaled vertex out of the numeric range, or
    // a triangle whose area underflows, is refused naming its row, never dropped.
    std::vector<float> rows;
    rows.reserve(9 * scene.triangles.size());
    for (const Triangle& t : scene.triangles)
        for (const Vec3& v : {t.v0, t.v1, t.v2})
            for (float c : {v.x, v.y, v.z}) rows.push_back(float(double(c) * render.scale));
    return sceneFromTriangles(rows.data(), scene.triangles.size(), sceneName);
}

std::vector<TracedFrame> renderRegressionFrames(const Scene& scene, const RegressionRender& render,
                                                const std::vector<std::string>& views,
                                                const std::vector<std::string>& layoutNames,
                                                bool embree,
                                                const std::vector<const BackendDesc*>& backends) {
    std::vector<FrameParams> frames;
    for (const std::string& v : views)
        frames.push_back(
            makeFrame(scene.bounds(), viewCamera(v, scene, render.width, render.height)));
    std::vector<const LayoutDesc*> chosen;
    for (const LayoutDesc& l : layouts())
        if (layoutNames.empty() ||
            std::find(layoutNames.begin(), layoutNames.end(), l.name) != layoutNames.end())
            chosen.push_back(&l);
    LayoutOptions opts;
    opts.build = render.build;
    std::shared_ptr<const Octree> tree;
    for (const LayoutDesc* l : chosen)
        if (l->usesOctree && !tree) tree = buildSharedOctree(scene, render.build);
    std::vector<const BackendDesc*> ours = backends;
    if (ours.empty()) ours.push_back(&hostBackend());
    std::vector<TracedFrame> out;
    auto renderOne = [&](const BackendDesc& b, const BuiltScene& built, const char* tracer,
                         size_t view) {
        TracedFrame f;
        f.tracer = tracer;
        f.backend = b.name;
        f.view = views[view];
        f.usesLayouts = b.usesLayouts;
        renderWith(b, built, frames[view], f.film);
        out.push_back(std::move(f));
    };
    for (const LayoutDesc* l : chosen) {
        // Converted once, rendered from every view on every backend.
        const BuiltScene built = convertLayout(scene, l->usesOctree ? tree : nullptr, *l, opts);
        for (size_t v = 0; v < views.size(); ++v)
            for (const BackendDesc* b : ours) renderOne(*b, built, l->name, v);
    }
    if (embree) {
        const BuiltScene bare = bareScene(scene);
        for (size_t v = 0; v < views.size(); ++v)
            renderOne(referenceBackend(), bare, referenceBackend().name, v);
    }
    return out;
}

}  // namespace oct
