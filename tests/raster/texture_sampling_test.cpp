// The Highway sampler against the double-precision reference, for every compiled target,
// every filter and wrap pair, on random and on hard inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "raster/texture.h"
#include "tests/raster/texture_test_helpers.h"

namespace pelt::raster::test {
namespace {

constexpr Wrap kWraps[] = {Wrap::Repeat, Wrap::Clamp, Wrap::Mirror};

struct Coords {
  std::vector<float> u, v;
};

// Blocks whose u, v are affine in the pixel (as a rasterizer interpolates them) with
// derivatives from 2^-14 to 2^6 texture widths per pixel, randomly rotated, some with a
// perspective-like bend, and blocks of independent random values (random LOD).
Coords random_coords(size_t blocks, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> base(-3.0f, 3.0f), unit(-1.0f, 1.0f), e(-14.0f, 6.0f);
  Coords c;
  for (size_t b = 0; b < blocks; ++b) {
    const float u0 = base(rng), v0 = base(rng);
    const float sx = std::exp2(e(rng)), sy = std::exp2(e(rng)), angle = unit(rng) * 3.14159f;
    const bool independent = b % 5 == 4;
    const float bend = b % 3 == 0 ? 0.05f * unit(rng) : 0.0f;
    for (int l = 0; l < 16; ++l) {
      const float x = float(l % 4), y = float(l / 4);
      if (independent) {
        c.u.push_back(base(rng));
        c.v.push_back(base(rng));
        continue;
      }
      const float w = 1.0f + bend * (x + y);
      c.u.push_back(u0 + (sx * std::cos(angle) * x - sy * std::sin(angle) * y) / w);
      c.v.push_back(v0 + (sx * std::sin(angle) * x + sy * std::cos(angle) * y) / w);
    }
  }
  return c;
}

// Exact 0 and 1, negatives, huge values, float extremes (no NaN or infinity), texel
// boundaries and centres of a w x h texture and their float neighbours, in blocks that are
// constant (zero derivative), mixed (huge derivative) or a 1-texel-per-pixel ramp from a
// boundary.
Coords hard_coords(int w, int h, uint32_t seed) {
  std::vector<float> values = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, -2.5f, 1e6f, -1e6f, 1e6f + 0.5f,
                               -1e6f - 0.25f, 1e-30f, -1e-30f, FLT_MIN, -FLT_MIN, 1e-45f, FLT_MAX,
                               -FLT_MAX, 3e9f, -3e9f, 16777216.0f, std::nextafter(1.0f, 0.0f),
                               std::nextafter(0.0f, -1.0f), std::nextafter(1.0f, 2.0f)};
  for (int side : {w, h})
    for (int k = 0; k <= side; ++k)
      for (float t : {float(k) / float(side), (float(k) + 0.5f) / float(side)})
        for (float x : {t, std::nextafter(t, -1.0f), std::nextafter(t, 2.0f), t - 1.0f, t + 3.0f})
          values.push_back(x);
  std::mt19937 rng(seed);
  auto pick = [&] { return values[rng() % values.size()]; };
  Coords c;
  const size_t blocks = 3 * values.size() / 16 + 8;
  for (size_t b = 0; b < blocks; ++b) {
    const int kind = int(b % 3);
    const float cu = pick(), cv = pick();
    for (int l = 0; l < 16; ++l) {
      if (kind == 0) {  // constant: zero derivative
        c.u.push_back(cu);
        c.v.push_back(cv);
      } else if (kind == 1) {  // independent extremes: huge derivative
        c.u.push_back(pick());
        c.v.push_back(pick());
      } else {  // one texel per pixel from a hard value
        c.u.push_back(cu + float(l % 4) / float(w));
        c.v.push_back(cv + float(l / 4) / float(h));
      }
    }
  }
  return c;
}

// Nearest is discontinuous at texel boundaries: the kernel's float arithmetic can round onto
// a boundary that the exact value misses. A lane that differs from the reference must then
// equal the reference at a coordinate the kernel's rounding could have produced: u itself
// moved by one float ulp (spans the rounding of u * size) or, for repeat, the wrapped float
// u - floor(u) and its neighbours (spans the rounding of the wrap of a negative u), for mirror
// the folded u in [0, 1] and its neighbours (on a texel boundary the tie goes up in the folded
// coordinate, which is down in a reflected period).
std::vector<float> nearby(float x, Wrap wrap) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> out = {x, std::nextafter(x, -inf), std::nextafter(x, inf)};
  if (wrap == Wrap::Repeat || wrap == Wrap::Mirror) {
    const double t = std::fmod(std::abs(double(x)), 2.0);
    const float c = wrap == Wrap::Repeat ? x - std::floor(x) : float(t > 1.0 ? 2.0 - t : t);
    out.insert(out.end(), {c, std::nextafter(c, -inf), std::nextafter(c, inf)});
  }
  return out;
}

