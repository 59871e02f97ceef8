// Textures: validation, the mip chain (sizes, area-exact box filter, alpha weighting, sRGB)
// and sampler properties with known answers, on every compiled Highway target.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "raster/parallel.h"
#include "raster/texture.h"
#include "tests/raster/texture_test_helpers.h"

namespace pelt::raster::test {
namespace {

TEST(Texture, LevelSizesFollowOpenGL) {
  const Texture t = random_texture(100, 37, TexelEncoding::Linear, 3);
  const int expect[][2] = {{100, 37}, {50, 18}, {25, 9}, {12, 4}, {6, 2}, {3, 1}, {1, 1}};
  ASSERT_EQ(t.levels(), 7);
  size_t offset = 0;
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(t.level(k).width, expect[k][0]) << k;
    EXPECT_EQ(t.level(k).height, expect[k][1]) << k;
    EXPECT_EQ(t.level(k).stride, expect[k][0] + 1) << k;
    EXPECT_EQ(t.level(k).offset, offset) << k;
    for (int y = 0; y < expect[k][1]; ++y)  // the padding texel repeats the row's first
      EXPECT_EQ(t.level_texels(k)[size_t(y) * size_t(t.level(k).stride) + size_t(expect[k][0])], t.texel(k, 0, y));
    offset += size_t(expect[k][0] + 1) * size_t(expect[k][1]);
  }
  EXPECT_EQ(t.bytes(), offset * 4);
  EXPECT_EQ(random_texture(1, 1, TexelEncoding::Linear, 1).levels(), 1);
  EXPECT_EQ(random_texture(256, 256, TexelEncoding::Linear, 1).levels(), 9);
  EXPECT_EQ(random_texture(1, 8, TexelEncoding::Linear, 1).levels(), 4);
}

TEST(Texture, Level0KeepsTheBytesOfVisibleTexels) {
  std::mt19937 rng(5);
  std::vector<uint8_t> bytes(13 * 6 * 4);
  for (auto& b : bytes) b = uint8_t(rng());
  for (size_t i = 3; i < bytes.size(); i += 12) bytes[i] = 0;  // every third texel transparent
  for (TexelEncoding enc : {TexelEncoding::Linear, TexelEncoding::Srgb}) {
    Texture t;
    ASSERT_FALSE(Texture::from_rgba8(13, 6, bytes.data(), enc, t));
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 13; ++x) {
        const uint8_t* in = &bytes[(size_t(y) * 13 + size_t(x)) * 4];
        EXPECT_EQ(channel(t.texel(0, x, y), 3), in[3]);
        if (in[3] == 0) continue;
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(channel(t.texel(0, x, y), ch), in[ch]);
      }
  }
}

// Every alpha-0 texel of every level carries the colour of the texel covering it one level
// up; visible texels keep theirs.
TEST(Texture, TransparentTexelsTakeTheColourAbove) {
  const Texture t = random_texture(37, 22, TexelEncoding::Srgb, 17);
  int filled = 0;
  for (int k = 0; k + 1 < t.levels(); ++k) {
    const MipLevel& L = t.level(k);
    const MipLevel& P = t.level(k + 1);
    for (int y = 0; y < L.height; ++y)
      for (int x = 0; x < L.width; ++x) {
        const uint32_t texel = t.texel(k, x, y);
        if (channel(texel, 3) != 0) continue;
        ++filled;
        const uint32_t above = t.texel(k + 1, x * P.width / L.width, y * P.height / L.height);
        ASSERT_EQ(texel, above & 0x00FFFFFFu) << "level " << k << " (" << x << ", " << y << ")";
      }
  }
  EXPECT_GT(filled, 100);
}

// SourceAlpha::ignored (colour and normal maps, whose alpha nothing draws): the texture of the
// same colours at alpha 1, byte for byte, whatever the source's alpha (0, partial, or a 4th
// channel outside [0, 1] that is no alpha); colours are validated as before.
TEST(Texture, IgnoredAlphaBuildsTheOpaqueTexture) {
  constexpr int w = 37, h = 21;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> source(size_t(w) * h * 4), opaque;
  for (size_t i = 0; i < source.size(); ++i) source[i] = unit(rng);
  for (size_t t = 0; t < size_t(w) * h; ++t) source[4 * t + 3] = t % 3 == 0 ? 0.0f : t % 3 == 1 ? 0.03f : 5.0f;
  opaque = source;
  for (size_t t = 0; t < size_t(w) * h; ++t) opaque[4 * t + 3] = 1.0f;
  for (TexelEncoding enc : {TexelEncoding::Srgb, TexelEncoding::Linear}) {
    Texture ignored, want, straight;
    ASSERT_FALSE(Texture::from_linear_float(w, h, source.data(), enc, ignored, {}, SourceAlpha::ignored));
    ASSERT_FALSE(Texture::from_linear_float(w, h, opaque.data(), enc, want));
    ASSERT_EQ(ignored.bytes(), want.bytes());
    EXPECT_EQ(std::memcmp(ignored.data(), want.data(), want.bytes()), 0) << "encoding " << int(enc);
    EXPECT_TRUE(Texture::from_linear_float(w, h, source.data(), enc, straight));  // 5.0 is no alpha
  }
  source[1] = 1.5f;  // a colour out of range is still refused
  Texture t;
  const auto e = Texture::from_linear_float(w, h, source.data(), TexelEncoding::Srgb, t, {}, SourceAlpha::ignored);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "rgba[1]");
}

