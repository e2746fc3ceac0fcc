#include "teach/legend.h"

#include <algorithm>

namespace oct {
namespace {

constexpr Rgb8 kBand = {255, 255, 255};
constexpr Rgb8 kInk = {20, 20, 24};
constexpr Rgb8 kGreyInk = {90, 90, 100};

// One line of text in the band.
struct Line {
    std::string text;
    int scale;
    Rgb8 colour;
};

// Breaks `text` at spaces into lines of at most `width` pixels at `scale`; a word longer than
// a line is cut by fitText.
void wrap(const std::string& text, int width, int scale, Rgb8 colour, std::vector<Line>& out) {
    auto flush = [&](std::string l) {
        const int s = fitText(l, width, scale);
        out.push_back({l, s, colour});
    };
    std::string line;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t end = text.find(' ', pos);
        if (end == std::string::npos) end = text.size();
        const std::string word = text.substr(pos, end - pos);
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && textWidth(candidate, scale) > width) {
            flush(line);
            line = word;
        } else {
            line = candidate;
        }
        pos = end + 1;
    }
    if (!line.empty()) flush(line);
}

}  // namespace

RgbImage withLegend(const RgbImage& picture, const Legend& legend) {
    const int width = std::max(picture.width, kMinLegendWidth);
    // Text scale: 2 from 512 pixels wide up (readable on a slide), 1 below, 3 from 1200.
    const int scale = std::clamp(width / 400 + 1, 1, 3);
    const int pad = 4 * scale;
    const int inner = width - 2 * pad;

    std::vector<Line> top;
    wrap(legend.title, inner, scale, kInk, top);
    for (const std::string& s : legend.subtitle) wrap(s, inner, scale, kGreyInk, top);
    std::vector<Line> bottom;
    for (const std::string& s : legend.notes) wrap(s, inner, scale, kGreyInk, bottom);
    const bool bar = !legend.barLow.empty();
    const int barHeight = bar ? 10 * scale : 0;
    const int labelScale = scale;
    // The swatches' rows: each swatch's x, and the row it is on.
    const int box = textHeight(labelScale) - 2 * labelScale;
    const int swatchStart =
        pad +
        (legend.swatchPrefix.empty() ? 0 : textWidth(legend.swatchPrefix, labelScale) + 2 * pad);
    std::vector<std::pair<int, int>> swatchAt;  // (x, row)
    int rows = 0;
    for (int i = 0, x = swatchStart; i < int(legend.swatches.size()); ++i) {
        const int w =
            box + labelScale * 3 + textWidth(legend.swatches[i].second, labelScale) + 2 * pad;
        if (x + w > width && x > swatchStart) {
            x = swatchStart;
            ++rows;
        }
        swatchAt.push_back({x, rows});
        x += w;
    }
    const int swatchRow = textHeight(labelScale) + pad;
    const int swatchHeight = legend.swatches.empty() ? 0 : (rows + 1) * swatchRow;

    int band = pad;
    for (const Line& l : top) band += textHeight(l.scale);
    if (bar) band += pad + barHeight + 2 + textHeight(labelScale);
    if (swatchHeight) band += pad + swatchHeight;
    for (const Line& l : bottom) band += textHeight(l.scale);
    band += pad;

    RgbImage out(width, picture.height + band, kBand);
    out.paste(picture, 0, 0);  // top left: PNG pixel (x, y) is the frame's pixel (x, y)
    int y = picture.height + pad;
    for (const Line& l : top) {
        drawText(out, pad, y, l.text, l.colour, l.scale);
        y += textHeight(l.scale);
    }
    if (bar) {
        y += pad;
        for (int x = 0; x < inner; ++x) {
            const Rgb8 c = mapColour(legend.barMap, inner > 1 ? double(x) / (inner - 1) : 0.0);
            out.fillRect(pad + x, y, pad + x + 1, y + barHeight, c);
        }
        // Tick marks at both ends and the middle.
        for (int x : {pad, pad + inner / 2, pad + inner - 1})
            out.fillRect(x, y + barHeight, x + 1, y + barHeight + 2 + scale, kInk);
        y += barHeight + 2;
        drawText(out, pad, y, legend.barLow, kInk, labelScale);
        if (!legend.barMid.empty())
            drawText(out, pad + inner / 2 - textWidth(legend.barMid, labelScale) / 2, y,
                     legend.barMid, kInk, labelScale);
        drawText(out, pad + inner - textWidth(legend.barHigh, labelScale), y, legend.barHigh, kInk,
                 labelScale);
        y += textHeight(labelScale);
    }
    if (swatchHeight) {
        y += pad;
        if (!legend.swatchPrefix.empty())
            drawText(out, pad, y, legend.swatchPrefix, kInk, labelScale);
        for (size_t i = 0; i < legend.swatches.size(); ++i) {
            const auto& [colour, label] = legend.swatches[i];
            const auto [x, row] = swatchAt[i];
            const int sy = y + row * swatchRow;
            out.fillRect(x, sy, x + box, sy + box, colour);
            drawText(out, x + box + 3 * labelScale, sy, label, kInk, labelScale);
        }
        y += swatchHeight;
    }
    for (const Line& l : bottom) {
        drawText(out, pad, y, l.text, l.colour, l.scale);
        y += textHeight(l.scale);
    }
    return out;
}

}  // namespace oct