void expect_nearest_matches(const Texture& tex, const SamplerState& s, const Coords& c,
                            const Samples& simd, const RefSamples& ref, const std::string& what) {
  for (size_t i = 0; i < c.u.size(); ++i) {
    auto equal = [&](const RefSamples& r, size_t j) {
      for (int ch = 0; ch < 4; ++ch)
        if (std::abs(double(simd.c[ch][i]) - r.c[ch][j]) > 1e-6) return false;
      return true;
    };
    if (equal(ref, i)) continue;
    const size_t b = i / 16 * 16;
    bool found = false;
    for (float nu : nearby(c.u[i], s.wrap_u))
      for (float nv : nearby(c.v[i], s.wrap_v)) {
        if (found) break;
        std::vector<float> u(c.u.begin() + long(b), c.u.begin() + long(b) + 16);
        std::vector<float> v(c.v.begin() + long(b), c.v.begin() + long(b) + 16);
        u[i - b] = nu;
        v[i - b] = nv;
        found = equal(run_reference(tex, s, u, v), i - b);
      }
    EXPECT_TRUE(found) << what << " nearest lane " << i << " u " << c.u[i] << " v " << c.v[i];
  }
}

void compare_all(const Texture& tex, const Coords& c, const std::string& name) {
  for_each_target([&](const std::string& target) {
    for (Filter f : kAllFilters)
      for (Wrap wu : kWraps)
        for (Wrap wv : kWraps)
          for (float bias : {0.0f, -1.5f, 2.25f}) {
            if (!mipmapped(f) && bias != 0.0f) continue;
            const SamplerState s{f, wu, wv, bias};
            const std::string what = name + " " + target + " filter " + std::to_string(int(f)) +
                                     " wrap " + std::to_string(int(wu)) + std::to_string(int(wv)) +
                                     " bias " + std::to_string(bias);
            const Samples simd = run_sample(tex, s, c.u, c.v);
            const RefSamples ref = run_reference(tex, s, c.u, c.v);
            if (f == Filter::Nearest) {
              expect_nearest_matches(tex, s, c, simd, ref, what);
              continue;
            }
            const double tol = linear_tolerance(tex);
            size_t failures = 0;
            for (size_t i = 0; i < c.u.size() && failures < 5; ++i) {
              const auto r = lane_matches(simd, ref, i, tol);
              if (!r) ++failures;
              EXPECT_TRUE(r) << what;
            }
          }
  });
}

struct Case {
  int w, h;
  TexelEncoding enc;
};

const Case kCases[] = {{256, 256, TexelEncoding::Linear}, {64, 64, TexelEncoding::Srgb},
                       {1, 1, TexelEncoding::Linear},     {1, 1, TexelEncoding::Srgb},
                       {100, 37, TexelEncoding::Linear},  {3, 5, TexelEncoding::Srgb},
                       {7, 1, TexelEncoding::Linear},     {1, 9, TexelEncoding::Linear}};

std::string case_name(const Case& k) {
  return std::to_string(k.w) + "x" + std::to_string(k.h) + (k.enc == TexelEncoding::Srgb ? " srgb" : " linear");
}

TEST(TextureSampling, RandomInputsMatchReferenceOnEveryTarget) {
  uint32_t seed = 1;
  for (const Case& k : kCases) {
    const Texture tex = random_texture(k.w, k.h, k.enc, seed++);
    compare_all(tex, random_coords(64, seed++), case_name(k) + " random");
  }
}

TEST(TextureSampling, HardInputsMatchReferenceOnEveryTarget) {
  uint32_t seed = 100;
  for (const Case& k : kCases) {
    const Texture tex = random_texture(k.w, k.h, k.enc, seed++);
    compare_all(tex, hard_coords(std::min(k.w, 64), std::min(k.h, 64), seed++), case_name(k) + " hard");
  }
}