TEST(Texture, RejectsBadInputNamingTheField) {
  Texture t;
  std::vector<uint8_t> bytes(16, 0);
  auto e = Texture::from_rgba8(0, 2, bytes.data(), TexelEncoding::Linear, t);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "width");
  e = Texture::from_rgba8(2, kMaxTextureSide + 1, bytes.data(), TexelEncoding::Linear, t);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "height");
  e = Texture::from_rgba8(2, 2, nullptr, TexelEncoding::Linear, t);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "rgba");
  EXPECT_TRUE(t.empty());

  std::vector<float> f(2 * 2 * 4, 0.5f);
  f[6] = 1.5f;  // texel (1, 0), blue
  e = Texture::from_linear_float(2, 2, f.data(), TexelEncoding::Srgb, t);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "rgba[6]");
  EXPECT_NE(e->reason.find("texel (1, 0) channel b"), std::string::npos) << e->reason;
  f[6] = std::nanf("");
  EXPECT_TRUE(Texture::from_linear_float(2, 2, f.data(), TexelEncoding::Srgb, t));
  f[6] = -0.25f;
  EXPECT_TRUE(Texture::from_linear_float(2, 2, f.data(), TexelEncoding::Linear, t));
  EXPECT_TRUE(t.empty());

  TextureArray arr;
  e = TextureArray::from_rgba8_layers(2, 2, 0, bytes.data(), TexelEncoding::Linear, arr);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "count");
}

// The boundary search against the pow it replaces: on random values, on every boundary's
// neighbours within 64 doubles, and on the edges of the domain.
TEST(Texture, SrgbByteEqualsThePowReference) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 1000000; ++i) {
    const double x = unit(rng);
    ASSERT_EQ(srgb_byte(x), srgb_byte_reference(x)) << x;
  }
  int boundaries = 0;
  for (uint64_t bits = 0; bits <= std::bit_cast<uint64_t>(1.0);) {
    // The next boundary above `bits`: bisection, as the table is built, but independent of it.
    const uint8_t b = srgb_byte_reference(std::bit_cast<double>(bits));
    if (b == 255) break;
    uint64_t lo = bits, hi = std::bit_cast<uint64_t>(1.0);
    while (hi - lo > 1) {
      const uint64_t mid = lo + (hi - lo) / 2;
      (srgb_byte_reference(std::bit_cast<double>(mid)) > b ? hi : lo) = mid;
    }
    for (uint64_t k = hi - std::min<uint64_t>(hi, 64); k <= hi + 64; ++k) {
      const double x = std::bit_cast<double>(k);
      ASSERT_EQ(srgb_byte(x), srgb_byte_reference(x)) << x;
    }
    ++boundaries;
    bits = hi;
  }
  EXPECT_EQ(boundaries, 255);
  for (double x : {0.0, -0.0, -1.0, 1e-320, 0.0031308, 1.0, 1.0000001, 2.0, 1e300})
    EXPECT_EQ(srgb_byte(x), srgb_byte_reference(x)) << x;
  EXPECT_EQ(srgb_byte(std::nan("")), 0);
}

TEST(Texture, SrgbFloatsRoundTripToTheirBytes) {
  // An 8-bit sRGB colour map read as linear floats and stored as Srgb keeps its bytes.
  const float* table = srgb8_to_linear_table();
  std::vector<float> f(256 * 4);
  for (int i = 0; i < 256; ++i) {
    f[size_t(i) * 4 + 0] = table[i];
    f[size_t(i) * 4 + 1] = table[255 - i];
    f[size_t(i) * 4 + 2] = table[i];
    f[size_t(i) * 4 + 3] = float(std::max(i, 1)) / 255.0f;  // alpha 0 would be filled
  }
  Texture t;
  ASSERT_FALSE(Texture::from_linear_float(256, 1, f.data(), TexelEncoding::Srgb, t));
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(channel(t.texel(0, i, 0), 0), i);
    EXPECT_EQ(channel(t.texel(0, i, 0), 1), 255 - i);
    EXPECT_EQ(channel(t.texel(0, i, 0), 3), std::max(i, 1));
  }
  EXPECT_FLOAT_EQ(table[255], 1.0f);
  EXPECT_EQ(table[0], 0.0f);
  EXPECT_NEAR(table[128], 0.2158605f, 1e-7);
}

