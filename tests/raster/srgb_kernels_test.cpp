// raster::srgb_bytes, the SIMD sRGB encoder behind colour maps' level 0 and the 8-bit image
// writes, against the scalar table search srgb_byte (itself checked against the pow
// reference in texture_test.cpp), on every compiled target the machine runs.
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "raster/texture.h"
#include "tests/hwy_targets.h"

namespace pelt::raster {
namespace {

using pelt::test::for_each_target;

size_t mismatches(const std::vector<float>& x) {
  std::vector<uint8_t> out(x.size(), 0xAB);
  srgb_bytes(x.data(), out.data(), x.size());
  size_t bad = 0;
  for (size_t i = 0; i < x.size(); ++i) bad += out[i] != srgb_byte(double(x[i]));
  return bad;
}

TEST(SrgbKernel, MatchesScalarAroundEveryByteBoundary) {
  // Each boundary and the two floats on either side of it: the single compare's edge.
  std::vector<float> x;
  for (int b = 0; b < 255; ++b) {
    float f = srgb_float_threshold(b);
    for (int k = 0; k < 2; ++k) f = std::nextafter(f, 0.0f);
    for (int k = 0; k < 5; ++k, f = std::nextafter(f, 2.0f)) x.push_back(f);
  }
  for_each_target([&](const std::string& target) { EXPECT_EQ(mismatches(x), 0u) << target; });
}

TEST(SrgbKernel, ThresholdsAreTheFirstFloatOfEachByte) {
  for (int b = 0; b < 255; ++b) {
    const float t = srgb_float_threshold(b);
    EXPECT_EQ(srgb_byte(double(t)), b + 1) << b;
    EXPECT_EQ(srgb_byte(double(std::nextafter(t, 0.0f))), b) << b;
  }
}

TEST(SrgbKernel, MatchesScalarOnASweepAndHardValues) {
  std::vector<float> x;
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  for (uint32_t bits = 0; bits <= one; bits += 61) x.push_back(std::bit_cast<float>(bits));
  const float floor_value = float(SrgbBoundaries::kFloor);
  for (float v : {-0.0f, -1e-30f, -1.0f, -FLT_MAX, std::nextafter(1.0f, 0.0f), 1.0f, std::nextafter(1.0f, 2.0f),
                  2.0f, FLT_MAX, std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::denorm_min(), FLT_MIN, std::nextafter(floor_value, 0.0f), floor_value,
                  std::nextafter(floor_value, 1.0f), 0.0031308f, 0.5f})
    x.push_back(v);
  for_each_target([&](const std::string& target) { EXPECT_EQ(mismatches(x), 0u) << target; });
}

TEST(SrgbKernel, HandlesEveryLengthAndOffset) {
  // Lengths around the vector widths, from unaligned starts: the scalar tail and the
  // unaligned loads, and nothing written past the end.
  std::vector<float> src(80);
  for (size_t i = 0; i < src.size(); ++i) src[i] = float(i) / 79.0f;
  for_each_target([&](const std::string& target) {
    for (size_t offset = 0; offset < 3; ++offset)
      for (size_t n = 0; n + offset <= 67; ++n) {
        std::vector<uint8_t> out(n + 1, 0xCD);
        srgb_bytes(src.data() + offset, out.data(), n);
        for (size_t i = 0; i < n; ++i)
          ASSERT_EQ(out[i], srgb_byte(double(src[offset + i]))) << target << " n " << n << " i " << i;
        ASSERT_EQ(out[n], 0xCD) << target << " wrote past n = " << n;
      }
  });
}

}  // namespace
}  // namespace pelt::raster
