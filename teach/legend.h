// The label band under a teaching image: what the picture shows, named in the picture itself,
// so a slide or a printed lab sheet cannot lose it. White band, dark text, below the picture.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "teach/image.h"

namespace oct {

struct Legend {
    std::string title;                  // what the pixels mean
    std::vector<std::string> subtitle;  // layout, scene, size, build parameters
    // A continuous colour bar from `barLow` (left) to `barHigh` (right), when barLow is set.
    ColourMap barMap = ColourMap::Inferno;
    std::string barLow, barMid, barHigh;
    // Discrete swatches (colour, label) in rows after `swatchPrefix`, when not empty; a row too
    // long for the band continues on the next one.
    std::string swatchPrefix;
    std::vector<std::pair<Rgb8, std::string>> swatches;
    std::vector<std::string> notes;  // statistics and caveats, after the bar
};

// Narrowest band (and so image) a legend is drawn at: a 64-pixel render still gets a readable
// label; the picture is centred above a wider band.
constexpr int kMinLegendWidth = 384;

// The picture with the legend band appended below it. Lines wrap at spaces. The picture keeps
// the top-left corner (a wider band extends to its right), so a pixel read off the PNG is the
// frame's pixel: the one `octrace explain --pixel x,y` traces.
RgbImage withLegend(const RgbImage& picture, const Legend& legend);

}  // namespace oct