// Level k of an N-texel-square checkerboard of black and white: squares of N >> k texels
// while they last, then uniform grey 0.5 (byte 128 by round-half-up).
TEST(Texture, CheckerboardLevelsAverageCorrectly) {
  const int size = 64, square = 8;
  const Texture t = make_texture(size, size, TexelEncoding::Linear, [&](int x, int y) {
    const uint8_t c = ((x / square + y / square) % 2) ? 255 : 0;
    return pack(c, c, c, 255);
  });
  for (int k = 0; k < t.levels(); ++k) {
    const MipLevel& L = t.level(k);
    const int sq = square >> k;
    for (int y = 0; y < L.height; ++y)
      for (int x = 0; x < L.width; ++x) {
        const int expect = sq >= 1 ? (((x / sq + y / sq) % 2) ? 255 : 0) : 128;
        ASSERT_EQ(channel(t.texel(k, x, y), 0), expect) << "level " << k << " (" << x << ", " << y << ")";
        ASSERT_EQ(channel(t.texel(k, x, y), 3), 255);
      }
  }
}

// Odd sizes: each texel of level k is the exact area average of the region of level k - 1
// it covers, [i W / W_k, (i + 1) W / W_k) x [j H / H_k, (j + 1) H / H_k) with W, H the sizes
// of level k - 1, computed here by midpoint sub-cells of 1 / W_k by 1 / H_k texel (which
// tile those bounds exactly) from the unrounded values of level k - 1. Every source texel
// counts: nothing of an odd row or column is dropped.
TEST(Texture, OddSizedLevelsAreAreaAverages) {
  for (const std::pair<int, int>& size : {std::pair{7, 5}, std::pair{5, 1}, std::pair{9, 11}, std::pair{3, 3}}) {
    const int w0 = size.first, h0 = size.second;  // named copies: lambdas below capture them
    std::mt19937 rng(uint32_t(w0 * 31 + h0));
    std::vector<double> prev(size_t(w0) * size_t(h0));
    for (double& x : prev) x = double(rng() % 256);
    const Texture t = make_texture(w0, h0, TexelEncoding::Linear, [&](int x, int y) {
      const uint8_t c = uint8_t(prev[size_t(y) * size_t(w0) + size_t(x)]);
      return pack(c, uint8_t(255 - c), 7, 255);
    });
    for (int k = 1; k < t.levels(); ++k) {
      const int w = t.level(k - 1).width, h = t.level(k - 1).height;
      const MipLevel& L = t.level(k);
      std::vector<double> cur(size_t(L.width) * size_t(L.height));
      for (int j = 0; j < L.height; ++j)
        for (int i = 0; i < L.width; ++i) {
          double sum = 0.0;
          int count = 0;
          // Sub-cell a spans [a, a + 1) / W_k source texels; texel i covers a in [i W, (i + 1) W).
          for (int b = j * h; b < (j + 1) * h; ++b)
            for (int a = i * w; a < (i + 1) * w; ++a) {
              const int x0 = int((a + 0.5) / L.width), y0 = int((b + 0.5) / L.height);
              sum += prev[size_t(y0) * size_t(w) + size_t(x0)];
              ++count;
            }
          const double expect = sum / count;
          cur[size_t(j) * size_t(L.width) + size_t(i)] = expect;
          EXPECT_LE(std::abs(channel(t.texel(k, i, j), 0) - expect), 0.5 + 1e-9)
              << w0 << "x" << h0 << " level " << k << " (" << i << ", " << j << ") expect " << expect;
          EXPECT_LE(std::abs(channel(t.texel(k, i, j), 1) - (255 - expect)), 0.5 + 1e-9);
          EXPECT_EQ(channel(t.texel(k, i, j), 2), 7);
        }
      prev = std::move(cur);
    }
  }
}

// An opaque red texel beside a transparent black one stays red (plain averaging would give
// dark red): in the mip chain (alpha-weighted box) and in the sampler (the transparent
// texel is filled with red).
TEST(Texture, TransparentTexelsDoNotDarkenTheirNeighbours) {
  const Texture t = make_texture(2, 1, TexelEncoding::Linear, [](int x, int) {
    return x == 0 ? pack(255, 0, 0, 255) : pack(0, 0, 0, 0);
  });
  ASSERT_EQ(t.levels(), 2);
  EXPECT_EQ(t.texel(1, 0, 0), pack(255, 0, 0, 128));
  for_each_target([&](const std::string& target) {
    std::vector<float> u(16, 0.5f), v(16, 0.5f);  // halfway between the two texel centres
    const Samples s = run_sample(t, {Filter::Bilinear, Wrap::Clamp, Wrap::Clamp, 0.0f}, u, v);
    for (size_t i = 0; i < 16; ++i) {
      EXPECT_NEAR(s.c[0][i], 1.0f, 1e-6) << target;
      EXPECT_NEAR(s.c[1][i], 0.0f, 1e-6) << target;
      EXPECT_NEAR(s.c[3][i], 0.5f, 1e-6) << target;
    }
  });
  // A fully transparent footprint keeps its own colour.
  const Texture clear = make_texture(4, 4, TexelEncoding::Linear, [](int, int) { return pack(40, 80, 120, 0); });
  EXPECT_EQ(clear.texel(2, 0, 0), pack(40, 80, 120, 0));
}

