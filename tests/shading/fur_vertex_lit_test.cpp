// shade_fur_vertex_lit against its scalar reference, bit for bit (NaN as NaN), on every compiled target:
// random lanes, hard values (NaN, infinities, products at and around 1, negative and huge
// inputs), channels sharing one array as the renderer passes them, the fins' per-lane tint
// from a height, and the argument checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "shading/fur_vertex_lit.h"
#include "tests/shading/batch_harness.h"

namespace pelt::shading {
namespace fur_vertex_lit_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::for_each_target;

struct Inputs {
  size_t blocks;
  std::vector<float> texel[3], tint[3], diffuse[3], specular[3];
  std::vector<float> height;  // per lane (the fins' per-lane tint); empty: per-block tint
  float tint_root[3] = {}, tint_slope[3] = {};
};

Inputs random_inputs(size_t blocks, uint32_t seed, bool hard) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.5f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float specials[] = {nan, inf, -inf, 0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f),
                            -1.0f, 3e38f, 1e-45f, 0.8f};
  auto value = [&] { return hard && rng() % 3 == 0 ? specials[rng() % std::size(specials)] : unit(rng); };
  Inputs in;
  in.blocks = blocks;
  for (int c = 0; c < 3; ++c) {
    for (size_t i = 0; i < blocks * 16; ++i) {
      in.texel[c].push_back(value());
      in.diffuse[c].push_back(value());
      in.specular[c].push_back(value() * 0.25f);
    }
    for (size_t b = 0; b < blocks; ++b) in.tint[c].push_back(value());
  }
  return in;
}

// The fins' form: a tint per lane from a height, heights around and outside [0, 1] (and, hard,
// NaN and infinities), tints root to tip.
Inputs height_inputs(size_t blocks, uint32_t seed, bool hard) {
  Inputs in = random_inputs(blocks, seed, hard);
  std::mt19937 rng(seed + 1000);
  std::uniform_real_distribution<float> h(-0.25f, 1.25f), t(0.0f, 1.3f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float specials[] = {nan, inf, -inf, 0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f),
                            std::nextafter(0.0f, 1.0f), -1e-30f};
  for (size_t i = 0; i < blocks * 16; ++i)
    in.height.push_back(hard && rng() % 3 == 0 ? specials[rng() % std::size(specials)] : h(rng));
  for (int c = 0; c < 3; ++c) {
    in.tint_root[c] = t(rng);
    in.tint_slope[c] = t(rng) - 0.5f;
  }
  return in;
}

// `shared`: one texel, diffuse and specular array for all three channels (a luminance shell
// under a grey light), as FurShader passes them.
FurVertexLitSoA batch(const Inputs& in, std::vector<float> (&out)[3], bool shared) {
  FurVertexLitSoA b;
  b.blocks = in.blocks;
  for (int c = 0; c < 3; ++c) {
    const int k = shared ? 0 : c;
    b.texel[c] = in.texel[k].data();
    b.diffuse[c] = in.diffuse[k].data();
    b.specular[c] = in.specular[k].data();
    b.tint[c] = in.height.empty() ? in.tint[c].data() : nullptr;  // not read with heights
    out[c].assign(in.blocks * 16, -7.0f);
    b.out[c] = out[c].data();
    b.tint_root[c] = in.tint_root[c];
    b.tint_slope[c] = in.tint_slope[c];
  }
  b.height = in.height.empty() ? nullptr : in.height.data();
  return b;
}

void expect_kernel_equals_reference(const Inputs& in, bool shared) {
  std::vector<float> want[3], got[3];
  shade_fur_vertex_lit_reference(batch(in, want, shared));
  for_each_target([&](int64_t) {
    shade_fur_vertex_lit(batch(in, got, shared));
    size_t bad = 0;
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < got[c].size(); ++i)
        // A NaN's sign and payload are not IEEE arithmetic's to define (Highway's scalar target
        // and the compiled reference differ there): NaN must meet NaN, all else bit for bit.
        if (!(std::isnan(got[c][i]) && std::isnan(want[c][i])) &&
            std::memcmp(&got[c][i], &want[c][i], sizeof(float)) != 0 && bad++ < 5)
          ADD_FAILURE() << "channel " << c << " lane " << i << ": " << got[c][i] << " want " << want[c][i];
    EXPECT_EQ(bad, 0u);
  });
}

