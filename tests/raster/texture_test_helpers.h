// Shared pieces of the texture tests: texture makers, per-target loops, sampling into
// vectors, and the SIMD-versus-reference comparison with its error bound.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "raster/texture.h"
#include "tests/hwy_targets.h"

namespace pelt::raster::test {

inline constexpr Filter kAllFilters[] = {Filter::Nearest, Filter::Bilinear, Filter::BilinearMip, Filter::Trilinear};

inline bool mipmapped(Filter f) { return f == Filter::Trilinear || f == Filter::BilinearMip; }

using pelt::test::for_each_target;

inline uint32_t pack(uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  return uint32_t{r} | (uint32_t{g} << 8) | (uint32_t{b} << 16) | (uint32_t{a} << 24);
}

inline uint8_t channel(uint32_t t, int ch) { return uint8_t((t >> (8 * ch)) & 255u); }

// A texture whose texel (x, y) is texel_fn(x, y) (packed RGBA8).
inline Texture make_texture(int w, int h, TexelEncoding enc,
                            const std::function<uint32_t(int, int)>& texel_fn) {
  std::vector<uint8_t> bytes(size_t(w) * size_t(h) * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t t = texel_fn(x, y);
      for (int ch = 0; ch < 4; ++ch) bytes[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(ch)] = channel(t, ch);
    }
  Texture tex;
  const auto err = Texture::from_rgba8(w, h, bytes.data(), enc, tex);
  EXPECT_FALSE(err.has_value()) << (err ? err->message() : "");
  return tex;
}

// Random texels; a third of them fully transparent, some fully opaque.
inline Texture random_texture(int w, int h, TexelEncoding enc, uint32_t seed) {
  std::mt19937 rng(seed);
  return make_texture(w, h, enc, [&](int, int) {
    const uint32_t r = rng();
    const uint32_t sel = rng() % 6;
    const uint8_t a = sel < 2 ? 0 : sel == 2 ? 255 : uint8_t(rng() & 255u);
    return (r & 0x00FFFFFFu) | (uint32_t{a} << 24);
  });
}

// A luminance-alpha texture of random (L, A) bytes, a third of them fully transparent, and its
// RGBA8 twin (R = G = B = L) built from the same bytes.
struct LaPair {
  Texture la, rgba;
};
inline LaPair random_la_texture(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> la(size_t(w) * size_t(h) * 2), rgba(size_t(w) * size_t(h) * 4);
  for (size_t i = 0; i < la.size() / 2; ++i) {
    const uint32_t sel = rng() % 6;
    la[2 * i] = uint8_t(rng() & 255u);
    la[2 * i + 1] = sel < 2 ? 0 : sel == 2 ? 255 : uint8_t(rng() & 255u);
    for (int c = 0; c < 3; ++c) rgba[4 * i + size_t(c)] = la[2 * i];
    rgba[4 * i + 3] = la[2 * i + 1];
  }
  LaPair p;
  auto e = Texture::from_la8(w, h, la.data(), p.la);
  EXPECT_FALSE(e.has_value()) << (e ? e->message() : "");
  e = Texture::from_rgba8(w, h, rgba.data(), TexelEncoding::Linear, p.rgba);
  EXPECT_FALSE(e.has_value()) << (e ? e->message() : "");
  return p;
}

// Level k of `tex` as a texture of its own (same bytes, same encoding).
inline Texture level_as_texture(const Texture& tex, int k) {
  const MipLevel& L = tex.level(k);
  return make_texture(L.width, L.height, tex.encoding(), [&](int x, int y) { return tex.texel(k, x, y); });
}

struct Samples {
  std::vector<float> c[4];
};

inline Samples run_sample(const Texture& tex, const SamplerState& s, const std::vector<float>& u,
                          const std::vector<float>& v, const uint16_t* block_mask = nullptr) {
  Samples out;
  for (auto& c : out.c) c.assign(u.size(), -1.0f);
  float* const ptr[4] = {out.c[0].data(), out.c[1].data(), out.c[2].data(), out.c[3].data()};
  sample(tex, s, u.data(), v.data(), u.size(), ptr, block_mask);
  return out;
}

struct RefSamples {
  std::vector<double> c[4];
};

inline RefSamples run_reference(const Texture& tex, const SamplerState& s, const std::vector<float>& u,
                                const std::vector<float>& v, const uint16_t* block_mask = nullptr) {
  RefSamples out;
  for (auto& c : out.c) c.assign(u.size(), -1.0);
  double* const ptr[4] = {out.c[0].data(), out.c[1].data(), out.c[2].data(), out.c[3].data()};
  sample_reference(tex, s, u.data(), v.data(), u.size(), ptr, block_mask);
  return out;
}

// Bound on |SIMD - reference| for bilinear and trilinear. The kernel forms the texel
// coordinate u * size - 0.5 in float: repeat's wrap (u - floor(u), exact for u >= 0, one
// rounding of at most 2^-25 for u < 0) and the product (half an ulp of a value below `size`,
// at most size * 2^-25) move a bilinear weight by at most size * 2^-24 per axis, and the
// output by that times the largest texel difference (<= 1). The reference has neither
// rounding. Float accumulation of at most 8 taps adds < 2e-6.
// For 256x256 this is 3.3e-5; for textures up to 64x64 it is below 1e-5.
inline double linear_tolerance(const Texture& tex) {
  return 2e-6 + double(tex.width() + tex.height()) * std::ldexp(1.0, -24);
}

// Compares one lane: every channel within `tol`, and finite.
inline ::testing::AssertionResult lane_matches(const Samples& s, const RefSamples& r, size_t i, double tol) {
  bool ok = true;
  for (int ch = 0; ch < 4; ++ch)
    ok = ok && std::isfinite(s.c[ch][i]) && std::abs(double(s.c[ch][i]) - r.c[ch][i]) <= tol;
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "lane " << i << " simd (" << s.c[0][i] << ", " << s.c[1][i] << ", " << s.c[2][i] << ", "
         << s.c[3][i] << ") reference (" << r.c[0][i] << ", " << r.c[1][i] << ", " << r.c[2][i]
         << ", " << r.c[3][i] << ") tol " << tol;
}

}  // namespace pelt::raster::test
