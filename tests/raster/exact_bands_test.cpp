// SortMode::Exact holds a tile's translucent fragments until it composites them; a tile that could
// hold more than RenderOptions::exact_fragment_cap draws its translucent pass in bands of blocks
// (ExactPasses in tile_kernels.cc). Each pixel must blend the same fragments in the same order
// (here, where the triangles pack alike in any band, not a bit of any plane changes), and a tile
// must hold at most the cap at once. Until 2026-11-27 a pile of layers held them
// all: 631 MB at 512 x 512 for a thousand blended full-screen quads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace exact_bands_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

constexpr int kWidth = 200, kHeight = 150;  // partial tiles at the right and bottom

struct Soup {
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
};

// `quads` full-screen quads, one behind the other, and `triangles` random ones among them, each
// vertex with a colour; the quads' colours vary across them.
Soup soup(int quads, int triangles) {
  Soup s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int q = 0; q < quads; ++q) {
    const float z = -4.0f - 0.01f * float(quads - q);  // farthest first
    const uint32_t first = uint32_t(s.pos.size());
    for (const glm::vec2 c : {glm::vec2(-9, -9), glm::vec2(9, -9), glm::vec2(9, 9), glm::vec2(-9, 9)}) {
      s.pos.push_back({c.x, c.y, z});
      s.var.insert(s.var.end(), {0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng)});
    }
    s.idx.insert(s.idx.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
  }
  for (int i = 0; i < triangles; ++i) {
    const glm::vec3 c(u(rng) * 3.0f, u(rng) * 2.0f, -4.5f + u(rng));
    for (int k = 0; k < 3; ++k) {
      s.pos.push_back(c + glm::vec3(u(rng), u(rng), 0.3f * u(rng)));
      s.var.insert(s.var.end(), {0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng)});
      s.idx.push_back(uint32_t(s.pos.size() - 1));
    }
  }
  return s;
}

DrawCall draw_of(const Soup& s, const Shader& sh, BlendMode blend) {
  DrawCall d;
  d.positions = s.pos.data();
  d.vertex_count = uint32_t(s.pos.size());
  d.indices = s.idx.data();
  d.triangle_count = uint32_t(s.idx.size() / 3);
  d.varyings = s.var.data();
  d.varying_count = 3;
  d.clip_from_object = glm::perspective(glm::radians(60.0f), float(kWidth) / kHeight, 0.5f, 20.0f);
  d.state.blend = blend;
  d.state.depth_write = false;
  d.shader = &sh;
  return d;
}

bool same_planes(const Image& a, const Image& b) {
  return std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(float)) == 0 &&
         std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0 && a.id == b.id;
}

RenderOptions exact(uint32_t cap) {
  RenderOptions o;
  o.background = {0.05f, 0.1f, 0.2f, 1.0f};
  o.sort = SortMode::Exact;
  o.exact_fragment_cap = cap;
  return o;
}

