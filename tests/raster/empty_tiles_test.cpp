// Tiles no triangle touches skip the tile planes and write the background straight into
// the target: every such pixel must hold exactly what a covered tile's empty pixels hold
// (the background colour, depth 1, id 0), on every target, in partial edge tiles, and
// into a colour plane that is not 16-byte aligned (no streaming stores there).
#include <gtest/gtest.h>

#include <vector>

#include <glm/ext/matrix_clip_space.hpp>

#include "raster/config.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace {

TEST(EmptyTiles, HoldTheBackgroundDepthOneAndIdZeroLikeCoveredTiles) {
  // 200 x 150: 4 x 3 tiles, the last column 8 and the last row 22 pixels wide. One
  // triangle in the top-left tile only (pixels 2..20 in NDC terms below).
  constexpr int kW = 200, kH = 150;
  const std::vector<glm::vec3> pos = {{-0.98f, 0.98f, 0.0f}, {-0.8f, 0.98f, 0.0f}, {-0.98f, 0.75f, 0.0f}};
  const std::vector<uint32_t> idx = {0, 1, 2};
  const ConstantShader red({1, 0, 0, 1});
  DrawCall d;
  d.positions = pos.data();
  d.vertex_count = 3;
  d.indices = idx.data();
  d.triangle_count = 1;
  d.shader = &red;
  RenderOptions opt;
  opt.background = glm::vec4(0.25f, 0.5f, 0.75f, 0.125f);
  for (const size_t offset : {size_t{0}, size_t{1}}) {  // aligned, then 4 bytes off
    for_each_target([&](const std::string& target) {
      std::vector<float> colour(size_t(kW) * kH * 4 + 4, -1.0f), depth(size_t(kW) * kH, -1.0f);
      std::vector<uint32_t> id(size_t(kW) * kH, 0xFFFFFFFFu);
      Renderer r(2);
      RasterStats st;
      r.render({&d, 1}, opt, RenderTarget{kW, kH, colour.data() + offset, depth.data(), id.data()}, &st);
      const float* c = colour.data() + offset;
      size_t covered = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const size_t p = size_t(y) * kW + x;
          if (id[p] != 0) {
            ASSERT_TRUE(x < kTileSize && y < kTileSize) << target << " pixel " << x << "," << y;
            ++covered;
            continue;
          }
          for (int k = 0; k < 4; ++k)
            ASSERT_EQ(c[4 * p + k], opt.background[k]) << target << " pixel " << x << "," << y << " channel " << k;
          ASSERT_EQ(depth[p], 1.0f) << target << " pixel " << x << "," << y;
        }
      EXPECT_GT(covered, 50u) << target;
      EXPECT_EQ(colour[0], offset ? -1.0f : opt.background[0]) << target;  // nothing written before the plane
      EXPECT_EQ(colour.back(), -1.0f) << target;                             // nor after it
    });
  }
}

}  // namespace
}  // namespace pelt::raster::test
