#include "validation/regression/golden.h"

#include <stb_image.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>

#include "core/io/input_file.h"
#include "core/io/output_file.h"
#include "validation/rays/ray_manifest.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using regression_detail::field;
using report_detail::fmt;

constexpr const char* kManifestName = "golden.json";
constexpr const char* kFormat = "octrace-golden";

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

}  // namespace

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
    // Read through the one input rule (a FIFO or device is refused unread), then decoded.
    const std::string bytes = readSmallInput(path, "the golden PNG", kMaxGoldenPngBytes,
                                             "restore it from git or rerun with --update");
    int channels = 0;
    stbi_uc* px = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                        int(bytes.size()), &width, &height, &channels, 3);
    if (!px)
        throw IoError(path + ": cannot read the golden PNG (" + stbi_failure_reason() +
                      "); restore it from git or rerun with --update");
    std::vector<uint8_t> rgb(px, px + size_t(width) * size_t(height) * 3);
    stbi_image_free(px);
    return rgb;
}

namespace {

// Update mode's row for one image: the frames of every layout must agree bit for bit; the new
// image is compared with the old one (none: every pixel new) and staged.
GoldenRow rewriteImage(const GoldenImage& g, const std::string& path,
                       const std::vector<TracedFrame>& frames, int channel, OutputSet& out) {
    const Film& film = frames.front().film;
    for (const TracedFrame& f : frames)
        if (f.film.rgb != film.rgb)
            throw std::runtime_error(fmt(
                "golden %s: layouts %s and %s render different images (%llu pixels); "
                "nothing was written: find out why before pinning an image",
                g.scene.c_str(), frames.front().tracer.c_str(), f.tracer.c_str(),
                (unsigned long long)compareImages(film.width, film.height, film.rgb, f.film.rgb, 0)
                    .differing));
    GoldenRow row{g.scene, g.file, "all layouts", frames.front().backend, {}, true, {}};
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        int w = 0, h = 0;
        const std::vector<uint8_t> old = readPngRgb(path, w, h);
        row.diff = compareImages(w, h, old, film.rgb, channel);
        if (w != film.width || h != film.height) row.diff.sizeMismatch = true;
    } else {
        row.diff.sizeMismatch = true;  // no old image: everything is new
        row.diff.pixels = film.pixelCount();
    }
    out.stage(path, encodePng(path, film.width, film.height, film.rgb));
    return row;
}

// The one skeleton of checking and updating: read the manifest, render each image's scene,
// compare every tracer with the image, or rewrite the images and the manifest (all or none).
GoldenReport runGolden(const std::string& dir, const std::string& root, RegressionMode mode,
                       bool embree, const GoldenTolerance& tolerance,
                       const std::vector<const BackendDesc*>& backends) {
    const auto start = std::chrono::steady_clock::now();
    const bool update = mode == RegressionMode::Update;
    GoldenManifest m = readGoldenManifest(dir);
    GoldenReport rep;
    rep.dir = dir;
    rep.goldenVersion = update ? octraceVersion() : m.octrace;
    rep.render = m.render;
    rep.tolerance = tolerance;
    rep.updated = update;
    const std::string manifestPath = (std::filesystem::path(dir) / kManifestName).string();
    OutputSet out;
    for (const GoldenImage& g : m.images) {
        const std::string path = (std::filesystem::path(dir) / g.file).string();
        if (update) {
            rep.rows.push_back(rewriteImage(
                g, path, renderRegressionFrames(g.scene, root, m.render, false, manifestPath),
                tolerance.channel, out));
            continue;
        }
        int w = 0, h = 0;
        const std::vector<uint8_t> golden = readPngRgb(path, w, h);
        for (const TracedFrame& f :
             renderRegressionFrames(g.scene, root, m.render, embree, manifestPath, backends)) {
            GoldenRow row{g.scene, g.file, f.tracer, f.backend, {}, false, {}};
            row.diff = compareImages(w, h, golden, f.film.rgb, tolerance.channel);
            row.pass = tolerance.passes(row.diff);
            if (!row.pass) row.images = {f.film.width, f.film.height, w, h, f.film.rgb, golden};
            rep.rows.push_back(std::move(row));
        }
    }
    if (update) {
        m.octrace = octraceVersion();
        const std::string text = manifestJson(m).dump(2) + "\n";
        out.stage(manifestPath, text.data(), text.size());
        out.commit();
    }
    rep.seconds = secondsSince(start);
    return rep;
}

}  // namespace

GoldenReport checkGolden(const std::string& dir, const std::string& root, bool embree,
                         const GoldenTolerance& tolerance,
                         const std::vector<const BackendDesc*>& backends) {
    return runGolden(dir, root, RegressionMode::Check, embree, tolerance, backends);
}

GoldenReport updateGolden(const std::string& dir, const std::string& root) {
    return runGolden(dir, root, RegressionMode::Update, false, GoldenTolerance{}, {});
}

json toJson(const GoldenReport& r) {
    json rows = json::array();
    for (const GoldenRow& x : r.rows) {
        json worst = nullptr;
        if (x.diff.maxDiff > 0) worst = {{"x", x.diff.worstX}, {"y", x.diff.worstY}};
        rows.push_back({{"scene", x.scene},
                        {"file", x.file},
                        {"tracer", x.tracer},
                        {"backend", x.backend},
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
            s += fmt("  %-28s %-10s %-7s FAIL: image size differs from the render\n",
                     x.file.c_str(), x.tracer.c_str(), x.backend.c_str());
            continue;
        }
        s +=
            fmt("  %-28s %-10s %-7s %s: %llu pixels differ, %llu over %d/255, max %d/255 at (%d, "
                "%d)\n",
                x.file.c_str(), x.tracer.c_str(), x.backend.c_str(), x.pass ? "pass" : "FAIL",
                (unsigned long long)x.diff.differing, (unsigned long long)x.diff.over,
                r.tolerance.channel, x.diff.maxDiff, x.diff.worstX, x.diff.worstY);
    }
    return s;
}

}  // namespace oct