// An opaque quad behind part of the pile, a blended pile, and an additive draw among it: the
// same planes with every cap, bands or none, on every SIMD target (the planner and the
// composite are compiled per target) at 3 threads, and on the best target at 1 thread too
// (which threads draw which bands is the scheduler's, the same code on every target); with a
// cap the tiles are drawn in bands, holding no more fragments than it at once.
TEST(ExactBands, BandsDrawTheSamePlanesWithinTheCap) {
  const Soup pile = soup(40, 300), glow = soup(0, 60), wall = soup(1, 0);
  const VaryingShader blended(0.3f, true), added(0.2f, false), opaque(1.0f, false);
  Soup near_wall = wall;
  for (glm::vec3& p : near_wall.pos) p = glm::vec3(p.x * 0.1f + 0.3f, p.y * 0.1f, -4.2f);
  const DrawCall draws[3] = {draw_of(near_wall, opaque, BlendMode::Opaque), draw_of(pile, blended, BlendMode::AlphaOver),
                             draw_of(glow, added, BlendMode::Additive)};
  const std::string best = hwy::TargetName(hwy::SupportedAndGeneratedTargets().front());
  for_each_target([&](const std::string& target) {
    const Image whole = render(draws, kWidth, kHeight, 1, exact(kExactFragmentCap));
    // One pass a tile: 4 x 3 tiles, each of 64 x 64 or less, under the default cap.
    EXPECT_EQ(whole.stats.exact_passes, 12u) << target;
    EXPECT_GT(whole.stats.exact_fragments_peak, 40u * 64 * 64) << target;  // the pile: 40 layers a pixel
    // 20000: bands of rows; 4096: runs of a row's blocks; 700: most blocks alone (each holds
    // 640 or more). (A cap of 16, every block alone, took 25 s of the sanitized suite.)
    for (const uint32_t cap : {20000u, 4096u, 700u}) {
      for (const int threads : {3, 1}) {
        if (threads == 1 && target != best) continue;
        const Image banded = render(draws, kWidth, kHeight, threads, exact(cap));
        EXPECT_TRUE(same_planes(whole, banded)) << target << " cap " << cap << " threads " << threads;
        EXPECT_GT(banded.stats.exact_passes, whole.stats.exact_passes) << target << " cap " << cap;
        EXPECT_EQ(banded.stats.fragments_blended, whole.stats.fragments_blended) << target << " cap " << cap;
        // A block of 16 pixels under 40-odd layers leaves more than 16 or 700 fragments: drawn
        // alone, as many as it leaves; otherwise within the cap.
        if (cap >= 16u * 400u) EXPECT_LE(banded.stats.exact_fragments_peak, cap) << target << " cap " << cap;
        else EXPECT_LE(banded.stats.exact_fragments_peak, 16u * 400u) << target << " cap " << cap;
      }
    }
  });
}

// A translucent draw that writes depth among the pile (later fragments of its pixels then fail
// the test) and the overdraw plane (the fragments that passed, per pixel): the same values banded
// or not, at 1 and 3 threads.
TEST(ExactBands, DepthWritingLayersAndTheOverdrawPlaneKeepTheirValues) {
  const Soup pile = soup(30, 0), sheets = soup(0, 200);
  const VaryingShader blended(0.3f, true), written(0.5f, false);
  DrawCall writing = draw_of(sheets, written, BlendMode::AlphaOver);
  writing.state.depth_write = true;
  const DrawCall draws[3] = {draw_of(pile, blended, BlendMode::AlphaOver), writing,
                             draw_of(pile, blended, BlendMode::AlphaOver)};
  struct Planes {
    std::vector<float> color, depth;
    std::vector<uint32_t> overdraw;
    RasterStats stats;
  };
  const auto planes = [&](uint32_t cap, int threads) {
    Planes p;
    p.color.assign(size_t(kWidth) * kHeight * 4, 0.0f);
    p.depth.assign(size_t(kWidth) * kHeight, 0.0f);
    p.overdraw.assign(size_t(kWidth) * kHeight, 0u);
    Renderer r(threads);
    RenderTarget t{kWidth, kHeight, p.color.data(), p.depth.data()};
    t.overdraw = p.overdraw.data();
    r.render(draws, exact(cap), t, &p.stats);
    return p;
  };
  const Planes whole = planes(kExactFragmentCap, 1);
  for (const int threads : {1, 3}) {
    const Planes banded = planes(2000, threads);
    EXPECT_GT(banded.stats.exact_passes, whole.stats.exact_passes);
    EXPECT_EQ(banded.color, whole.color) << threads;
    EXPECT_EQ(banded.depth, whole.depth) << threads;
    EXPECT_EQ(banded.overdraw, whole.overdraw) << threads;
  }
  // The written depth holds fragments back: fewer than the two piles' layers at some pixel.
  EXPECT_LT(*std::min_element(whole.overdraw.begin(), whole.overdraw.end()), 60u);
}

