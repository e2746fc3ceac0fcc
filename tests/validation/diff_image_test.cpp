// validate's difference image (validation/report/diff_image.h) on hand-made validations: a few
// wrong pixels are ringed so that one is visible in a large image; many are not, so the rings
// do not paint a mostly right picture red.
#include "validation/report/diff_image.h"

#include <gtest/gtest.h>

namespace oct {
namespace {

// A w x h validation where every pixel's hit agrees exactly (dark grey), but those listed.
FilmValidation agreeing(int w, int h) {
    FilmValidation v;
    v.width = w;
    v.height = h;
    v.primaryClass.assign(size_t(w) * h, uint8_t(HitClass::Agree));
    v.shadowClass.assign(size_t(w) * h, 255);
    v.relativeDt.assign(size_t(w) * h, 0.0f);
    return v;
}

void markWrong(FilmValidation& v, int x, int y) {
    v.primaryClass[size_t(y) * v.width + x] = uint8_t(HitClass::Wrong);
}

bool red(const std::vector<uint8_t>& rgb, int w, int x, int y) {
    const uint8_t* p = &rgb[3 * (size_t(y) * w + x)];
    return p[0] == 255 && p[1] == 0 && p[2] == 0;
}

TEST(DiffImage, AFewWrongPixelsAreRinged) {
    FilmValidation v = agreeing(64, 64);
    markWrong(v, 30, 30);
    const DiffMarks m = diffMarks(v);
    EXPECT_EQ(m.wrongPrimary, 1u);
    EXPECT_TRUE(m.ringed);
    const std::vector<uint8_t> img = diffImage(v, 1e-5);
    EXPECT_TRUE(red(img, 64, 30, 30));
    EXPECT_TRUE(red(img, 64, 33, 30));   // on the ring
    EXPECT_FALSE(red(img, 64, 31, 30));  // inside it: the pixel's neighbours stay visible
}

TEST(DiffImage, ManyWrongPixelsAreNotRinged) {
    // Every 7th pixel of a row, every 5th row wrong: 2 % of the image, as the sheet's fault.
    FilmValidation v = agreeing(140, 100);
    uint64_t wrong = 0;
    for (int y = 0; y < v.height; y += 5)
        for (int x = 0; x < v.width; x += 7, ++wrong) markWrong(v, x, y);
    const DiffMarks m = diffMarks(v);
    EXPECT_EQ(m.wrongPrimary, wrong);
    EXPECT_FALSE(m.ringed);
    const std::vector<uint8_t> img = diffImage(v, 1e-5);
    uint64_t reds = 0;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) reds += red(img, v.width, x, y);
    EXPECT_EQ(reds, wrong) << "only the wrong pixels are red";
}

}  // namespace
}  // namespace oct
