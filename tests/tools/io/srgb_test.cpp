#include "tools/io/srgb.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>


namespace pelt::io {
namespace {

TEST(Srgb, ReferenceValues) {
  EXPECT_EQ(linear_to_srgb8(0.0f), 0);
  EXPECT_EQ(linear_to_srgb8(-1.0f), 0);
  EXPECT_EQ(linear_to_srgb8(NAN), 0);
  EXPECT_EQ(linear_to_srgb8(1.0f), 255);
  EXPECT_EQ(linear_to_srgb8(INFINITY), 255);
  EXPECT_EQ(linear_to_srgb8(0.5f), 188);     // 255 * 0.735357 = 187.52
  EXPECT_EQ(linear_to_srgb8(0.0031308f), 10);  // 255 * 0.04045 = 10.31
  EXPECT_EQ(linear_to_srgb8(0.18f), 118);    // 255 * 0.461356 = 117.65
  EXPECT_EQ(linear_to_unorm8(0.5f), 128);    // 127.5 rounds half up
  EXPECT_EQ(linear_to_unorm8(0.2f), 51);
}

TEST(Srgb, DecodeInvertsEncode) {
  for (int b = 0; b < 256; ++b) EXPECT_EQ(linear_to_srgb8(srgb8_to_linear(static_cast<uint8_t>(b))), b) << b;
  EXPECT_EQ(srgb8_to_linear(0), 0.0f);
  EXPECT_EQ(srgb8_to_linear(255), 1.0f);
}

TEST(Srgb, FastMatchesExactAtEveryByteBoundary) {
  for (int b = 0; b < 255; ++b) {
    const float t = srgb8_threshold(b);
    const float below = std::nextafter(t, 0.0f);
    EXPECT_EQ(linear_to_srgb8(t), b + 1) << b;
    EXPECT_EQ(linear_to_srgb8(below), b) << b;
    EXPECT_EQ(linear_to_srgb8_fast(t), b + 1) << b;
    EXPECT_EQ(linear_to_srgb8_fast(below), b) << b;
  }
}

TEST(Srgb, FastMatchesExactOnADenseSweep) {
  // Every 13th float bit pattern in [0, 1] (about 82 million values), plus the
  // special values around it.
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  size_t mismatches = 0;
  for (uint32_t bits = 0; bits <= one; bits += 13) {
    const float x = std::bit_cast<float>(bits);
    mismatches += linear_to_srgb8_fast(x) != linear_to_srgb8(x);
  }
  EXPECT_EQ(mismatches, 0u);
  for (float x : {-0.0f, -1e-30f, std::nextafter(1.0f, 2.0f), 2.0f, NAN, -INFINITY, INFINITY,
                  std::numeric_limits<float>::denorm_min()})
    EXPECT_EQ(linear_to_srgb8_fast(x), linear_to_srgb8(x)) << x;
}

TEST(Srgb, EncodeRowsHandlesAlphaAndStrides) {
  // 2 rows of 2 RGBA pixels, source rows padded to 10 floats, destination to 9 bytes.
  std::vector<float> src = {0.5f, 0.18f, 1.0f, 0.5f, 0.0f, 2.0f, -1.0f, 0.2f, 9, 9,
                            0.25f, 0.75f, 0.0031308f, 1.0f, 1.0f, 0.0f, 0.5f, 0.0f, 9, 9};
  std::vector<uint8_t> dst(18, 7);
  encode_srgb8_rows(src.data(), 10, dst.data(), 9, 2, 2, 4, Alpha::straight);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 4; ++c) {
        const float v = src[y * 10 + x * 4 + c];
        EXPECT_EQ(dst[y * 9 + x * 4 + c], c == 3 ? linear_to_unorm8(v) : linear_to_srgb8(v));
      }
  EXPECT_EQ(dst[8], 7);  // padding untouched
  EXPECT_EQ(dst[17], 7);
}

// A render's colour is premultiplied; an 8-bit file holds straight colour: divided by alpha
// where alpha lies in (0, 1), 0 where alpha is 0 (or NaN), as it is where alpha is 1.
TEST(Srgb, EncodeRowsDividesPremultipliedColourByAlpha) {
  const std::vector<float> src = {0.25f, 0.1f,  0.0f, 0.5f,   // half covered: straight 0.5, 0.2, 0
                                  0.3f,  0.2f,  0.1f, 0.0f,   // alpha 0: colour undefined, written 0
                                  0.3f,  0.2f,  0.1f, 1.0f,   // opaque: as it is, bit for bit
                                  0.02f, 0.01f, 0.0f, 0.01f,  // a faint fringe: straight 2, 1, 0
                                  0.4f,  0.4f,  0.4f, NAN};
  std::vector<uint8_t> dst(src.size());
  encode_srgb8_rows(src.data(), src.size(), dst.data(), dst.size(), 5, 1, 4, Alpha::premultiplied);
  const float want[5][3] = {{0.5f, 0.2f, 0.0f}, {0, 0, 0}, {0.3f, 0.2f, 0.1f}, {2.0f, 1.0f, 0.0f}, {0, 0, 0}};
  for (int p = 0; p < 5; ++p) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(dst[4 * p + c], linear_to_srgb8(want[p][c])) << p << " " << c;
    EXPECT_EQ(dst[4 * p + 3], linear_to_unorm8(src[4 * p + 3])) << p;
  }
  // Grey and alpha alike.
  const float ga[4] = {0.1f, 0.5f, 0.7f, 0.0f};
  uint8_t gb[4];
  encode_srgb8_rows(ga, 4, gb, 4, 2, 1, 2, Alpha::premultiplied);
  EXPECT_EQ(gb[0], linear_to_srgb8(0.2f));
  EXPECT_EQ(gb[2], 0);
}

// encode_srgb8_span is raster::srgb_bytes (compared with the scalar search on every target in
// tests/raster/srgb_kernels_test.cpp); here, that io's scalar and span encoders agree.
TEST(Srgb, SpanMatchesScalarOnASweep) {
  std::vector<float> x;
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  for (uint32_t bits = 0; bits <= one; bits += 997) x.push_back(std::bit_cast<float>(bits));
  for (float v : {-1.0f, 2.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()})
    x.push_back(v);
  std::vector<uint8_t> out(x.size(), 0xAB);
  encode_srgb8_span(x.data(), out.data(), x.size());
  size_t bad = 0;
  for (size_t i = 0; i < x.size(); ++i) bad += out[i] != linear_to_srgb8_fast(x[i]);
  EXPECT_EQ(bad, 0u);
}

}  // namespace
}  // namespace pelt::io