// Slivers whose bounding boxes cover whole tiles but whose fragments are few: counted, they fit
// the cap, and every tile is drawn in one pass, as without a cap.
TEST(ExactBands, ATileWhoseFragmentsFitTheCapIsOnePass) {
  Soup slivers;
  for (int i = 0; i < 150; ++i) {
    const float y = -2.0f + 0.027f * float(i), z = -4.0f - 0.001f * float(i);
    const uint32_t first = uint32_t(slivers.pos.size());
    slivers.pos.insert(slivers.pos.end(), {{-3.0f, y - 1.5f, z}, {3.0f, y + 1.5f, z}, {3.0f, y + 1.52f, z}});
    slivers.var.insert(slivers.var.end(), 9, 0.5f);
    slivers.idx.insert(slivers.idx.end(), {first, first + 1, first + 2});
  }
  const VaryingShader sh(0.3f, true);
  const DrawCall d = draw_of(slivers, sh, BlendMode::AlphaOver);
  const Image whole = render({&d, 1}, kWidth, kHeight, 1, exact(kExactFragmentCap));
  const Image capped = render({&d, 1}, kWidth, kHeight, 1, exact(4000));
  ASSERT_LE(whole.stats.exact_fragments_peak, 4000u);  // the slivers leave few fragments a tile
  EXPECT_EQ(capped.stats.exact_passes, whole.stats.exact_passes);
  EXPECT_TRUE(same_planes(whole, capped));
}

// Whatever the triangles (small, thin, large), no pass holds more than the cap: the bounds that
// let a tile skip its count (a triangle's area and perimeter, its bounding box) never fall short.
// Small ones make tiles whose count is near the caps: there a bound of a quarter of the true one
// let tiles through in one pass holding more than the cap (seen by mutation).
TEST(ExactBands, NoPassHoldsMoreThanTheCap) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Soup soup_of_shapes;
  for (int i = 0; i < 600; ++i) {
    const glm::vec3 c(u(rng) * 3.0f, u(rng) * 2.0f, -4.5f + u(rng));
    const float size = i % 50 == 0 ? 2.0f : i % 3 == 0 ? 0.3f : i % 3 == 1 ? 0.15f : 0.06f;
    const glm::vec3 d(u(rng), u(rng), 0.0f);
    const glm::vec3 thin = i % 4 == 0 ? glm::vec3(-d.y, d.x, 0.0f) * 0.01f : glm::vec3(u(rng), u(rng), 0.0f);
    const uint32_t first = uint32_t(soup_of_shapes.pos.size());
    soup_of_shapes.pos.insert(soup_of_shapes.pos.end(), {c, c + d * size, c + (d + thin) * size});
    soup_of_shapes.var.insert(soup_of_shapes.var.end(), 9, 0.5f);
    soup_of_shapes.idx.insert(soup_of_shapes.idx.end(), {first, first + 1, first + 2});
  }
  const VaryingShader sh(0.3f, false);
  const DrawCall d = draw_of(soup_of_shapes, sh, BlendMode::AlphaOver);
  const Image whole = render({&d, 1}, kWidth, kHeight, 1, exact(kExactFragmentCap));
  for (const uint32_t cap : {400u, 800u, 1500u, 3000u, 6000u}) {
    const Image capped = render({&d, 1}, kWidth, kHeight, 2, exact(cap));
    EXPECT_LE(capped.stats.exact_fragments_peak, cap) << cap;
    EXPECT_EQ(capped.color, whole.color) << cap;  // no derivatives: packing moves nothing
  }
}

// The composite of a band matches the scalar order it stands for: a pixel under the pile holds
// the layers back to front over the background, whatever the bands.
TEST(ExactBands, APileIsCompositedBackToFront) {
  const Soup pile = soup(25, 0);
  const VaryingShader sh(0.25f, false);
  const DrawCall d = draw_of(pile, sh, BlendMode::AlphaOver);
  const Image img = render({&d, 1}, kWidth, kHeight, 2, exact(1000));
  ASSERT_GT(img.stats.exact_passes, 12u);
  // The quads are submitted farthest first, so drawing them in submission order (SortMode::None,
  // blended as they come) is the back-to-front order the exact sort must find.
  RenderOptions none = exact(kExactFragmentCap);
  none.sort = SortMode::None;
  const Image in_order = render({&d, 1}, kWidth, kHeight, 2, none);
  for (size_t i = 0; i < img.color.size(); ++i) ASSERT_NEAR(img.color[i], in_order.color[i], 1e-6f) << i;
}

}  // namespace exact_bands_test
}  // namespace pelt::raster::test