TEST(FurVertexLit, RandomLanesMatchTheReferenceBitForBit) {
  expect_kernel_equals_reference(random_inputs(37, 1, false), false);
  expect_kernel_equals_reference(random_inputs(37, 2, false), true);
}

TEST(FurVertexLit, HardValuesMatchTheReferenceBitForBit) {
  expect_kernel_equals_reference(random_inputs(64, 3, true), false);
  expect_kernel_equals_reference(random_inputs(64, 4, true), true);
}

TEST(FurVertexLit, PerLaneTintMatchesTheReferenceBitForBit) {
  expect_kernel_equals_reference(height_inputs(37, 7, false), false);
  expect_kernel_equals_reference(height_inputs(37, 8, false), true);
  expect_kernel_equals_reference(height_inputs(64, 9, true), false);
  expect_kernel_equals_reference(height_inputs(64, 10, true), true);
}

// The per-lane tint is root + slope h with h clamped to [0, 1] and NaN taken as 0.
TEST(FurVertexLit, PerLaneTintFollowsTheClampedHeight) {
  Inputs in = height_inputs(1, 11, false);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float heights[] = {0.0f, 0.5f, 1.0f, -3.0f, 7.0f, nan};
  const float expect_h[] = {0.0f, 0.5f, 1.0f, 0.0f, 1.0f, 0.0f};
  for (int c = 0; c < 3; ++c) {
    in.tint_root[c] = 0.25f;
    in.tint_slope[c] = 0.5f;
    for (int l = 0; l < 6; ++l) {
      in.texel[c][size_t(l)] = 1.0f;
      in.diffuse[c][size_t(l)] = 1.0f;
      in.specular[c][size_t(l)] = 0.0f;
    }
  }
  for (int l = 0; l < 6; ++l) in.height[size_t(l)] = heights[l];
  std::vector<float> out[3];
  for_each_target([&](int64_t) {
    shade_fur_vertex_lit(batch(in, out, false));
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < 6; ++l) EXPECT_EQ(out[c][size_t(l)], 0.25f + 0.5f * expect_h[l]) << "lane " << l;
  });
}

TEST(FurVertexLit, ClampsTheTintedTexelAtOneAndNaNToOne) {
  Inputs in = random_inputs(1, 5, false);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int c = 0; c < 3; ++c) {
    in.tint[c][0] = 2.0f;
    in.texel[c][0] = 0.75f;   // 1.5: clamped to 1
    in.texel[c][1] = 0.25f;   // 0.5: kept
    in.texel[c][2] = nan;     // NaN: 1
    for (int l = 0; l < 3; ++l) {
      in.diffuse[c][l] = 0.5f;
      in.specular[c][l] = 0.125f;
    }
  }
  std::vector<float> out[3];
  for_each_target([&](int64_t) {
    shade_fur_vertex_lit(batch(in, out, false));
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(out[c][0], 0.625f);
      EXPECT_EQ(out[c][1], 0.375f);
      EXPECT_EQ(out[c][2], 0.625f);
    }
  });
}

TEST(FurVertexLit, NullPointersAreNamed) {
  Inputs in = random_inputs(1, 6, false);
  std::vector<float> out[3];
  FurVertexLitSoA b = batch(in, out, false);
  b.diffuse[2] = nullptr;
  try {
    shade_fur_vertex_lit(b);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("diffuse[2]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(shade_fur_vertex_lit_reference(b), std::invalid_argument);
  b.blocks = 0;
  EXPECT_NO_THROW(shade_fur_vertex_lit(b));
  // With per-lane heights the per-block tint is not needed, and not read.
  Inputs h = height_inputs(1, 12, false);
  FurVertexLitSoA bh = batch(h, out, false);
  EXPECT_EQ(bh.tint[0], nullptr);
  EXPECT_NO_THROW(shade_fur_vertex_lit(bh));
  bh.height = nullptr;
  EXPECT_THROW(shade_fur_vertex_lit(bh), std::invalid_argument);
}

}  // namespace fur_vertex_lit_test
}  // namespace pelt::shading
