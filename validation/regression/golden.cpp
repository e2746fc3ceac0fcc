#include "validation/regression/golden.h"

#include <stb_image.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_backend.h"
#include "cpu_ref/render_cpu.h"
#include "validation/rays/ray_manifest.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using regression_detail::field;
using report_detail::fmt;

constexpr const char* kManifestName = "golden.json";
constexpr const char* kFormat = "octrace-golden";

bool isGenerated(const std::string& scene) { return scene.rfind("grid:", 0) == 0; }

struct GoldenImage {
    std::string scene, file;
};

struct GoldenManifest {
    std::string octrace;
    RegressionRender render;
    std::vector<GoldenImage> images;
};

GoldenManifest readGoldenManifest(const std::string& dir) {
    const std::string path = (std::filesystem::path(dir) / kManifestName).string();
    json j = readRegressionJson(path, "golden image manifest");
    if (field<std::string>(j, "format", path) != kFormat || field<int>(j, "version", path) != 1)
        throw IoError(path + ": not an " + kFormat + " version 1 manifest");
    GoldenManifest m;
    m.octrace = field<std::string>(j, "octrace", path);
    m.render = regressionRenderFromJson(field<json>(j, "render", path), path);
    for (const json& e : field<json>(j, "images", path))
        m.images.push_back(
            {field<std::string>(e, "scene", path), field<std::string>(e, "file", path)});
    if (m.images.empty()) throw IoError(path + ": lists no images; add some (scene, file)");
    return m;
}

json manifestJson(const GoldenManifest& m) {
    json images = json::array();
    for (const GoldenImage& g : m.images) images.push_back({{"scene", g.scene}, {"file", g.file}});
    return {{"format", kFormat},
            {"version", 1},
            {"octrace", m.octrace},
            {"render", toJson(m.render)},
            {"images", images}};
}

double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

