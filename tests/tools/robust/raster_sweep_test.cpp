// Stability sweep of the rasterizer: over 100,000 random triangles with extreme coordinates
// (tiny, denormal, huge, crossing the near plane and w = 0, a few NaN and Inf) through
// raster::Renderer with every blend, cull and sort mode. No pixel may get a NaN or infinite
// colour, a depth outside [0, 1] or an id beyond the draw; no shader lane a non-finite varying
// or (covered) depth outside [0, 1].
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/renderer.h"

namespace pelt::raster {
namespace {

constexpr uint32_t kTrianglesPerDraw = 1024;
constexpr int kDraws = 100;
constexpr int kWidth = 136, kHeight = 72;  // partial tiles and blocks on both axes

struct Counters {
  std::atomic<uint64_t> lanes{0}, bad_varyings{0}, bad_depth{0};
};

class CheckingShader final : public Shader {
 public:
  CheckingShader(float alpha, Counters* c) : alpha_(alpha), c_(c) {}
  void shade(const FragmentBatch& b) const override {
    uint64_t bad_v = 0, bad_d = 0;
    const size_t lanes = size_t{b.blocks} * kBlockLanes;
    for (size_t i = 0; i < lanes; ++i) {
      const bool covered = (b.mask[i / kBlockLanes] >> (i % kBlockLanes)) & 1u;
      for (int k = 0; k < 3; ++k) {
        const float v = b.varying[k][i];
        if (!std::isfinite(v)) ++bad_v;
        b.out[k][i] = std::isfinite(v) ? v : 0.0f;
      }
      if (covered && !(b.depth[i] >= 0.0f && b.depth[i] <= 1.0f)) ++bad_d;
      b.out[3][i] = alpha_;
    }
    c_->lanes += lanes;
    c_->bad_varyings += bad_v;
    c_->bad_depth += bad_d;
  }

 private:
  float alpha_;
  Counters* c_;
};

float extreme(std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 15);
  switch (pick(gen)) {
    case 0: return pick(gen) < 2 ? std::numeric_limits<float>::quiet_NaN() : float(u(gen) * 1e8);
    case 1: return float(u(gen) * 1e-40);                                   // denormal
    case 2: return float(u(gen) * 3e38);                                    // near FLT_MAX
    case 3: return pick(gen) < 1 ? std::numeric_limits<float>::infinity() : float(u(gen) * 1e30);
    case 4: return float(u(gen) * 1e-20);
    case 5: return 0.0f;
    case 6: case 7: return float(u(gen) * 1e4);                             // guard-band crossers
    default: return float(u(gen) * 2.0);                                    // ordinary
  }
}

TEST(RasterSweep, ExtremeTrianglesStayFiniteAndInRange) {
  std::mt19937_64 gen(0xacce55);
  Renderer renderer(2);
  Counters counters;
  std::vector<float> color(size_t{kWidth} * kHeight * 4), depth(size_t{kWidth} * kHeight);
  std::vector<uint32_t> id(size_t{kWidth} * kHeight);
  const RenderTarget target{kWidth, kHeight, color.data(), depth.data(), id.data()};

  std::vector<glm::vec3> positions(kTrianglesPerDraw * 3);
  std::vector<uint32_t> indices(kTrianglesPerDraw * 3);
  std::vector<float> varyings(kTrianglesPerDraw * 9, 0.0f);
  for (uint32_t i = 0; i < indices.size(); ++i) {
    indices[i] = i;
    varyings[size_t{i} * 3 + i % 3] = 1.0f;
  }
  const glm::mat4 perspective = glm::perspective(glm::radians(60.0f), float(kWidth) / kHeight, 1e-3f, 1e6f);

  uint64_t triangles = 0, pixels = 0, bad_color = 0, bad_depth = 0, bad_id = 0, visible = 0;
  for (int d = 0; d < kDraws; ++d) {
    for (auto& p : positions) p = glm::vec3(extreme(gen), extreme(gen), extreme(gen));
    DrawCall draw;
    draw.positions = positions.data();
    draw.vertex_count = uint32_t(positions.size());
    draw.indices = indices.data();
    draw.triangle_count = kTrianglesPerDraw;
    draw.varyings = varyings.data();
    draw.varying_count = 3;
    // Identity: clip coordinates with w = 1; perspective: w = -z, so any sign and size.
    draw.clip_from_object = d % 2 ? perspective : glm::mat4(1.0f);
    draw.state.cull = CullMode(d % 3);
    draw.state.blend = BlendMode((d / 3) % 3);
    draw.state.depth_func = DepthFunc((d / 9) % 3);
    const CheckingShader shader(draw.state.blend == BlendMode::Opaque ? 1.0f : 0.5f, &counters);
    draw.shader = &shader;
    RenderOptions options;
    options.sort = SortMode((d / 27) % 3);
    RasterStats stats;
    renderer.render(std::span<const DrawCall>(&draw, 1), options, target, &stats);
    triangles += stats.triangles_submitted;

    for (size_t p = 0; p < depth.size(); ++p) {
      ++pixels;
      if (!(depth[p] >= 0.0f && depth[p] <= 1.0f)) ++bad_depth;
      if (id[p] > kTrianglesPerDraw) ++bad_id;
      if (id[p] != 0) ++visible;
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(color[p * 4 + c])) ++bad_color;
    }
  }
  std::printf("raster sweep: %llu triangles in %d draws, %llu pixels checked (%llu with a visible triangle), "
              "%llu shader lanes; %llu non-finite colours, %llu depths outside [0, 1], %llu bad ids, "
              "%llu non-finite varyings, %llu fragment depths outside [0, 1]\n",
              (unsigned long long)triangles, kDraws, (unsigned long long)pixels, (unsigned long long)visible,
              (unsigned long long)counters.lanes.load(), (unsigned long long)bad_color,
              (unsigned long long)bad_depth, (unsigned long long)bad_id,
              (unsigned long long)counters.bad_varyings.load(), (unsigned long long)counters.bad_depth.load());
  EXPECT_GE(triangles, 100'000u);
  EXPECT_GT(visible, 0u) << "no triangle reached the image: the sweep would test nothing";
  EXPECT_EQ(bad_color, 0u);
  EXPECT_EQ(bad_depth, 0u);
  EXPECT_EQ(bad_id, 0u);
  EXPECT_EQ(counters.bad_varyings.load(), 0u);
  EXPECT_EQ(counters.bad_depth.load(), 0u);
}

}  // namespace
}  // namespace pelt::raster
