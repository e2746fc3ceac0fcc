// A frame's band (core/render/camera.h): the Film rows of K bands dealt in blocks of B image rows
// cover every image row once, and filmRowOf undoes imageRowOf, so renderPixel writes each pixel of
// a band into the Film row the band's loop gave it.
#include <gtest/gtest.h>

#include <vector>

#include "core/render/camera.h"

namespace oct {
namespace {

TEST(FrameBand, BandsDealtInBlocksCoverTheImageOnceAndMapBack) {
    for (int height : {1, 2, 7, 37, 512})
        for (int ranks : {1, 2, 3, 5})
            for (int block : {1, 2, 4, 16}) {
                std::vector<int> seen(size_t(height), 0);
                for (int r = 0; r < ranks; ++r) {
                    FrameParams p{};
                    p.height = height;
                    p.bandBegin = r * block;
                    p.bandBlock = block;
                    p.bandStride = block * ranks;
                    int rows = 0;  // the band's rows: its blocks' rows below the image's end
                    for (int b = r * block; b < height; b += block * ranks)
                        rows += std::min(block, height - b);
                    if (rows == 0) continue;
                    p.bandRows = rows;
                    EXPECT_EQ(frameRows(p), rows);
                    for (int j = 0; j < rows; ++j) {
                        const int y = imageRowOf(p, j);
                        ASSERT_GE(y, 0);
                        ASSERT_LT(y, height) << "band " << r << " row " << j;
                        ++seen[size_t(y)];
                        EXPECT_EQ(filmRowOf(p, y), j);
                    }
                }
                for (int y = 0; y < height; ++y)
                    EXPECT_EQ(seen[size_t(y)], 1) << "row " << y << " of " << height << ", "
                                                  << ranks << " bands of blocks of " << block;
            }
}

TEST(FrameBand, NoBandIsTheWholeImage) {
    FrameParams p{};
    p.height = 9;
    EXPECT_EQ(frameRows(p), 9);
    for (int y = 0; y < 9; ++y) {
        EXPECT_EQ(imageRowOf(p, y), y);
        EXPECT_EQ(filmRowOf(p, y), y);
    }
}

}  // namespace
}  // namespace oct