// 1024-wide levels: the float coordinate error bound grows with the size (see
// linear_tolerance); this checks that it holds there too.
TEST(TextureSampling, LargeTextureMatchesReference) {
  const Texture tex = random_texture(1024, 512, TexelEncoding::Linear, 7);
  compare_all(tex, random_coords(32, 8), "1024x512 random");
}

// Blocks of 0.5 to 6 texels a pixel, axis-aligned and at 45 degrees, centred on a level's
// edges: across the wrap in u and in v, on the last row and column (the padding texel) and
// inside, so footprints that straddle the edges are compared with the reference.
Coords edge_coords(int w, int h) {
  Coords c;
  const float du = 1.0f / float(w), dv = 1.0f / float(h);
  for (float scale : {0.5f, 1.0f, 3.9f, 6.0f})
    for (float angle : {0.0f, 0.7853982f})
      for (float cu : {0.0f, 0.5f * du, 1.0f - 2.0f * du, 1.0f - 0.5f * du, 0.5f})
        for (float cv : {0.0f, 0.5f * dv, 1.0f - 2.0f * dv, 1.0f - 0.5f * dv, 0.5f})
          for (int l = 0; l < 16; ++l) {
            const float x = float(l % 4) - 1.5f, y = float(l / 4) - 1.5f;
            c.u.push_back(cu + scale * du * (std::cos(angle) * x - std::sin(angle) * y));
            c.v.push_back(cv + scale * dv * (std::sin(angle) * x + std::cos(angle) * y));
          }
  return c;
}

TEST(TextureSampling, FootprintsOnLevelEdgesMatchReference) {
  uint32_t seed = 500;
  for (const Case& k : kCases) {
    const Texture tex = random_texture(k.w, k.h, k.enc, seed++);
    compare_all(tex, edge_coords(k.w, k.h), case_name(k) + " edges");
    if (k.enc == TexelEncoding::Linear)
      compare_all(random_la_texture(k.w, k.h, seed++).la, edge_coords(k.w, k.h), case_name(k) + " la8 edges");
  }
}

// Luminance-alpha textures (the fur shells' format) against the reference, which reads their
// texels expanded to RGBA8, on every target, filter and wrap.
TEST(TextureSampling, LuminanceAlphaMatchesReferenceOnEveryTarget) {
  uint32_t seed = 300;
  for (const Case& k : kCases) {
    if (k.enc != TexelEncoding::Linear) continue;
    const LaPair t = random_la_texture(k.w, k.h, seed++);
    compare_all(t.la, random_coords(64, seed++), case_name(k) + " la8 random");
    compare_all(t.la, hard_coords(std::min(k.w, 64), std::min(k.h, 64), seed++), case_name(k) + " la8 hard");
  }
}

// The La8 kernel weighs the same texels with the same weights in the same order as the
// RGBA8 kernel: a La8 texture samples bit for bit like its RGBA8 twin.
TEST(TextureSampling, LuminanceAlphaSamplesBitForBitLikeItsRgbaTwin) {
  uint32_t seed = 400;
  for (const Case& k : kCases) {
    if (k.enc != TexelEncoding::Linear) continue;
    const LaPair t = random_la_texture(k.w, k.h, seed++);
    for (const Coords& c : {random_coords(64, seed++), hard_coords(std::min(k.w, 64), std::min(k.h, 64), seed++)})
      for_each_target([&](const std::string& target) {
        for (Filter f : kAllFilters)
          for (Wrap wu : kWraps)
            for (Wrap wv : kWraps)
              for (float bias : {0.0f, -1.5f, 2.25f}) {
                const SamplerState s{f, wu, wv, bias};
                const Samples a = run_sample(t.la, s, c.u, c.v), b = run_sample(t.rgba, s, c.u, c.v);
                for (int ch = 0; ch < 4; ++ch)
                  ASSERT_EQ(0, std::memcmp(a.c[ch].data(), b.c[ch].data(), a.c[ch].size() * sizeof(float)))
                      << case_name(k) << " " << target << " filter " << int(f) << " wrap " << int(wu) << int(wv)
                      << " bias " << bias << " channel " << ch;
              }
      });
  }
}

