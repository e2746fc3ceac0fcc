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
    if (updated) return 0;
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

GoldenRow judgeImage(GoldenRow row, const Film& frame, int goldenWidth, int goldenHeight,
                     const std::vector<uint8_t>& golden) {
    row.diff = compareImages(goldenWidth, goldenHeight, golden, frame.rgb, row.tolerance.channel);
    if (goldenWidth != frame.width || goldenHeight != frame.height) row.diff.sizeMismatch = true;
    row.pass = row.tolerance.passes(row.diff);
    if (!row.pass)
        row.images = {frame.width, frame.height, goldenWidth, goldenHeight, frame.rgb, golden};
    return row;
}

namespace {

json toleranceJson(const GoldenTolerance& t) {
    return {
        {"channel", t.channel}, {"max_over_fraction", t.maxOverFraction}, {"max_diff", t.maxDiff}};
}

// "at most 0.05% of pixels over 1/255" or "no pixel over 0/255".
std::string ruleText(const GoldenTolerance& t) {
    std::string s = t.maxOverFraction > 0.0 ? fmt("at most %.3g%% of pixels over %d/255",
                                                  100.0 * t.maxOverFraction, t.channel)
                                            : fmt("no pixel over %d/255", t.channel);
    if (t.maxDiff < 255 && t.maxOverFraction > 0.0) s += fmt(", none over %d/255", t.maxDiff);
    return s;
}

}  // namespace

json toJson(const GoldenReport& r) {
    json rows = json::array();
    for (const GoldenRow& x : r.rows) {
        json worst = nullptr;
        if (x.diff.maxDiff > 0) worst = {{"x", x.diff.worstX}, {"y", x.diff.worstY}};
        rows.push_back({{"scene", x.scene},
                        {"view", x.view},
                        {"file", x.file},
                        {"tracer", x.tracer},
                        {"backend", x.backend},
                        {"render", toJson(x.render)},
                        {"tolerance", toleranceJson(x.tolerance)},
                        {"pass", x.pass},
                        {"missing", x.missing},
                        {"size_mismatch", x.diff.sizeMismatch},
                        {"pixels", x.diff.pixels},
                        {"differing", x.diff.differing},
                        {"over_tolerance", x.diff.over},
                        {"max_diff", x.diff.maxDiff},
                        {"worst", worst}});
    }
    return {{"pass", r.passes()},       {"manifest", r.manifest},
            {"updated", r.updated},     {"golden_octrace", r.goldenVersion},
            {"failures", r.failures()}, {"images", rows},
            {"seconds", r.seconds}};
}

std::string humanSummary(const GoldenReport& r) {
    std::string s;
    if (r.updated) {
        s += fmt("golden   %s: wrote %zu images, octrace %s\n", r.manifest.c_str(), r.rows.size(),
                 r.goldenVersion.c_str());
        for (const GoldenRow& x : r.rows)
            s += x.diff.sizeMismatch
                     ? fmt("  %-28s new (no earlier image of this size)\n", x.file.c_str())
                 : x.diff.differing == 0
                     ? fmt("  %-28s unchanged\n", x.file.c_str())
                     : fmt("  %-28s %llu pixels changed, %llu by more than %d/255, max %d/255 "
                           "at (%d, %d)\n",
                           x.file.c_str(), (unsigned long long)x.diff.differing,
                           (unsigned long long)x.diff.over, x.tolerance.channel, x.diff.maxDiff,
                           x.diff.worstX, x.diff.worstY);
        return s;
    }
    // The rule of each backend, in the order the rows first name them.
    std::vector<std::pair<std::string, std::string>> rules;
    for (const GoldenRow& x : r.rows) {
        bool seen = false;
        for (const auto& rule : rules) seen = seen || rule.first == x.backend;
        if (!seen) rules.push_back({x.backend, ruleText(x.tolerance)});
    }
    std::string ruleList;
    for (const auto& [backend, text] : rules)
        ruleList += (ruleList.empty() ? "" : "; ") + backend + " " + text;
    s += fmt("golden   %s: %zu comparisons (images of octrace %s); rule: %s: %s (%.2f s)\n",
             r.manifest.c_str(), r.rows.size(), r.goldenVersion.c_str(), ruleList.c_str(),
             r.passes() ? "PASS" : "FAIL", r.seconds);
    for (const GoldenRow& x : r.rows) {
        if (x.pass && x.diff.differing == 0) continue;
        const std::string head =
            fmt("  %-28s %-10s %-7s", x.file.c_str(), x.tracer.c_str(), x.backend.c_str());
        if (x.missing) {
            s += head + " FAIL: no golden image for this frame: rerun with --update\n";
            continue;
        }
        if (x.diff.sizeMismatch) {
            s += head + " FAIL: image size differs from the render\n";
            continue;
        }
        s += head + fmt(" %s: %llu pixels differ, %llu over %d/255, max %d/255 at (%d, %d)\n",
                        x.pass ? "pass" : "FAIL", (unsigned long long)x.diff.differing,
                        (unsigned long long)x.diff.over, x.tolerance.channel, x.diff.maxDiff,
                        x.diff.worstX, x.diff.worstY);
    }
    return s;
}

}  // namespace oct
