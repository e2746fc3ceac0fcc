// Cost heat maps: the per-pixel work of a frame (the Film's boxes tested or primitives tested,
// primary and shadow ray together; the paper's cost measure) as an inferno colour map with a
// legend naming the quantity, the layout and the scale. With a fixed scale maximum, images of
// different layouts use the same colours for the same cost and so compare honestly.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/geometry/vec3.h"
#include "core/render/film.h"
#include "teach/image.h"
#include "teach/legend.h"

namespace oct {

enum class CostQuantity : uint8_t { Nodes, Prims };

// "boxes" (or its old name "nodes") or "prims"; throws TeachError naming `option` and the value
// otherwise.
CostQuantity parseCostQuantity(const std::string& text, const std::string& option);
const char* costQuantityName(CostQuantity q);  // "boxes" / "prims"

struct CostStats {
    uint32_t min = 0, max = 0;
    double mean = 0.0;
    uint32_t p99 = 0;       // 99th percentile (nearest rank)
    uint32_t scaleMax = 0;  // the colour bar's top: the requested maximum, else p99
    uint64_t clipped = 0;   // pixels above scaleMax (drawn in the top colour)
};

// Statistics of one cost array. scaleMax 0 means automatic: the image's 99th percentile, so a
// few extreme pixels (grazing rays) do not push every other pixel into the darkest colours;
// the pixels above it are counted and named in the legend.
CostStats costStats(const Film& film, CostQuantity q, uint32_t scaleMax);

struct HeatmapSpec {
    CostQuantity quantity = CostQuantity::Nodes;
    uint32_t scaleMax = 0;      // 0: the image's 99th percentile (--heatmap-max N fixes it)
    std::string layout;         // named in the legend
    std::string scene;          // named in the legend
    std::string details;        // a further legend line (build parameters), may be empty
    std::optional<Vec3> light;  // the frame's point light, named in the legend when set
};

// The heat map with its legend (colour bar 0 .. scale max, the image's min / mean / max, the
// number of pixels above the scale). Cost 0 maps to the bottom colour, scaleMax and above to the
// top.
RgbImage heatmapImage(const Film& film, const HeatmapSpec& spec, CostStats* stats = nullptr);
// The legend heatmapImage draws under the picture (stats: costStats of the same film and spec).
Legend heatmapLegend(const Film& film, const HeatmapSpec& spec, const CostStats& stats);

}  // namespace oct