json readRegressionJson(const std::string& path, const char* what) {
    std::ifstream in(path);
    if (!in)
        throw IoError(path + ": cannot read the " + what +
                      " (missing? docs/VALIDATION.md describes it; restore it from git)");
    try {
        return json::parse(in);
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
                                                const std::string& file) {
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
    std::vector<TracedFrame> out;
    for (const LayoutDesc& l : layouts()) {
        TracedFrame f;
        f.tracer = l.name;
        renderCpu(frame, convertLayout(scene, l.usesOctree ? tree : nullptr, l, opts), f.film);
        out.push_back(std::move(f));
    }
    if (embree) {
        TracedFrame f;
        f.tracer = "embree";
        f.usesLayouts = false;
        EmbreeSceneTracer(bareScene(scene)).render(frame, f.film);
        out.push_back(std::move(f));
    }
    return out;
}

ImageDiff compareImages(int width, int height, const std::vector<uint8_t>& golden,
                        const std::vector<uint8_t>& rgb, int channel) {
    ImageDiff d;
    const size_t n = size_t(width) * size_t(height);
    d.pixels = n;
    if (golden.size() != 3 * n || rgb.size() != 3 * n) {
        d.sizeMismatch = true;
        return d;
    }
    for (size_t i = 0; i < n; ++i) {
        int m = 0;
        for (int c = 0; c < 3; ++c)
            m = std::max(m, std::abs(int(golden[3 * i + c]) - rgb[3 * i + c]));
        if (m > 0) ++d.differing;
        if (m > channel) ++d.over;
        if (m > d.maxDiff) {
            d.maxDiff = m;
            d.worstX = int(i % size_t(width));
            d.worstY = int(i / size_t(width));
        }
    }
    return d;
}

bool GoldenTolerance::passes(const ImageDiff& d) const {
    if (d.sizeMismatch) return false;
    return double(d.over) <= maxOverFraction * double(d.pixels) && d.maxDiff <= maxDiff;
}

uint64_t GoldenReport::failures() const {
    uint64_t n = 0;
    for (const GoldenRow& r : rows) n += r.pass ? 0 : 1;
    return n;
}

std::vector<uint8_t> readPngRgb(const std::string& path, int& width, int& height) {
    int channels = 0;
    stbi_uc* px = stbi_load(path.c_str(), &width, &height, &channels, 3);
    if (!px)
        throw IoError(path + ": cannot read the golden PNG (" + stbi_failure_reason() +
                      "); restore it from git or rerun with --update");
    std::vector<uint8_t> rgb(px, px + size_t(width) * size_t(height) * 3);
    stbi_image_free(px);
    return rgb;
}

GoldenReport checkGolden(const std::string& dir, const std::string& root, bool embree,
                         const GoldenTolerance& tolerance) {
    const auto start = std::chrono::steady_clock::now();
    const GoldenManifest m = readGoldenManifest(dir);
    GoldenReport rep;
    rep.dir = dir;
    rep.goldenVersion = m.octrace;
    rep.render = m.render;
    rep.tolerance = tolerance;
    const std::string manifestPath = (std::filesystem::path(dir) / kManifestName).string();
    for (const GoldenImage& g : m.images) {
        int w = 0, h = 0;
        const std::vector<uint8_t> golden =
            readPngRgb((std::filesystem::path(dir) / g.file).string(), w, h);
        for (const TracedFrame& f :
             renderRegressionFrames(g.scene, root, m.render, embree, manifestPath)) {
            GoldenRow row{g.scene, g.file, f.tracer, {}, false};
            row.diff = compareImages(w, h, golden, f.film.rgb, tolerance.channel);
            row.pass = tolerance.passes(row.diff);
            rep.rows.push_back(std::move(row));
        }
    }
    rep.seconds = since(start);
    return rep;
}

GoldenReport updateGolden(const std::string& dir, const std::string& root) {
    const auto start = std::chrono::steady_clock::now();
    GoldenManifest m = readGoldenManifest(dir);
    GoldenReport rep;
    rep.dir = dir;
    rep.goldenVersion = octraceVersion();
    rep.render = m.render;
    rep.updated = true;
    const std::string manifestPath = (std::filesystem::path(dir) / kManifestName).string();
    OutputSet out;
    for (const GoldenImage& g : m.images) {
        const std::vector<TracedFrame> frames =
            renderRegressionFrames(g.scene, root, m.render, false, manifestPath);
        const Film& film = frames.front().film;
        for (const TracedFrame& f : frames)
            if (f.film.rgb != film.rgb)
                throw std::runtime_error(
                    fmt("golden %s: layouts %s and %s render different images (%llu pixels); "
                        "nothing was written: find out why before pinning an image",
                        g.scene.c_str(), frames.front().tracer.c_str(), f.tracer.c_str(),
                        (unsigned long long)compareImages(film.width, film.height, film.rgb,
                                                          f.film.rgb, 0)
                            .differing));
        const std::string path = (std::filesystem::path(dir) / g.file).string();
        GoldenRow row{g.scene, g.file, "all layouts", {}, true};
        std::error_code ec;
        if (std::filesystem::exists(path, ec)) {
            int w = 0, h = 0;
            const std::vector<uint8_t> old = readPngRgb(path, w, h);
            row.diff = compareImages(w, h, old, film.rgb, rep.tolerance.channel);
            if (w != film.width || h != film.height) row.diff.sizeMismatch = true;
        } else {
            row.diff.sizeMismatch = true;  // no old image: everything is new
            row.diff.pixels = film.pixelCount();
        }
        rep.rows.push_back(row);
        out.stage(path, encodePng(path, film.width, film.height, film.rgb));
    }
    m.octrace = octraceVersion();
    const std::string text = manifestJson(m).dump(2) + "\n";
    out.stage(manifestPath, text.data(), text.size());
    out.commit();
    rep.seconds = since(start);
    return rep;
}

json toJson(const GoldenReport& r) {
    json rows = json::array();
    for (const GoldenRow& x : r.rows) {
        json worst = nullptr;
        if (x.diff.maxDiff > 0) worst = {{"x", x.diff.worstX}, {"y", x.diff.worstY}};
        rows.push_back({{"scene", x.scene},
                        {"file", x.file},
                        {"tracer", x.tracer},
                        {"pass", x.pass},
                        {"size_mismatch", x.diff.sizeMismatch},
                        {"pixels", x.diff.pixels},
                        {"differing", x.diff.differing},
                        {"over_tolerance", x.diff.over},
                        {"max_diff", x.diff.maxDiff},
                        {"worst", worst}});
    }
    return {{"pass", r.passes()},
            {"dir", r.dir},
            {"updated", r.updated},
            {"golden_octrace", r.goldenVersion},
            {"render", toJson(r.render)},
            {"tolerance",
             {{"channel", r.tolerance.channel},
              {"max_over_fraction", r.tolerance.maxOverFraction},
              {"max_diff", r.tolerance.maxDiff}}},
            {"failures", r.failures()},
            {"images", rows},
            {"seconds", r.seconds}};
}

std::string humanSummary(const GoldenReport& r) {
    std::string s;
    if (r.updated) {
        s += fmt("golden   %s: wrote %zu images (%dx%d), octrace %s\n", r.dir.c_str(),
                 r.rows.size(), r.render.width, r.render.height, r.goldenVersion.c_str());
        for (const GoldenRow& x : r.rows)
            s += x.diff.sizeMismatch
                     ? fmt("  %-28s new (no earlier image of this size)\n", x.file.c_str())
                 : x.diff.differing == 0
                     ? fmt("  %-28s unchanged\n", x.file.c_str())
                     : fmt("  %-28s %llu pixels changed, %llu by more than %d/255, max %d/255 "
                           "at (%d, %d)\n",
                           x.file.c_str(), (unsigned long long)x.diff.differing,
                           (unsigned long long)x.diff.over, r.tolerance.channel, x.diff.maxDiff,
                           x.diff.worstX, x.diff.worstY);
        return s;
    }
    const std::string cap =
        r.tolerance.maxDiff < 255 ? fmt(", none over %d/255", r.tolerance.maxDiff) : "";
    s +=
        fmt("golden   %s: %zu comparisons (%dx%d, images of octrace %s), rule: at most %.3g%% of "
            "pixels over %d/255%s: %s (%.2f s)\n",
            r.dir.c_str(), r.rows.size(), r.render.width, r.render.height, r.goldenVersion.c_str(),
            100.0 * r.tolerance.maxOverFraction, r.tolerance.channel, cap.c_str(),
            r.passes() ? "PASS" : "FAIL", r.seconds);
    for (const GoldenRow& x : r.rows) {
        if (x.pass && x.diff.differing == 0) continue;
        if (x.diff.sizeMismatch) {
            s += fmt("  %-28s %-10s FAIL: image size differs from the render\n", x.file.c_str(),
                     x.tracer.c_str());
            continue;
        }
        s += fmt("  %-28s %-10s %s: %llu pixels differ, %llu over %d/255, max %d/255 at (%d, %d)\n",
                 x.file.c_str(), x.tracer.c_str(), x.pass ? "pass" : "FAIL",
                 (unsigned long long)x.diff.differing, (unsigned long long)x.diff.over,
                 r.tolerance.channel, x.diff.maxDiff, x.diff.worstX, x.diff.worstY);
    }
    return s;
}

}  // namespace oct