// A La8 texture's three colour channels are equal, so a caller may pass one array for all three
// (the fur shader does): it then holds the luminance, bit for bit the separate arrays' red, with
// and without a block mask (the per-block and the dense paths), on every target.
TEST(TextureSampling, LuminanceIntoOneArrayForAllThreeChannels) {
  uint32_t seed = 700;
  const LaPair t = random_la_texture(64, 32, seed++);
  const Coords c = random_coords(100, seed++);
  std::mt19937 rng(seed++);
  std::vector<uint16_t> mask(c.u.size() / 16);
  for (uint16_t& m : mask) m = uint16_t(rng());
  for_each_target([&](const std::string& target) {
    for (Filter f : kAllFilters)
      for (Wrap w : kWraps)
        for (const uint16_t* m : {static_cast<const uint16_t*>(nullptr), static_cast<const uint16_t*>(mask.data())}) {
          const SamplerState s{f, w, w, 0.5f};
          const Samples separate = run_sample(t.la, s, c.u, c.v, m);
          std::vector<float> colour(c.u.size(), -1.0f), alpha(c.u.size(), -1.0f);
          float* const out[4] = {colour.data(), colour.data(), colour.data(), alpha.data()};
          sample(t.la, s, c.u.data(), c.v.data(), c.u.size(), out, m);
          EXPECT_EQ(0, std::memcmp(colour.data(), separate.c[0].data(), colour.size() * sizeof(float)))
              << target << " filter " << int(f) << " wrap " << int(w) << " mask " << (m != nullptr);
          EXPECT_EQ(0, std::memcmp(alpha.data(), separate.c[3].data(), alpha.size() * sizeof(float)))
              << target << " filter " << int(f) << " wrap " << int(w) << " mask " << (m != nullptr);
        }
  });
}

// Samples `textures` with and without a block mask on every target, filter and (wrap_u, wrap_v)
// of `wraps`, on random and hard coordinates: the lanes inside the mask sample bit for bit as
// without it, both in the kernel and in the reference, and within the reference's tolerance; every
// lane outside it reads +0. The masks cover the shapes that let a vector be skipped on each width
// (one half, one row, one lane) as well as empty, full and random blocks.
void expect_masked_samples_like_unmasked(std::span<const Texture> textures, std::span<const std::pair<Wrap, Wrap>> wraps,
                                         uint32_t seed) {
  const uint16_t shapes[] = {0x0000, 0xFFFF, 0x00FF, 0xFF00, 0x000F, 0xF000, 0x0001, 0x8000, 0x0F0F, 0x1248};
  for (const Texture& tex : textures)
    for (const Coords& c : {random_coords(150, seed++), hard_coords(tex.width(), tex.height(), seed++)}) {
      std::mt19937 rng(seed++);
      std::vector<uint16_t> mask(c.u.size() / 16);
      for (size_t b = 0; b < mask.size(); ++b)
        mask[b] = b % 2 ? shapes[b / 2 % std::size(shapes)] : uint16_t(rng());
      auto inside = [&](size_t i) { return (mask[i / 16] >> (i % 16)) & 1u; };
      for_each_target([&](const std::string& target) {
        for (Filter f : kAllFilters)
          for (const auto& [wu, wv] : wraps) {
            const SamplerState s{f, wu, wv, f == Filter::Trilinear ? 0.75f : 0.0f};
            const Samples all = run_sample(tex, s, c.u, c.v), masked = run_sample(tex, s, c.u, c.v, mask.data());
            const RefSamples ref_all = run_reference(tex, s, c.u, c.v);
            const RefSamples ref_masked = run_reference(tex, s, c.u, c.v, mask.data());
            size_t failures = 0;
            for (size_t i = 0; i < c.u.size() && failures < 5; ++i)
              for (int ch = 0; ch < 4; ++ch) {
                const float want = inside(i) ? all.c[ch][i] : 0.0f;
                const double ref_want = inside(i) ? ref_all.c[ch][i] : 0.0;
                const bool ok = std::memcmp(&masked.c[ch][i], &want, sizeof(float)) == 0 &&
                                std::memcmp(&ref_masked.c[ch][i], &ref_want, sizeof(double)) == 0;
                // And close to the reference (nearest: see expect_nearest_matches, run on `all`).
                const bool near_ref = f == Filter::Nearest || !inside(i) ||
                                      std::abs(double(masked.c[ch][i]) - ref_all.c[ch][i]) <= linear_tolerance(tex);
                failures += !ok || !near_ref;
                EXPECT_TRUE(near_ref) << target << " filter " << int(f) << " wrap " << int(wu) << int(wv) << " lane "
                                      << i << " channel " << ch << ": " << masked.c[ch][i] << " / " << ref_all.c[ch][i];
                EXPECT_TRUE(ok) << target << " filter " << int(f) << " wrap " << int(wu) << int(wv) << " lane " << i
                                << " mask " << mask[i / 16] << " channel " << ch << ": " << masked.c[ch][i]
                                << " / " << ref_masked.c[ch][i] << " want " << want << " / " << ref_want;
              }
          }
      });
    }
}