// A constant texture samples to its constant with every filter, wrap, LOD and bias, and its
// whole chain holds the same bytes (sRGB: decoded, averaged and re-encoded exactly).
TEST(Texture, ConstantTextureSamplesToTheConstant) {
  const uint32_t colours[] = {pack(200, 100, 30, 255), pack(10, 250, 128, 77), pack(90, 91, 92, 0),
                              pack(0, 0, 0, 0), pack(255, 255, 255, 255)};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> any(-50.0f, 50.0f);
  std::vector<float> u(16 * 32), v(16 * 32);
  for (size_t i = 0; i < u.size(); ++i) {
    u[i] = any(rng);
    v[i] = any(rng);
  }
  for (TexelEncoding enc : {TexelEncoding::Linear, TexelEncoding::Srgb})
    for (auto [w, h] : {std::pair{37, 20}, std::pair{16, 16}, std::pair{1, 1}})
      for (uint32_t c : colours) {
        const Texture t = make_texture(w, h, enc, [&](int, int) { return c; });
        for (int k = 0; k < t.levels(); ++k) ASSERT_EQ(t.texel(k, 0, 0), c) << "level " << k;
        double expect[4];
        for (int ch = 0; ch < 3; ++ch)
          expect[ch] = enc == TexelEncoding::Srgb ? srgb8_to_linear_table()[channel(c, ch)] : channel(c, ch) / 255.0;
        expect[3] = channel(c, 3) / 255.0;
        for_each_target([&](const std::string& target) {
          for (Filter f : kAllFilters)
            for (float bias : {-3.0f, 0.0f, 1.7f, 100.0f}) {
              const Samples s = run_sample(t, {f, Wrap::Repeat, Wrap::Clamp, bias}, u, v);
              for (size_t i = 0; i < u.size(); ++i)
                for (int ch = 0; ch < 4; ++ch)
                  ASSERT_NEAR(s.c[ch][i], expect[ch], 1e-6) << target << " filter " << int(f) << " lane " << i;
            }
        });
      }
}

// A 4x4 block whose u advances `du` and v `dv` per pixel in x and y (no rotation).
void ramp_block(float u0, float v0, float du, float dv, std::vector<float>& u, std::vector<float>& v) {
  for (int l = 0; l < 16; ++l) {
    u.push_back(u0 + du * float(l % 4));
    v.push_back(v0 + dv * float(l / 4));
  }
}

TEST(Texture, BlockLodFromDerivatives) {
  std::vector<float> u, v;
  ramp_block(0.25f, 0.5f, 4.0f / 256, 1.0f / 256, u, v);  // 4 texels per pixel in x, 1 in y
  EXPECT_DOUBLE_EQ(block_lod(u.data(), v.data(), 256, 256), 2.0);
  u.clear();
  v.clear();
  ramp_block(0.25f, 0.5f, 0.0f, 0.5f / 64, u, v);  // 0.5 texel per pixel in y only
  EXPECT_DOUBLE_EQ(block_lod(u.data(), v.data(), 64, 64), -1.0);
  u.assign(16, 0.3f);
  v.assign(16, 0.7f);
  EXPECT_EQ(block_lod(u.data(), v.data(), 64, 64), -std::numeric_limits<double>::infinity());
}

// Blocks for the level-of-detail tests: random ones (random derivatives, rotations and
// perspective-like bends), then hard ones (zero, tiny, subnormal, huge and non-finite
// derivatives, exact powers of two, 1e38 next to 1). Returns the count of random blocks.
size_t lod_test_blocks(std::vector<float>& u, std::vector<float>& v) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int i = 0; i < 200; ++i) {
    const float scale = std::ldexp(1.0f, int(rng() % 40) - 30);
    const float a = unit(rng) * scale, b = unit(rng) * scale, c = unit(rng) * scale, d = unit(rng) * scale;
    const float u0 = unit(rng) * 100.0f, v0 = unit(rng) * 100.0f, bend = unit(rng) * 0.2f;
    for (int l = 0; l < 16; ++l) {
      const float x = float(l % 4), y = float(l / 4), w = 1.0f + bend * (x + y);
      u.push_back(u0 + (a * x + b * y) / w);
      v.push_back(v0 + (c * x + d * y) / w);
    }
  }
  const size_t random_blocks = u.size() / 16;
  // Hard blocks: constant, exact powers of two per pixel, tiny, huge, non-finite, cancelling.
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float step : {0.0f, 1.0f / 256, 2.0f / 256, 4.0f / 256, 64.0f / 256, 1e-40f, 1e-30f, 1e30f, 3e38f})
    ramp_block(0.25f, 0.5f, step, step, u, v);
  ramp_block(0.25f, 0.5f, 4.0f / 256, 0.0f, u, v);
  for (float bad : {nan, inf, -inf, 1e38f, -1e38f}) {
    ramp_block(0.25f, 0.5f, 1.0f / 256, 1.0f / 256, u, v);
    u[u.size() - 1 - rng() % 16] = bad;
    ramp_block(0.25f, 0.5f, 1.0f / 256, 1.0f / 256, u, v);
    v[v.size() - 16] = bad;
  }
  ramp_block(1.0f, 1.0f, 0.0f, 0.0f, u, v);
  u[u.size() - 13] = 1e38f;  // lane 3: row 0's last value
  // Each lane alone non-finite or huge, in u and in v: every row, column and sum sees one.
  for (int lane = 0; lane < 16; ++lane)
    for (float bad : {nan, inf, 1e38f}) {
      ramp_block(0.25f, 0.5f, 3.0f / 256, 1.0f / 256, u, v);
      u[u.size() - 16 + size_t(lane)] = bad;
      ramp_block(0.25f, 0.5f, 1.0f / 256, 3.0f / 256, u, v);
      v[v.size() - 16 + size_t(lane)] = -bad;
    }
  return random_blocks;
}

