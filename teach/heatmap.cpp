#include "teach/heatmap.h"

#include <algorithm>
#include <cstdio>

#include "teach/legend.h"
#include "teach/teach_error.h"

namespace oct {

CostQuantity parseCostQuantity(const std::string& text, const std::string& option) {
    // "nodes" was the name of boxes tested before the words of docs/TEACHING.md ("Words").
    if (text == "boxes" || text == "nodes") return CostQuantity::Nodes;
    if (text == "prims") return CostQuantity::Prims;
    throw TeachError(option + " '" + text +
                     "' names no cost: boxes (boxes tested) or prims (primitives tested)");
}

const char* costQuantityName(CostQuantity q) {
    return q == CostQuantity::Nodes ? "boxes" : "prims";
}

namespace {

std::string point(Vec3 p) {
    char b[96];
    std::snprintf(b, sizeof b, "(%g, %g, %g)", p.x, p.y, p.z);
    return b;
}

const std::vector<uint32_t>& costArray(const Film& film, CostQuantity q) {
    return q == CostQuantity::Nodes ? film.nodes : film.primsTested;
}

}  // namespace

CostStats costStats(const Film& film, CostQuantity q, uint32_t scaleMax) {
    const std::vector<uint32_t>& v = costArray(film, q);
    CostStats s;
    if (v.empty()) return s;
    s.min = *std::min_element(v.begin(), v.end());
    s.max = *std::max_element(v.begin(), v.end());
    double sum = 0.0;
    for (uint32_t c : v) sum += c;
    s.mean = sum / double(v.size());
    std::vector<uint32_t> sorted = v;
    const size_t rank = (sorted.size() * 99 + 99) / 100;  // nearest rank: ceil(0.99 n)
    std::nth_element(sorted.begin(), sorted.begin() + (rank - 1), sorted.end());
    s.p99 = sorted[rank - 1];
    s.scaleMax = scaleMax > 0 ? scaleMax : s.p99;
    for (uint32_t c : v) s.clipped += c > s.scaleMax;
    return s;
}

Legend heatmapLegend(const Film& film, const HeatmapSpec& spec, const CostStats& s) {
    Legend legend;
    legend.title = spec.quantity == CostQuantity::Nodes ? "Node boxes tested per pixel"
                                                        : "Primitives tested per pixel";
    legend.subtitle.push_back(spec.layout + " | " + spec.scene + " | " +
                              std::to_string(film.width) + "x" + std::to_string(film.height) +
                              " | primary + shadow ray");
    if (!spec.details.empty()) legend.subtitle.push_back(spec.details);
    // The shadow ray's cost depends on where the light is (a side light leaves dark patches).
    if (spec.light) legend.subtitle.push_back("light at " + point(*spec.light));
    legend.barMap = ColourMap::Inferno;
    legend.barLow = "0";
    legend.barMid = std::to_string(s.scaleMax / 2);
    legend.barHigh = std::to_string(s.scaleMax) + (spec.scaleMax > 0 ? " (fixed)" : " (99th pct)");
    char line[160];
    std::snprintf(line, sizeof line, "image: min %u  mean %.1f  max %u", s.min, s.mean, s.max);
    legend.notes.push_back(line);
    if (s.clipped > 0) {
        std::snprintf(line, sizeof line, "%llu pixels above %u: top colour",
                      (unsigned long long)s.clipped, s.scaleMax);
        legend.notes.push_back(line);
    }
    if (s.max == 0) legend.notes.push_back("every pixel is 0: this layout has no nodes to visit");
    legend.notes.push_back(
        "pixel x,y of this PNG (from the top left) is octrace explain's "
        "--pixel x,y");
    return legend;
}

RgbImage heatmapImage(const Film& film, const HeatmapSpec& spec, CostStats* statsOut) {
    const CostStats s = costStats(film, spec.quantity, spec.scaleMax);
    const std::vector<uint32_t>& v = costArray(film, spec.quantity);
    RgbImage picture(film.width, film.height, {0, 0, 0});
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const uint32_t c = v[size_t(y) * film.width + x];
            // An all-zero image (exhaustive tracing visits no nodes) stays at the bottom colour.
            const double u = s.scaleMax > 0 ? double(c) / double(s.scaleMax) : 0.0;
            picture.set(x, y, mapColour(ColourMap::Inferno, u));
        }
    if (statsOut) *statsOut = s;
    return withLegend(picture, heatmapLegend(film, spec, s));
}

}  // namespace oct
