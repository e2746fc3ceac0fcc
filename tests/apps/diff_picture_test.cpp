// The legend of validate's difference image (apps/diff_picture.h): every colour the image can
// hold is named, with the counts that carry it and whether the wrong pixels are ringed.
#include "apps/diff_picture.h"

#include <gtest/gtest.h>

namespace oct {
namespace {

std::string legendText(const Legend& l) {
    std::string s = l.title + "\n";
    for (const std::string& t : l.subtitle) s += t + "\n";
    for (const auto& [colour, label] : l.swatches)
        s += "[" + std::to_string(colour.r) + "," + std::to_string(colour.g) + "," +
             std::to_string(colour.b) + "] " + label + "\n";
    for (const std::string& t : l.notes) s += t + "\n";
    return s;
}

TEST(DiffPicture, TheLegendNamesEveryColourAndTheCounts) {
    DiffMarks m;
    m.pixels = 65536;
    m.wrongPrimary = 1355;
    m.ambiguousPrimary = 2;
    m.ringed = false;
    const std::string text = legendText(diffLegend(m, 1e-5));
    for (const char* says :
         {"[0,0,0] both miss", "[40,40,40] same t", "[255,0,0] wrong", "[255,0,255] wrong shadow",
          "[255,140,0] ambiguous", "1355 wrong", "not ringed", "1e-05"})
        EXPECT_NE(text.find(says), std::string::npos) << says << " in\n" << text;
    m.wrongPrimary = 3;
    m.ringed = true;
    EXPECT_NE(legendText(diffLegend(m, 1e-5)).find("ringed"), std::string::npos);
}

}  // namespace
}  // namespace oct