// The sampler's SIMD squared derivative length (block_lod_length2s) against the scalar
// block_lod_length2, bit for bit, on every target (NaN where it gives NaN).
TEST(Texture, BlockLength2IsTheScalarBitForBitOnEveryTarget) {
  std::vector<float> u, v;
  lod_test_blocks(u, v);
  const size_t blocks = u.size() / 16;
  for_each_target([&](const std::string& target) {
    for (const auto& [w, h] : {std::pair{256, 128}, std::pair{1, 16384}, std::pair{1000, 3}}) {
      std::vector<double> got(blocks, -1.0);
      block_lod_length2s(u.data(), v.data(), blocks, w, h, got.data());
      for (size_t k = 0; k < blocks; ++k) {
        const double want = block_lod_length2(u.data() + 16 * k, v.data() + 16 * k, w, h);
        if (std::isnan(want)) {
          EXPECT_TRUE(std::isnan(got[k])) << target << " block " << k;
        } else {
          EXPECT_EQ(std::bit_cast<uint64_t>(got[k]), std::bit_cast<uint64_t>(want))
              << target << " " << w << "x" << h << " block " << k << ": " << got[k] << " against " << want;
        }
      }
    }
  });
  double out = 0.0;
  EXPECT_THROW(block_lod_length2s(u.data(), nullptr, 1, 256, 256, &out), std::invalid_argument);
  EXPECT_THROW(block_lod_length2s(u.data(), v.data(), 1, 256, 0, &out), std::invalid_argument);
}

// The sampler's SIMD level of detail (block_lods) against the scalar block_lod, clamped the
// same way, on every target, on lod_test_blocks. Highway's log may differ from std::log2 by
// an ulp or two; an exact power of 4 must give the exact integer.
TEST(Texture, BlockLodsMatchScalarLodOnEveryTarget) {
  std::vector<float> u, v;
  const size_t random_blocks = lod_test_blocks(u, v);
  const size_t blocks = u.size() / 16;
  const int levels = 9;
  for_each_target([&](const std::string& target) {
    for (float bias : {0.0f, -1.5f, 2.25f}) {
      std::vector<double> got(blocks, -1.0);
      // Not square, so that the two axes' scales cannot trade places unnoticed.
      block_lods(u.data(), v.data(), blocks, 256, 128, bias, levels, got.data());
      for (size_t k = 0; k < blocks; ++k) {
        const double lambda = block_lod(u.data() + 16 * k, v.data() + 16 * k, 256, 128) + double(bias);
        const double want = lambda > 0.0 ? std::min(lambda, double(levels - 1)) : 0.0;
        ASSERT_TRUE(std::isfinite(got[k])) << target << " block " << k;
        if (want == std::floor(want) && k >= random_blocks) {
          EXPECT_EQ(got[k], want) << target << " bias " << bias << " block " << k;
        } else {
          EXPECT_NEAR(got[k], want, 1e-14) << target << " bias " << bias << " block " << k;
        }
      }
    }
  });
  double out = 0.0;
  EXPECT_THROW(block_lods(u.data(), nullptr, 1, 256, 256, 0.0f, 1, &out), std::invalid_argument);
  EXPECT_THROW(block_lods(u.data(), v.data(), 1, 0, 256, 0.0f, 1, &out), std::invalid_argument);
}

// With the LOD an exact integer k (from the derivatives, or from the bias), trilinear returns
// exactly what bilinear returns on level k alone. (Opaque, so that rebuilding level k as a
// texture of its own does not refill its transparent texels from a different chain.)
TEST(Texture, TrilinearAtIntegerLodEqualsBilinearOnThatLevel) {
  std::mt19937 texel_rng(21);
  const Texture t = make_texture(128, 64, TexelEncoding::Srgb, [&](int, int) { return texel_rng() | 0xFF000000u; });
  std::mt19937 rng(4);
  for (int k = 0; k < t.levels(); ++k) {
    const Texture level = level_as_texture(t, k);
    std::vector<float> u, v, ub, vb;
    for (int b = 0; b < 24; ++b) {
      // Start on multiples of 2^-10 so that every u + du * x is exact in float.
      const float u0 = float(int(rng() % 4096) - 2048) / 1024.0f, v0 = float(int(rng() % 4096) - 2048) / 1024.0f;
      ramp_block(u0, v0, std::ldexp(1.0f, k) / 128, 0.0f, u, v);  // 2^k texels per pixel
      ramp_block(u0, v0, 1.0f / 128, 1.0f / 64, ub, vb);            // 1 texel per pixel
    }
    for_each_target([&](const std::string& target) {
      for (Wrap w : {Wrap::Repeat, Wrap::Clamp}) {
        const Samples bil = run_sample(level, {Filter::Bilinear, w, w, 0.0f}, u, v);
        const Samples tri = run_sample(t, {Filter::Trilinear, w, w, 0.0f}, u, v);
        const Samples bil_b = run_sample(level, {Filter::Bilinear, w, w, 0.0f}, ub, vb);
        const Samples tri_b = run_sample(t, {Filter::Trilinear, w, w, float(k)}, ub, vb);
        for (int ch = 0; ch < 4; ++ch) {
          ASSERT_EQ(tri.c[ch], bil.c[ch]) << target << " level " << k << " channel " << ch;
          ASSERT_EQ(tri_b.c[ch], bil_b.c[ch]) << target << " bias " << k << " channel " << ch;
        }
      }
    });
  }
}

