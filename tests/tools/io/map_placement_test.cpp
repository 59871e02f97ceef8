// io::MapPlacement: flipping v with the uvs, and how `pelt info` describes a placement.
#include "tools/io/map_placement.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace pelt::io {
namespace {

// A placement read in flipped uvs reads the texel the placement reads in the file's own: for
// any uv, flipping then placing by flipped_v(p) equals placing by p then flipping. And the flip
// is its own inverse.
TEST(MapPlacement, FlippedVReadsTheSameTexel) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> x(-3.0f, 3.0f);
  for (int trial = 0; trial < 100; ++trial) {
    MapPlacement p;
    for (float& k : p.m) k = x(rng);
    const MapPlacement f = flipped_v(p);
    const float u = x(rng), v = x(rng);
    const float pu = p.m[0] * u + p.m[1] * v + p.m[2], pv = p.m[3] * u + p.m[4] * v + p.m[5];
    const float fv = 1.0f - v;
    EXPECT_NEAR(f.m[0] * u + f.m[1] * fv + f.m[2], pu, 1e-4f);
    EXPECT_NEAR(f.m[3] * u + f.m[4] * fv + f.m[5], 1.0f - pv, 1e-4f);
    const MapPlacement back = flipped_v(f);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(back.m[size_t(k)], p.m[size_t(k)], 1e-5f);
  }
  EXPECT_EQ(flipped_v(MapPlacement{}), MapPlacement{});
}

TEST(MapPlacement, DescribeSaysWrapsAndTransform) {
  EXPECT_EQ(describe(MapPlacement{}), "as the uvs say");
  MapPlacement p;
  p.wrap_u = raster::Wrap::Mirror;
  p.wrap_v = raster::Wrap::Clamp;
  EXPECT_EQ(describe(p), "mirror u, clamp v");
  p.m = {2.0f, 0.0f, 0.25f, 0.0f, 3.0f, -0.5f};
  EXPECT_EQ(describe(p), "mirror u, clamp v; u' = 2 u + 0.25, v' = 3 v - 0.5");
  MapPlacement flip;
  flip.m = {-1.0f, 0.0f, 1.0f, 0.0f, 1.0f, 0.0f};
  EXPECT_EQ(describe(flip), "u' = -u + 1, v' = v");
  // A quarter turn as KHR_texture_transform composes it: cos(pi / 2) in float is 6e-17, not 0.
  const double r = 1.5707963267948966;
  MapPlacement turn;
  turn.m = {float(std::cos(r)), float(std::sin(r)), 0.1f, float(-std::sin(r)), float(std::cos(r)), 0.0f};
  EXPECT_EQ(describe(turn), "u' = v + 0.1, v' = -u");
}

}  // namespace
}  // namespace pelt::io
