// Image error on hand-made images whose answers are known: identical images, one channel
// of one pixel off by a known number of 8-bit steps, alpha and clamping.
#include "tools/tradeoff/image_compare.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "tools/io/srgb.h"

namespace pelt::tradeoff {
namespace {

// A w x h linear RGBA image whose every pixel encodes to the sRGB bytes (r, g, b) and alpha 1.
std::vector<float> flat(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<float> img;
  for (int i = 0; i < w * h; ++i)
    for (float v : {io::srgb8_to_linear(r), io::srgb8_to_linear(g), io::srgb8_to_linear(b), 1.0f}) img.push_back(v);
  return img;
}

void set_byte(std::vector<float>& img, int w, int x, int y, int c, uint8_t b) {
  img[(size_t(y) * w + x) * 4 + c] = io::srgb8_to_linear(b);
}

DisplayImage display(int w, int h, const std::vector<float>& img) { return to_display(w, h, img); }

// A render's colour is premultiplied; the PNG holds it straight.
TEST(TradeoffImageCompare, ToDisplayEncodesLikeThePngWriter) {
  const std::vector<float> px = {0.05f, -1.0f, 2.0f, 0.25f, 0.0031308f, NAN, 1.0f, 1.0f};
  const DisplayImage d = to_display(2, 1, px);
  ASSERT_EQ(d.rgba.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    const float a = px[i / 4 * 4 + 3];
    const bool alpha = i % 4 == 3;
    EXPECT_EQ(d.rgba[i], alpha ? io::linear_to_unorm8(px[i]) : io::linear_to_srgb8(px[i] / a)) << i;
  }
  EXPECT_EQ(d.rgba[0], io::linear_to_srgb8(0.2f));  // 0.05 at alpha 0.25
  EXPECT_EQ(d.rgba[1], 0);    // negative clamps to 0
  EXPECT_EQ(d.rgba[2], 255);  // above 1 clamps to 1
  EXPECT_EQ(d.rgba[5], 0);    // NaN is 0
}

TEST(TradeoffImageCompare, ToDisplayRejectsAWrongSize) {
  const std::vector<float> px(4 * 5, 0.5f);
  EXPECT_THROW(to_display(2, 3, px), std::invalid_argument);
  EXPECT_THROW(to_display(0, 5, px), std::invalid_argument);
}

TEST(TradeoffImageCompare, IdenticalImagesHaveZeroErrorAndInfinitePsnr) {
  const DisplayImage a = display(10, 10, flat(10, 10, 30, 140, 250));
  const ImageError e = compare(a, a);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_TRUE(std::isinf(e.psnr_db) && e.psnr_db > 0);
  EXPECT_EQ(e.max_abs, 0.0);
  EXPECT_EQ(e.share_over_1_255, 0.0);
}

TEST(TradeoffImageCompare, OnePixelTwoStepsOffInOneChannel) {
  const std::vector<float> ref = flat(10, 10, 100, 100, 100);
  std::vector<float> img = ref;
  set_byte(img, 10, 3, 7, 1, 102);
  const ImageError e = compare(display(10, 10, img), display(10, 10, ref));
  EXPECT_DOUBLE_EQ(e.share_over_1_255, 0.01);
  EXPECT_NEAR(e.max_abs, 2.0 / 255.0, 1e-7);
  // 300 channel values, one of them 2/255 off.
  const double rmse = std::sqrt((2.0 / 255.0) * (2.0 / 255.0) / 300.0);
  EXPECT_NEAR(e.rmse, rmse, 1e-7 * rmse);
  EXPECT_NEAR(e.psnr_db, 20.0 * std::log10(1.0 / rmse), 1e-4);
}

TEST(TradeoffImageCompare, OneStepOffIsNotOverTheThreshold) {
  const std::vector<float> ref = flat(10, 10, 200, 10, 0);
  std::vector<float> img = ref;
  set_byte(img, 10, 0, 0, 0, 201);
  set_byte(img, 10, 9, 9, 2, 1);
  const ImageError e = compare(display(10, 10, img), display(10, 10, ref));
  EXPECT_EQ(e.share_over_1_255, 0.0);
  EXPECT_NEAR(e.max_abs, 1.0 / 255.0, 1e-7);
  EXPECT_GT(e.rmse, 0.0);
}

TEST(TradeoffImageCompare, RmseByHandOverSeveralPixelsAndChannels) {
  // 4x2 image: (0,0) red +10 steps and blue -3 steps; (3,1) green +5 steps, red +2 steps.
  const std::vector<float> ref = flat(4, 2, 50, 60, 70);
  std::vector<float> img = ref;
  set_byte(img, 4, 0, 0, 0, 60);
  set_byte(img, 4, 0, 0, 2, 67);
  set_byte(img, 4, 3, 1, 1, 65);
  set_byte(img, 4, 3, 1, 0, 52);
  const ImageError e = compare(display(4, 2, img), display(4, 2, ref));
  const double sum_sq = (100.0 + 9.0 + 25.0 + 4.0) / (255.0 * 255.0);
  const double rmse = std::sqrt(sum_sq / (8.0 * 3.0));
  EXPECT_NEAR(e.rmse, rmse, 1e-7 * rmse);
  EXPECT_NEAR(e.max_abs, 10.0 / 255.0, 1e-7);
  EXPECT_DOUBLE_EQ(e.share_over_1_255, 2.0 / 8.0);
}

TEST(TradeoffImageCompare, AlphaIsLeftOut) {
  const std::vector<float> ref = flat(3, 3, 20, 40, 60);
  DisplayImage img = display(3, 3, ref);
  for (size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 0;
  const ImageError e = compare(img, display(3, 3, ref));
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.share_over_1_255, 0.0);
}

TEST(TradeoffImageCompare, ValuesBeyondTheDisplayRangeCompareClamped) {
  std::vector<float> ref = flat(2, 2, 255, 0, 255);
  std::vector<float> img = ref;
  img[0] = 7.5f;   // red above 1: still 255
  img[1] = -0.5f;  // green below 0: still 0
  const ImageError e = compare(display(2, 2, img), display(2, 2, ref));
  EXPECT_EQ(e.rmse, 0.0);
}

TEST(TradeoffImageCompare, DifferentSizesAreRefused) {
  const DisplayImage a = display(4, 2, flat(4, 2, 1, 2, 3));
  const DisplayImage b = display(2, 4, flat(2, 4, 1, 2, 3));
  EXPECT_THROW(compare(a, b), std::invalid_argument);
}

}  // namespace
}  // namespace pelt::tradeoff