// OpenGL's *_MIPMAP_NEAREST rule: level 0 up to lambda = 0.5, then the nearest level with
// halves rounding down.
TEST(Texture, NearestMipLevelFollowsOpenGl) {
  const double above = std::nextafter(0.5, 1.0);
  EXPECT_EQ(nearest_mip_level(0.0), 0);
  EXPECT_EQ(nearest_mip_level(0.5), 0);
  EXPECT_EQ(nearest_mip_level(above), 1);
  EXPECT_EQ(nearest_mip_level(1.0), 1);
  EXPECT_EQ(nearest_mip_level(1.5), 1);
  EXPECT_EQ(nearest_mip_level(std::nextafter(1.5, 2.0)), 2);
  EXPECT_EQ(nearest_mip_level(7.0), 7);
}

// BilinearMip returns exactly what bilinear returns on the nearest level alone, for LODs from
// the derivatives (clamped at the last level) and from the bias.
TEST(Texture, BilinearMipSamplesTheNearestLevel) {
  std::mt19937 texel_rng(22);
  const Texture t = make_texture(128, 64, TexelEncoding::Srgb, [&](int, int) { return texel_rng() | 0xFF000000u; });
  ASSERT_EQ(t.levels(), 8);
  struct Lod {
    float lambda, bias;
    int level;
  };
  const Lod lods[] = {{0.3f, 0.0f, 0}, {0.7f, 0.0f, 1}, {1.2f, 0.0f, 1}, {1.8f, 0.0f, 2}, {2.4f, 0.0f, 2},
                      {3.6f, 0.0f, 4}, {9.5f, 0.0f, 7}, {0.0f, 1.6f, 2},  {0.0f, -3.0f, 0}};
  std::mt19937 rng(5);
  for (const Lod& lod : lods) {
    std::vector<float> u, v;
    for (int b = 0; b < 16; ++b) {
      const float u0 = float(int(rng() % 4096) - 2048) / 1024.0f, v0 = float(int(rng() % 4096) - 2048) / 1024.0f;
      ramp_block(u0, v0, std::exp2(lod.lambda) / 128, 0.0f, u, v);
    }
    const Texture level = level_as_texture(t, lod.level);
    for_each_target([&](const std::string& target) {
      for (Wrap w : {Wrap::Repeat, Wrap::Clamp}) {
        const Samples mip = run_sample(t, {Filter::BilinearMip, w, w, lod.bias}, u, v);
        const Samples bil = run_sample(level, {Filter::Bilinear, w, w, 0.0f}, u, v);
        for (int ch = 0; ch < 4; ++ch)
          ASSERT_EQ(mip.c[ch], bil.c[ch]) << target << " lambda " << lod.lambda << " bias " << lod.bias
                                          << " channel " << ch;
      }
    });
  }
}

// Beyond the last level the LOD clamps: a huge derivative samples the 1x1 level.
TEST(Texture, HugeDerivativeClampsToTheLastLevel) {
  const Texture t = random_texture(32, 8, TexelEncoding::Linear, 9);
  const uint32_t last = t.texel(t.levels() - 1, 0, 0);
  std::vector<float> u, v;
  ramp_block(0.1f, 0.2f, 1e5f, -3e4f, u, v);
  for_each_target([&](const std::string& target) {
    const Samples s = run_sample(t, {Filter::Trilinear, Wrap::Repeat, Wrap::Repeat, 0.0f}, u, v);
    for (size_t i = 0; i < 16; ++i) {
      ASSERT_NEAR(s.c[3][i], channel(last, 3) / 255.0, 1e-6) << target;
      if (channel(last, 3) > 0) {
        ASSERT_NEAR(s.c[0][i], channel(last, 0) / 255.0, 1e-6) << target;
      }
    }
  });
}