// A block mask (a fur batch's covered lanes), the same wrap on both axes. On 16-lane targets the
// power-of-two textures with repeat go through the dense lanes (texture_kernels.cc): 150 blocks
// span three of its chunks, and the non-square textures give levels whose width and height stop
// halving apart.
TEST(TextureSampling, ABlockMaskSamplesItsLanesAndZeroesTheRest) {
  uint32_t seed = 500;
  const LaPair la = random_la_texture(64, 64, seed++);
  const LaPair la_wide = random_la_texture(256, 16, seed++);
  const Texture textures[] = {random_texture(64, 64, TexelEncoding::Linear, seed++),
                              random_texture(37, 20, TexelEncoding::Srgb, seed++),
                              random_texture(8, 128, TexelEncoding::Srgb, seed++), la.la, la_wide.la};
  const std::pair<Wrap, Wrap> wraps[] = {
      {Wrap::Repeat, Wrap::Repeat}, {Wrap::Clamp, Wrap::Clamp}, {Wrap::Mirror, Wrap::Mirror}};
  expect_masked_samples_like_unmasked(textures, wraps, seed);
}

// The dense lanes decide repeat or clamp per axis (DenseLevels::repeat_u, repeat_v), and apply
// when each repeating axis has a power-of-two size, whatever the size of a clamped one: a fin's
// texture repeats along u and clamps from root to tip. Mixed wraps, with the clamped axis of
// power-of-two and of other sizes, and one repeating non-power-of-two axis (the per-block path).
TEST(TextureSampling, ABlockMaskWithMixedWrapsSamplesLikeNoMask) {
  uint32_t seed = 900;
  const LaPair fin = random_la_texture(64, 20, seed++);
  const LaPair tall = random_la_texture(12, 64, seed++);
  const Texture textures[] = {fin.la, tall.la, random_texture(32, 32, TexelEncoding::Srgb, seed++),
                              random_texture(128, 5, TexelEncoding::Linear, seed++)};
  const std::pair<Wrap, Wrap> wraps[] = {{Wrap::Repeat, Wrap::Clamp}, {Wrap::Clamp, Wrap::Repeat},
                                          {Wrap::Mirror, Wrap::Repeat}, {Wrap::Clamp, Wrap::Mirror}};
  expect_masked_samples_like_unmasked(textures, wraps, seed);
}

