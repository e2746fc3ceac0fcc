#include "validation/regression/artifacts.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/io/markup.h"
#include "core/io/output_file.h"
#include "validation/report/report_util.h"

namespace oct {

using report_detail::fmt;

namespace {

// A file name of letters, digits, '.', '-' and '_' only: the row's image, tracer and backend.
std::string safeName(const std::string& s) {
    std::string out;
    for (char c : s) out += (std::isalnum((unsigned char)c) || c == '.' || c == '-') ? c : '_';
    return out;
}

std::string costCell(const std::optional<CostTotals>& t) {
    return t ? fmt("%.3f / %.3f", t->nodesPerPixel(), t->primsPerPixel()) : "—";
}

const char* kStyle =
    "body{font-family:sans-serif;margin:1.5em}img{image-rendering:pixelated;width:256px;"
    "border:1px solid #888}td,th{padding:.2em .6em;text-align:left}table{border-collapse:"
    "collapse}tr:nth-child(even){background:#f2f2f2}.key{display:inline-block;width:1em;"
    "height:1em;vertical-align:middle;border:1px solid #888}";

}  // namespace

std::vector<uint8_t> goldenDiffImage(const GoldenImages& im, int channel) {
    if (im.width != im.goldenWidth || im.height != im.goldenHeight) return {};
    std::vector<uint8_t> out(im.golden.size());
    for (size_t p = 0; p + 2 < im.golden.size(); p += 3) {
        int d = 0;
        for (int c = 0; c < 3; ++c)
            d = std::max(d, std::abs(int(im.golden[p + c]) - int(im.actual[p + c])));
        const uint8_t dim[3] = {uint8_t(im.golden[p] / 3), uint8_t(im.golden[p + 1] / 3),
                                uint8_t(im.golden[p + 2] / 3)};
        const uint8_t blue[3] = {40, 110, 255}, red[3] = {255, 0, 0};
        const uint8_t* colour = d == 0 ? dim : d <= channel ? blue : red;
        std::copy(colour, colour + 3, out.begin() + p);
    }
    return out;
}

ArtifactsWritten writeRegressionArtifacts(const std::string& dir, const RegressionReport& r,
                                          bool always) {
    ArtifactsWritten w;
    std::vector<const GoldenRow*> images;
    if (r.golden)
        for (const GoldenRow& row : r.golden->rows)
            if (!row.pass) images.push_back(&row);
    std::vector<const CostRow*> costs;
    if (r.cost)
        for (const CostRow& row : r.cost->rows)
            if (!row.passes()) costs.push_back(&row);
    w.failingImages = images.size();
    w.failingCostRows = costs.size();
    if (!always && images.empty() && costs.empty() && r.skipped.empty()) return w;

    std::filesystem::create_directories(dir);
    OutputSet out;
    auto stagePng = [&](const std::string& name, int width, int height,
                        const std::vector<uint8_t>& rgb) {
        const std::string path = (std::filesystem::path(dir) / name).string();
        out.stage(path, encodePng(path, width, height, rgb));
        w.files.push_back(path);
    };
    std::string page = std::string(
                           "<!doctype html><meta charset=\"utf-8\"><title>octrace "
                           "regression</title><style>") +
                       kStyle + "</style><h1>octrace validate: " +
                       (r.passes() ? (r.skipped.empty() ? "PASS" : "INCOMPLETE") : "FAIL") +
                       "</h1>";
    for (const SkippedBackend& b : r.skipped)
        page += "<p>Skipped backend <b>" + xmlEscape(b.name) + "</b>: " + xmlEscape(b.why) +
                " (not run, so not a pass).</p>";
    if (r.golden) {
        page += fmt("<h2>Golden images: %zu of %zu comparisons fail</h2>", images.size(),
                    r.golden->rows.size());
        page +=
            "<p>d: a pixel's largest channel difference, in 1/255 steps. Diff: <span class=key "
            "style=\"background:#555\"></span> d = 0 (the golden, dimmed) <span class=key "
            "style=\"background:rgb(40,110,255)\"></span> d within the backend's channel "
            "tolerance <span class=key style=\"background:red\"></span> d over it, counted by "
            "the rule.</p>";
        for (const GoldenRow* row : images) {
            const std::string title = "<h3>" + xmlEscape(row->scene) + " (view " +
                                      xmlEscape(row->view) + "): " + xmlEscape(row->tracer) +
                                      " on " + xmlEscape(row->backend) + "</h3>";
            if (row->missing) {
                page += title + "<p>No golden image for this frame: rerun with --update.</p>";
                continue;
            }
            const int channel = row->tolerance.channel;
            const std::string stem = safeName(row->file + "-" + row->tracer + "-" + row->backend);
            const GoldenImages& im = row->images;
            stagePng(stem + "-actual.png", im.width, im.height, im.actual);
            stagePng(stem + "-golden.png", im.goldenWidth, im.goldenHeight, im.golden);
            const std::vector<uint8_t> diff = goldenDiffImage(im, channel);
            if (!diff.empty()) stagePng(stem + "-diff.png", im.goldenWidth, im.goldenHeight, diff);
            page +=
                title + "<p>" +
                (row->diff.sizeMismatch
                     ? fmt("The frame is %dx%d, the golden %dx%d: no diff.", im.width, im.height,
                           im.goldenWidth, im.goldenHeight)
                     : fmt("%llu of %llu pixels differ, %llu over %d/255 (the rule allows "
                           "%.0f, %s's); largest %d/255 at (%d, %d).",
                           (unsigned long long)row->diff.differing,
                           (unsigned long long)row->diff.pixels, (unsigned long long)row->diff.over,
                           channel, row->tolerance.maxOverFraction * double(row->diff.pixels),
                           row->backend.c_str(), row->diff.maxDiff, row->diff.worstX,
                           row->diff.worstY)) +
                "</p><table><tr><th>this build</th><th>golden</th><th>diff</th></tr><tr>";
            for (const char* kind : {"actual", "golden", "diff"})
                page += (std::string(kind) == "diff" && diff.empty())
                            ? std::string("<td>—</td>")
                            : "<td><img src=\"" + xmlEscape(stem) + "-" + kind + ".png\"></td>";
            page += "</tr></table>";
        }
    }
    if (r.cost) {
        page += fmt("<h2>Cost baselines: %zu of %zu rows fail (above %+.0f%%, or missing)</h2>",
                    costs.size(), r.cost->rows.size(), 100.0 * r.cost->tolerance);
        if (!costs.empty()) {
            page +=
                "<table><tr><th>scene</th><th>view</th><th>layout</th><th>backend</th><th>verdict</"
                "th><th>"
                "baseline nodes / prims per pixel</th><th>now</th><th>change nodes, "
                "prims</th></tr>";
            for (const CostRow* c : costs)
                page += "<tr><td>" + xmlEscape(c->scene) + "</td><td>" + xmlEscape(c->view) +
                        "</td><td>" + xmlEscape(c->layout) + "</td><td>" + xmlEscape(c->backend) +
                        "</td><td>" + costVerdictName(c->verdict) + "</td><td>" +
                        costCell(c->baseline) + "</td><td>" + costCell(c->now) + "</td><td>" +
                        fmt("%+.2f%%, %+.2f%%", 100.0 * c->nodesChange, 100.0 * c->primsChange) +
                        "</td></tr>";
            page += "</table>";
        }
    }
    const std::string index = (std::filesystem::path(dir) / "index.html").string();
    out.stage(index, page.data(), page.size());
    w.files.insert(w.files.begin(), index);
    out.commit();
    return w;
}

}  // namespace oct