// Repeat is periodic: shifting u and v by whole numbers (exactly, in float) changes nothing,
// with every filter, including the LOD (the derivatives are unchanged).
TEST(Texture, RepeatWrappingIsPeriodic) {
  const Texture t = random_texture(48, 20, TexelEncoding::Linear, 13);
  std::mt19937 rng(2);
  std::vector<float> u, v;
  for (int b = 0; b < 32; ++b)
    ramp_block(float(rng() % 1024) / 1024.0f, float(rng() % 1024) / 1024.0f,
               float(int(rng() % 64)) / 1024.0f, float(int(rng() % 64)) / 1024.0f, u, v);
  for_each_target([&](const std::string& target) {
    for (Filter f : kAllFilters) {
      const SamplerState s{f, Wrap::Repeat, Wrap::Repeat, 0.0f};
      const Samples base = run_sample(t, s, u, v);
      for (auto [n, m] : {std::pair{1, 0}, std::pair{-1, 3}, std::pair{-7, -2}, std::pair{1000, -1000}}) {
        std::vector<float> us(u), vs(v);
        for (auto& x : us) x += float(n);
        for (auto& x : vs) x += float(m);
        const Samples shifted = run_sample(t, s, us, vs);
        for (int ch = 0; ch < 4; ++ch)
          ASSERT_EQ(shifted.c[ch], base.c[ch]) << target << " filter " << int(f) << " shift " << n << ", " << m;
      }
    }
  });
}

// Nearest picks the texel whose cell holds the coordinate: texel centres at (i + 0.5) / W.
TEST(Texture, NearestAndBilinearHitTexelCentres) {
  const Texture t = make_texture(5, 3, TexelEncoding::Linear, [](int x, int y) {
    return pack(uint8_t(x * 50), uint8_t(y * 100), 0, 255);
  });
  std::vector<float> u, v;
  for (int l = 0; l < 16; ++l) {
    const int x = l % 5, y = l % 3;
    u.push_back((float(x) + 0.5f) / 5.0f);
    v.push_back((float(y) + 0.5f) / 3.0f);
  }
  for_each_target([&](const std::string& target) {
    for (Filter f : {Filter::Nearest, Filter::Bilinear}) {
      const Samples s = run_sample(t, {f, Wrap::Clamp, Wrap::Clamp, 0.0f}, u, v);
      for (int l = 0; l < 16; ++l) {
        ASSERT_NEAR(s.c[0][size_t(l)], (l % 5) * 50 / 255.0, 2e-6) << target << " filter " << int(f);
        ASSERT_NEAR(s.c[1][size_t(l)], (l % 3) * 100 / 255.0, 2e-6) << target << " filter " << int(f);
      }
    }
  });
}

// A La8 texture is its RGBA8 twin (R = G = B = L) stored as 2-byte texels, L low and A high:
// every level's texels are equal, each row ends in the padding texel (a copy of its first),
// the levels lie where the twin's do, and the storage is half the twin's plus the spare texel.
TEST(Texture, LuminanceAlphaLevelsEqualTheirRgbaTwinAtTwoBytesATexel) {
  for (auto [w, h] : {std::pair{64, 64}, std::pair{37, 5}, std::pair{1, 1}, std::pair{1, 7}, std::pair{6, 1}}) {
    const LaPair t = random_la_texture(w, h, uint32_t(w * 100 + h));
    EXPECT_EQ(t.la.format(), TexelFormat::La8);
    EXPECT_EQ(t.rgba.format(), TexelFormat::Rgba8);
    EXPECT_EQ(t.la.level_texels(0), nullptr);
    EXPECT_EQ(t.rgba.level_la(0), nullptr);
    EXPECT_EQ(t.la.bytes(), t.rgba.bytes() / 2 + 2);
    ASSERT_EQ(t.la.levels(), t.rgba.levels());
    for (int k = 0; k < t.la.levels(); ++k) {
      const MipLevel& L = t.la.level(k);
      EXPECT_EQ(L.offset, t.rgba.level(k).offset);
      EXPECT_EQ(L.stride, L.width + 1);
      for (int y = 0; y < L.height; ++y) {
        const uint16_t* row = t.la.level_la(k) + size_t(y) * size_t(L.stride);
        for (int x = 0; x < L.width; ++x) {
          ASSERT_EQ(t.la.texel(k, x, y), t.rgba.texel(k, x, y)) << w << "x" << h << " level " << k << " texel " << x << "," << y;
          const uint32_t rgba = t.rgba.texel(k, x, y);
          ASSERT_EQ(row[x], (rgba & 255u) | ((rgba >> 16) & 0xFF00u)) << w << "x" << h << " level " << k;
        }
        ASSERT_EQ(row[L.width], row[0]) << "padding texel";
      }
    }
  }
  Texture t;
  EXPECT_TRUE(Texture::from_la8(0, 4, nullptr, t).has_value());
  const uint8_t la[2] = {1, 2};
  auto e = Texture::from_la8(4, 0, la, t);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "height");
  e = Texture::from_la8(4, 4, nullptr, t);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "la");
  TextureArray arr;
  e = TextureArray::from_la8_layers(2, 2, 0, la, arr);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "count");
}

