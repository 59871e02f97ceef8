// Alpha-tested opaque draws (PipelineState::alpha_test): a fragment whose shaded alpha is below
// the cutoff, or NaN, writes neither depth nor visibility; a kept one is an opaque fragment,
// stored with alpha 1. Compared with the scalar reference rasterizer, which applies the same
// contract pixel by pixel, on every SIMD target, and across thread counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/reference_raster.h"
#include "tests/raster/render_helpers.h"

namespace pelt::raster::test {
namespace alpha_test_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// The alphas a fragment may get: both sides of the cutoff 0.5 and the cutoff itself, out of
// range, and NaN.
const std::vector<float> kAlphas = {0.0f, 0.25f, 0.4999f, 0.5f, 0.5001f, 1.0f, 2.0f, -1.0f,
                                    std::numeric_limits<float>::quiet_NaN()};

// Draw `draw`'s fragment alpha at pixel (px, py) of triangle `primitive`: a hash, so that
// neighbouring pixels and triangles differ.
float alpha_at(uint32_t draw, uint32_t primitive, int px, int py) {
  uint32_t h = (primitive + 1) * 0x9E3779B1u ^ (uint32_t(px) * 0x85EBCA6Bu) ^ (uint32_t(py) * 0xC2B2AE35u) ^
               (draw * 0x27D4EB2Fu);
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  return kAlphas[h % kAlphas.size()];
}

// Colour from the triangle, alpha by alpha_at at each lane's pixel.
class PixelAlphaShader final : public Shader {
 public:
  PixelAlphaShader(uint32_t draw, bool derivatives) : draw_(draw), derivatives_(derivatives) {}
  bool uses_derivatives() const override { return derivatives_; }
  void shade(const FragmentBatch& b) const override {
    for (uint32_t k = 0; k < b.blocks; ++k)
      for (int l = 0; l < kBlockLanes; ++l) {
        const size_t i = size_t{k} * kBlockLanes + size_t(l);
        const uint32_t p = b.primitive[i];
        b.out[0][i] = float(p % 7) / 7.0f;
        b.out[1][i] = float(p % 5) / 5.0f;
        b.out[2][i] = float(draw_) / 4.0f;
        b.out[3][i] = alpha_at(draw_, p, b.block_x[k] + l % kBlockSize, b.block_y[k] + l / kBlockSize);
      }
  }

 private:
  uint32_t draw_;
  bool derivatives_;
};

// Alpha 1 everywhere: every fragment kept.
class ConstantOpaque final : public Shader {
 public:
  void shade(const FragmentBatch& b) const override {
    for (int c = 0; c < 4; ++c) std::fill(b.out[c], b.out[c] + size_t{b.blocks} * kBlockLanes, 1.0f);
  }
};

// Four draws of random triangles in front of the camera: plain opaque, alpha-tested (with and
// without derivatives, so packed and per-triangle opaque shading both meet it), plain opaque
// again (submitted after an alpha-tested draw, drawn before it: the contract).
struct CutOutSoup {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  std::vector<PixelAlphaShader> shaders;
  std::vector<DrawCall> draws;