// Non-finite coordinates give unspecified samples but never read outside the texture
// (texture.h): the kernels clamp every texel coordinate into a few texels of the texture
// before converting it to an index, NaN included, and the conversion relies on that. Lanes of
// NaN and infinities, alone in a block or among finite lanes, in u, in v or both, on every
// target, filter and wrap, through the per-block and the dense paths: every sample is finite
// and within [0, 1] (an index from an unclamped NaN lies 2^29 texels away; under the test
// build's AddressSanitizer that is a report, elsewhere garbage or a crash).
TEST(TextureSampling, NonFiniteCoordinatesReadInsideTheTexture) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float bad[] = {nan, -nan, inf, -inf};
  uint32_t seed = 800;
  const LaPair la = random_la_texture(64, 64, seed++);
  const Texture textures[] = {la.la, random_texture(37, 20, TexelEncoding::Linear, seed++),
                              random_texture(64, 16, TexelEncoding::Srgb, seed++)};
  Coords c = random_coords(48, seed++);
  std::mt19937 rng(seed++);
  for (size_t b = 0; b < c.u.size() / 16; ++b)
    for (size_t l = 0; l < 16; ++l) {
      const size_t i = 16 * b + l;
      const bool whole = b % 4 == 0;  // every lane of the block; else about a third of them
      if (!whole && rng() % 3 != 0) continue;
      const float x = bad[rng() % std::size(bad)];
      switch (b % 3) {
        case 0: c.u[i] = x; break;
        case 1: c.v[i] = x; break;
        default: c.u[i] = x; c.v[i] = bad[rng() % std::size(bad)];
      }
    }
  std::vector<uint16_t> mask(c.u.size() / 16);
  for (uint16_t& m : mask) m = uint16_t(rng() | 1u);
  for (const Texture& tex : textures)
    for_each_target([&](const std::string& target) {
      for (Filter f : kAllFilters)
        for (Wrap wu : kWraps)
          for (Wrap wv : kWraps)
            for (const uint16_t* m : {static_cast<const uint16_t*>(nullptr), static_cast<const uint16_t*>(mask.data())}) {
              const Samples got = run_sample(tex, SamplerState{f, wu, wv, 0.0f}, c.u, c.v, m);
              size_t failures = 0;
              for (size_t i = 0; i < c.u.size() && failures < 5; ++i)
                for (int ch = 0; ch < 4; ++ch) {
                  const float x = got.c[ch][i];
                  const bool ok = std::isfinite(x) && x >= 0.0f && x <= 1.0f + 1e-6f;
                  failures += !ok;
                  EXPECT_TRUE(ok) << tex.width() << "x" << tex.height() << " " << target << " filter " << int(f)
                                  << " wrap " << int(wu) << int(wv) << " mask " << (m != nullptr) << " lane " << i
                                  << " (u " << c.u[i] << ", v " << c.v[i] << ") channel " << ch << ": " << x;
                }
            }
    });
}

TEST(TextureSampling, RejectsBadArguments) {
  const Texture tex = random_texture(4, 4, TexelEncoding::Linear, 1);
  std::vector<float> u(16, 0.5f), v(16, 0.5f), o(16);
  float* const out[4] = {o.data(), o.data(), o.data(), o.data()};
  EXPECT_THROW(sample(tex, {}, u.data(), v.data(), 15, out), std::invalid_argument);
  EXPECT_THROW(sample(Texture{}, {}, u.data(), v.data(), 16, out), std::invalid_argument);
  EXPECT_THROW(sample(tex, {}, nullptr, v.data(), 16, out), std::invalid_argument);
  float* const bad_out[4] = {o.data(), nullptr, o.data(), o.data()};
  EXPECT_THROW(sample(tex, {}, u.data(), v.data(), 16, bad_out), std::invalid_argument);
  try {
    sample(tex, {}, u.data(), v.data(), 20, out);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lanes"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(sample(tex, {}, u.data(), v.data(), 0, out));
  SamplerState bad_wrap;
  bad_wrap.wrap_v = static_cast<Wrap>(7);
  EXPECT_THROW(sample(tex, bad_wrap, u.data(), v.data(), 16, out), std::invalid_argument);
}

// Mirrored repeat as OpenGL defines it (GL_MIRRORED_REPEAT): along an axis of `size` texels,
// index i reads texel i mod 2 size, reflected in the second half. Nearest samples at texel
// centres over four periods, on both sides of 0, of an odd, non-power-of-two texture (the
// kernel folds coordinates; this states the definition independently of fold and reference).
TEST(TextureSampling, MirrorReadsTheTexelsOpenGlReflects) {
  constexpr int kW = 5, kH = 3;
  const Texture tex = random_texture(kW, kH, TexelEncoding::Linear, 77);
  const auto reflect = [](int i, int size) {
    const int m = ((i % (2 * size)) + 2 * size) % (2 * size);
    return m < size ? m : 2 * size - 1 - m;
  };
  std::vector<float> u, v;
  std::vector<std::pair<int, int>> want;
  for (int j = -2 * kH; j < 2 * kH; ++j)
    for (int i = -2 * kW; i < 2 * kW; ++i) {
      u.push_back((float(i) + 0.5f) / kW);
      v.push_back((float(j) + 0.5f) / kH);
      want.emplace_back(reflect(i, kW), reflect(j, kH));
    }
  while (u.size() % 16 != 0) {
    u.push_back(0.1f);
    v.push_back(0.1f);
    want.emplace_back(0, 0);
  }
  for_each_target([&](const std::string& target) {
    const Samples got = run_sample(tex, {Filter::Nearest, Wrap::Mirror, Wrap::Mirror, 0.0f}, u, v);
    for (size_t k = 0; k < u.size(); ++k) {
      const uint32_t t = tex.texel(0, want[k].first, want[k].second);
      ASSERT_NEAR(got.c[3][k], channel(t, 3) / 255.0, 1e-6) << target << " u " << u[k] << " v " << v[k];
      if (channel(t, 3) > 0) {
        ASSERT_NEAR(got.c[0][k], channel(t, 0) / 255.0, 1e-6) << target << " u " << u[k] << " v " << v[k];
      }
    }
  });
}

// The mirror's fold kernel is its scalar reference bit for bit, on every target: random
// coordinates of every scale and sign, and the hard ones (mirror lines, an ulp either side of
// them, signed zeros, denormals, coordinates past 2^24 where every float is even, the largest
// float, infinities and NaN, which fold to NaN), at counts that leave a partial last vector.
TEST(TextureSampling, TheMirrorFoldKernelIsItsReference) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> c = {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, -2.0f, 3.0f, 0.5f, 1.5f, -1.5f, FLT_MIN, -FLT_MIN,
                          FLT_TRUE_MIN, 16777216.0f, 16777218.0f, 33554436.0f, -1e30f, FLT_MAX, -FLT_MAX, inf, -inf, nan};
  for (const float m : {1.0f, 2.0f, 3.0f, 1024.0f, 65537.0f})
    for (const float x : {m, -m}) c.insert(c.end(), {std::nextafter(x, -inf), std::nextafter(x, inf)});
  std::mt19937 rng(1234);
  for (int k = 0; k < 4000; ++k) {
    const float scale = std::ldexp(1.0f, int(rng() % 60) - 30);
    c.push_back(scale * (std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng)));
  }
  for_each_target([&](const std::string& target) {
    for (const size_t n : {c.size(), size_t{1}, size_t{7}, size_t{17}, size_t{33}}) {
      std::vector<float> got(n, -7.0f);
      fold_mirror(c.data(), got.data(), n);
      for (size_t i = 0; i < n; ++i) {
        const float want = fold_mirror_reference(c[i]);
        if (std::isnan(want)) {
          ASSERT_TRUE(std::isnan(got[i])) << target << " c " << c[i];
        } else {
          ASSERT_EQ(std::memcmp(&got[i], &want, sizeof want), 0) << target << " c " << c[i] << " got " << got[i]
                                                                 << " want " << want;
          ASSERT_TRUE(want >= 0.0f && want <= 1.0f) << c[i];
        }
      }
    }
  });
}