TEST(TextureArray, LayersMatchSingleTextures) {
  const int w = 16, h = 8, n = 3;
  std::mt19937 rng(8);
  std::vector<uint8_t> bytes(size_t(w) * h * 4 * n);
  for (auto& b : bytes) b = uint8_t(rng());
  TextureArray arr;
  ASSERT_FALSE(TextureArray::from_rgba8_layers(w, h, n, bytes.data(), TexelEncoding::Linear, arr));
  ASSERT_EQ(arr.layers.size(), size_t(n));
  EXPECT_EQ(arr.width(), w);
  EXPECT_EQ(arr.height(), h);
  for (int s = 0; s < n; ++s) {
    Texture one;
    ASSERT_FALSE(Texture::from_rgba8(w, h, bytes.data() + size_t(s) * w * h * 4, TexelEncoding::Linear, one));
    ASSERT_EQ(arr.layers[size_t(s)].levels(), one.levels());
    for (int k = 0; k < one.levels(); ++k)
      for (int y = 0; y < one.level(k).height; ++y)
        for (int x = 0; x < one.level(k).width; ++x)
          ASSERT_EQ(arr.layers[size_t(s)].texel(k, x, y), one.texel(k, x, y));
  }
}

// The parallel builds split rows and layers into items: the bytes must not depend on how the
// items run. Built serially, on a real pool of 2 and 3 threads, and with the items in reverse
// order; an odd size makes odd-sized levels and a partial last item.
TEST(Texture, ParallelBuildsGiveTheSerialBytes) {
  ThreadPool two(2), three(3);
  auto pool_of = [](ThreadPool& pool) -> ParallelFor {
    return [&pool](size_t count, const std::function<void(size_t)>& fn) {
      pool.parallel_for(count, [&fn](size_t k, int) { fn(k); });
    };
  };
  const ParallelFor reverse = [](size_t count, const std::function<void(size_t)>& fn) {
    for (size_t k = count; k-- > 0;) fn(k);
  };
  const ParallelFor runs[] = {pool_of(two), pool_of(three), reverse};
  const int w = 301, h = 157, layers = 5;
  std::mt19937 rng(21);
  std::vector<float> f(size_t(w) * h * 4);
  for (auto& x : f) x = float(rng() % 1001) / 1000.0f * (rng() % 4 == 0 ? 0.0f : 1.0f);  // a quarter transparent-ish
  std::vector<uint8_t> rgba(size_t(w) * h * 4 * layers), la(size_t(w) * h * 2 * layers);
  for (auto& b : rgba) b = uint8_t(rng());
  for (auto& b : la) b = uint8_t(rng() % 3 == 0 ? 0 : rng());
  auto same = [](const Texture& a, const Texture& b) {
    if (a.levels() != b.levels() || a.bytes() != b.bytes()) return false;
    return std::memcmp(a.data(), b.data(), a.bytes()) == 0;
  };
  for (TexelEncoding enc : {TexelEncoding::Srgb, TexelEncoding::Linear}) {
    Texture serial;
    ASSERT_FALSE(Texture::from_linear_float(w, h, f.data(), enc, serial));
    for (const ParallelFor& run : runs) {
      Texture t;
      ASSERT_FALSE(Texture::from_linear_float(w, h, f.data(), enc, t, run));
      EXPECT_TRUE(same(serial, t)) << "from_linear_float, encoding " << int(enc);
    }
  }
  TextureArray serial_rgba, serial_la;
  ASSERT_FALSE(TextureArray::from_rgba8_layers(w, h, layers, rgba.data(), TexelEncoding::Srgb, serial_rgba));
  ASSERT_FALSE(TextureArray::from_la8_layers(w, h, layers, la.data(), serial_la));
  for (const ParallelFor& run : runs) {
    TextureArray a, b;
    ASSERT_FALSE(TextureArray::from_rgba8_layers(w, h, layers, rgba.data(), TexelEncoding::Srgb, a, run));
    ASSERT_FALSE(TextureArray::from_la8_layers(w, h, layers, la.data(), b, run));
    for (int s = 0; s < layers; ++s) {
      EXPECT_TRUE(same(serial_rgba.layers[size_t(s)], a.layers[size_t(s)])) << "rgba layer " << s;
      EXPECT_TRUE(same(serial_la.layers[size_t(s)], b.layers[size_t(s)])) << "la layer " << s;
    }
    Texture one;
    ASSERT_FALSE(Texture::from_rgba8(w, h, rgba.data(), TexelEncoding::Linear, one, run));
    Texture one_serial;
    ASSERT_FALSE(Texture::from_rgba8(w, h, rgba.data(), TexelEncoding::Linear, one_serial));
    EXPECT_TRUE(same(one_serial, one));
  }
  // The first bad value is named whatever runs the packing.
  std::vector<float> bad = f;
  bad[4 * (size_t(w) * 100 + 7) + 2] = 1.5f;
  bad[4 * (size_t(w) * 120 + 3) + 1] = -1.0f;
  Texture t;
  const auto e = Texture::from_linear_float(w, h, bad.data(), TexelEncoding::Srgb, t, runs[0]);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "rgba[" + std::to_string(4 * (size_t(w) * 100 + 7) + 2) + "]");
}

}  // namespace
}  // namespace pelt::raster::test