  CutOutSoup(unsigned seed, int per_draw, float cutoff = 0.5f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const int n = 4 * per_draw;
    for (int i = 0; i < n; ++i) {
      const glm::vec3 c(u(rng) * 3.0f, u(rng) * 3.0f, -5.0f + u(rng) * 3.0f);
      const float s = 0.1f + 0.6f * (u(rng) + 1.0f);
      for (int k = 0; k < 3; ++k) {
        pos.push_back(c + s * glm::vec3(u(rng), u(rng), u(rng)));
        idx.push_back(uint32_t(pos.size() - 1));
      }
    }
    for (uint32_t d = 0; d < 4; ++d) shaders.emplace_back(d, d == 2);
    for (uint32_t d = 0; d < 4; ++d) {
      DrawCall dc;
      dc.positions = pos.data();
      dc.vertex_count = uint32_t(pos.size());
      dc.indices = idx.data() + 3 * size_t(d) * size_t(per_draw);
      dc.triangle_count = uint32_t(per_draw);
      dc.clip_from_object = glm::perspective(glm::radians(60.0f), 4.0f / 3.0f, 0.5f, 20.0f);
      dc.shader = &shaders[d];
      dc.id_base = d * uint32_t(per_draw);
      dc.state.alpha_test = d == 1 || d == 2;
      dc.state.alpha_cutoff = cutoff;
      draws.push_back(dc);
    }
  }
  CutOutSoup(const CutOutSoup&) = delete;
  CutOutSoup& operator=(const CutOutSoup&) = delete;
};

// Depth and visible triangle agree with the reference bit for bit on every target.
TEST(AlphaTest, DepthAndVisibilityMatchTheReferenceOnEveryTarget) {
  const CutOutSoup soup(7, 400);
  const ReferenceImage ref = reference_render(soup.draws, 160, 120, false, alpha_at);
  size_t cut = 0;  // pixels where an alpha-tested triangle is seen
  for (const uint32_t id : ref.id) cut += id > 400 && id <= 1200;
  EXPECT_GT(cut, 1000u);
  for_each_target([&](const std::string& target) {
    const Image img = render(soup.draws, 160, 120, 2);
    EXPECT_EQ(img.id, ref.id) << target;
    EXPECT_EQ(0, std::memcmp(img.depth.data(), ref.depth.data(), ref.depth.size() * sizeof(float))) << target;
  });
}

// Without the test the same draws hide more: the discarded fragments mattered (the comparison
// above can fail).
TEST(AlphaTest, DiscardedFragmentsShowWhatLiesBehind) {
  CutOutSoup soup(7, 400);
  const Image cut = render(soup.draws, 160, 120, 2);
  for (DrawCall& d : soup.draws) d.state.alpha_test = false;
  const Image whole = render(soup.draws, 160, 120, 2);
  size_t differ = 0;
  for (size_t i = 0; i < cut.id.size(); ++i) differ += cut.id[i] != whole.id[i];
  EXPECT_GT(differ, 1000u);
}

// A kept fragment is stored opaque: alpha 1 (the shader's there reached the cutoff, and may be
// 2), and each visible pixel's colour is its triangle's.
TEST(AlphaTest, KeptFragmentsAreStoredOpaque) {
  const CutOutSoup soup(11, 300);
  const Image img = render(soup.draws, 160, 120, 1);
  for (size_t p = 0; p < img.id.size(); ++p) {
    if (img.id[p] == 0) continue;
    const uint32_t draw = (img.id[p] - 1) / 300, prim = (img.id[p] - 1) % 300;
    ASSERT_EQ(img.color[4 * p + 0], float(prim % 7) / 7.0f) << p;
    ASSERT_EQ(img.color[4 * p + 2], float(draw) / 4.0f) << p;
    if (draw == 1 || draw == 2) {
      ASSERT_EQ(img.color[4 * p + 3], 1.0f) << p;  // plain draws store their alpha
    }
  }
}

// The cutoff is the draw's: at 0 every fragment with a finite alpha of at least 0 stays (NaN
// and -1 go), and the reference agrees.
TEST(AlphaTest, TheCutoffIsTheDraws) {
  const CutOutSoup soup(13, 300, 0.0f);
  const ReferenceImage ref = reference_render(soup.draws, 128, 96, false, alpha_at);
  const Image img = render(soup.draws, 128, 96, 2);
  EXPECT_EQ(img.id, ref.id);
}

// An alpha-tested draw under DepthFunc::Always may raise the depth; the next alpha-tested draw
// is tested against what it wrote, not against the depth before it (its batch is written
// first). Three quads: plain near, filling the screen; alpha-tested far under Always, a small
// one in the middle (a few blocks: its batch is not yet full when the next draw starts), which
// pushes the depth back there; alpha-tested between them under Less, filling the screen,
// which must win in the middle.
TEST(AlphaTest, ADrawAfterAnAlwaysDrawIsTestedAgainstItsDepth) {
  std::vector<glm::vec3> pos;
  for (const float z : {-2.0f, -12.0f, -6.0f}) {
    const float half = z == -12.0f ? 0.1f * -z : -z;
    for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
      pos.emplace_back(c.x * half, c.y * half, z);
  }
  const std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11};
  const ConstantOpaque shader;
  std::vector<DrawCall> draws(3);
  for (uint32_t d = 0; d < 3; ++d) {
    draws[d].positions = pos.data();
    draws[d].vertex_count = uint32_t(pos.size());
    draws[d].indices = idx.data() + 6 * d;
    draws[d].triangle_count = 2;
    draws[d].clip_from_object = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
    draws[d].shader = &shader;
    draws[d].id_base = 2 * d;
    draws[d].state.alpha_test = d > 0;
  }
  draws[1].state.depth_func = DepthFunc::Always;
  for_each_target([&](const std::string& target) {
    const Image img = render(draws, 64, 64, 1);
    const uint32_t mid = img.id[32 * 64 + 32];
    EXPECT_TRUE(mid == 5u || mid == 6u) << target << ": " << mid;  // draw 2's triangles (ids 5 and 6)
    EXPECT_TRUE(img.id[4 * 64 + 4] == 1u || img.id[4 * 64 + 4] == 2u) << target;  // elsewhere the near quad
  });
}

// Random draws under Always and LessEqual agree with the reference.
TEST(AlphaTest, OtherDepthFunctionsMatchTheReference) {
  CutOutSoup soup(23, 400);
  soup.draws[1].state.depth_func = DepthFunc::Always;
  const ReferenceImage ref = reference_render(soup.draws, 160, 120, false, alpha_at);
  for_each_target([&](const std::string& target) {
    const Image img = render(soup.draws, 160, 120, 2);
    EXPECT_EQ(img.id, ref.id) << target;
  });
  // LessEqual keeps the later of two fragments at one depth: the reference agrees too.
  soup.draws[1].state.depth_func = DepthFunc::LessEqual;
  EXPECT_EQ(render(soup.draws, 160, 120, 1).id, reference_render(soup.draws, 160, 120, false, alpha_at).id);
}

// The same image on any thread count (tiles are independent; the batches within a tile are
// flushed in submission order).
TEST(AlphaTest, OneTwoAndEightThreadsGiveIdenticalImages) {
  const CutOutSoup soup(17, 1500);
  const Image one = render(soup.draws, 320, 240, 1);
  for (int threads : {2, 8}) {
    const Image many = render(soup.draws, 320, 240, threads);
    EXPECT_EQ(0, std::memcmp(one.color.data(), many.color.data(), one.color.size() * sizeof(float))) << threads;
    EXPECT_EQ(one.id, many.id) << threads;
  }
}

// A cutoff outside [0, 1] (or NaN), and the test on a blended draw, are the caller's error.
TEST(AlphaTest, ACutoffOutsideTheUnitRangeIsRefused) {
  CutOutSoup soup(19, 10);
  for (float bad : {-0.1f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
    soup.draws[1].state.alpha_cutoff = bad;
    EXPECT_THROW(render(soup.draws, 32, 32, 1), std::invalid_argument) << bad;
  }
  soup.draws[1].state.alpha_cutoff = 0.5f;
  soup.draws[1].state.blend = BlendMode::AlphaOver;
  EXPECT_THROW(render(soup.draws, 32, 32, 1), std::invalid_argument);
}

}  // namespace alpha_test_test
}  // namespace pelt::raster::test