// A block that crosses a mirror line keeps the level of detail of its coordinates: trilinear
// at 4 texels a pixel along u, across u = 1, samples exactly what it samples at the mirror image of the
// block, 2 - u, and what bilinear samples on level 2 alone, not the sharper level that folded
// coordinates' smaller differences would give.
TEST(TextureSampling, MirrorKeepsTheBlocksLevelOfDetail) {
  std::mt19937 texel_rng(31);
  const Texture t = make_texture(64, 64, TexelEncoding::Linear, [&](int, int) { return texel_rng() | 0xFF000000u; });
  const Texture level2 = level_as_texture(t, 2);
  std::vector<float> u, v, mirrored;
  for (int l = 0; l < 16; ++l) {
    u.push_back(1.0f + float(l % 4 - 2) * (4.0f / 64.0f) + 1.0f / 128.0f);
    v.push_back(0.25f + float(l / 4) * (1.0f / 64.0f));  // 1 texel a pixel: u alone sets the level
    mirrored.push_back(2.0f - u.back());
  }
  for_each_target([&](const std::string& target) {
    const Samples tri = run_sample(t, {Filter::Trilinear, Wrap::Mirror, Wrap::Mirror, 0.0f}, u, v);
    const Samples tri_m = run_sample(t, {Filter::Trilinear, Wrap::Mirror, Wrap::Mirror, 0.0f}, mirrored, v);
    const Samples bil = run_sample(level2, {Filter::Bilinear, Wrap::Mirror, Wrap::Mirror, 0.0f}, u, v);
    for (int ch = 0; ch < 4; ++ch) {
      EXPECT_EQ(tri.c[ch], tri_m.c[ch]) << target << " channel " << ch;
      EXPECT_EQ(tri.c[ch], bil.c[ch]) << target << " channel " << ch;
    }
  });
}

}  // namespace
}  // namespace pelt::raster::test
