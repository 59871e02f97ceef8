// RenderTarget::overdraw: per pixel, the translucent fragments that passed the depth test. It
// must count exactly the fragments the scalar reference rasterizer finds (the translucent
// draws depth-tested against the opaque ones, without depth writes), once per fragment for
// every sort mode and thread count, a pixel on a shared edge once, and leave the colour alone.
// And the colour the translucent pass blends from those fragments, per pixel against a scalar
// compositor over the reference's fragment lists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "tests/raster/reference_raster.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace overdraw_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

constexpr int kW = 150, kH = 110;  // partial tiles on both axes

struct Soup {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;

  DrawCall draw(const Shader& sh, BlendMode blend) const {
    DrawCall d;
    d.positions = pos.data();
    d.vertex_count = uint32_t(pos.size());
    d.indices = idx.data();
    d.triangle_count = uint32_t(idx.size() / 3);
    d.shader = &sh;
    d.state.blend = blend;
    d.state.depth_write = blend == BlendMode::Opaque;
    d.state.depth_func = DepthFunc::LessEqual;
    return d;
  }
};

// Random triangles in NDC, from a pixel wide to larger than the viewport, at random depths.
Soup random_triangles(std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> u(-1.2f, 1.2f), size(0.01f, 1.5f), depth(-0.9f, 0.9f);
  Soup s;
  for (int i = 0; i < count; ++i) {
    const float cx = u(rng), cy = u(rng), r = size(rng), z = depth(rng);
    for (int k = 0; k < 3; ++k) {
      s.pos.push_back({cx + r * u(rng), cy + r * u(rng), z + 0.1f * u(rng)});
      s.idx.push_back(uint32_t(s.pos.size() - 1));
    }
  }
  return s;
}

// A grid of n x n quads over most of the viewport, two triangles each, every inner edge shared
// (by index) between two triangles: a pixel on a shared edge belongs to one of them.
Soup quad_grid(int n, float z) {
  Soup s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.pos.push_back({-0.9f + 1.8f * i / n, -0.85f + 1.7f * j / n + 0.01f * i, z});
  auto at = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      s.idx.insert(s.idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
  return s;
}

struct Counted {
  std::vector<float> color;
  std::vector<uint32_t> overdraw;
  RasterStats stats;
};

Counted render_counted(std::span<const DrawCall> draws, int threads, SortMode sort, bool count) {
  Counted c;
  c.color.assign(size_t(kW) * kH * 4, -1.0f);
  if (count) c.overdraw.assign(size_t(kW) * kH, 0xDEADBEEFu);
  RenderTarget t{kW, kH, c.color.data()};
  t.overdraw = count ? c.overdraw.data() : nullptr;
  RenderOptions opt;
  opt.sort = sort;
  Renderer(threads).render(draws, opt, t, &c.stats);
  return c;
}

// The reference's translucent fragments per pixel: the opaque draws, then the translucent ones
// drawn as opaque without depth writes; the difference of the two counts.
std::vector<uint32_t> reference_overdraw(std::span<const DrawCall> opaque, std::span<const DrawCall> translucent) {
  std::vector<DrawCall> all(opaque.begin(), opaque.end());
  for (DrawCall d : translucent) {
    d.state.blend = BlendMode::Opaque;
    d.state.depth_write = false;
    all.push_back(d);
  }
  const ReferenceImage base = reference_render(opaque, kW, kH), with = reference_render(all, kW, kH);
  std::vector<uint32_t> out(base.count.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = with.count[i] - base.count[i];
  return out;
}

TEST(Overdraw, CountsTheFragmentsTheReferenceFindsOnEveryTargetSortAndThreadCount) {
  std::mt19937 rng(42);
  const Soup walls = random_triangles(rng, 40), glass = random_triangles(rng, 300), grid = quad_grid(7, 0.2f);
  const ConstantShader grey({0.5f, 0.5f, 0.5f, 1.0f}), tint({0.9f, 0.3f, 0.1f, 0.25f});
  const VaryingShader lanes(0.4f, true);  // derivatives: triangles pack only across shared edges
  const DrawCall opaque[] = {walls.draw(grey, BlendMode::Opaque)};
  const DrawCall translucent[] = {glass.draw(tint, BlendMode::AlphaOver), grid.draw(lanes, BlendMode::AlphaOver),
                                  glass.draw(tint, BlendMode::Additive)};
  const std::vector<uint32_t> want = reference_overdraw(opaque, translucent);
  const uint64_t total = std::accumulate(want.begin(), want.end(), uint64_t{0});
  ASSERT_GT(total, uint64_t{kW} * kH);  // piles of fragments, and some pixels hidden
  ASSERT_GT(std::count(want.begin(), want.end(), 0u), 0);

  std::vector<DrawCall> draws(std::begin(opaque), std::end(opaque));
  draws.insert(draws.end(), std::begin(translucent), std::end(translucent));
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact})
      for (int threads : {0, 1, 2}) {
        const std::string what = target + " sort " + std::to_string(int(sort)) + " threads " + std::to_string(threads);
        const Counted got = render_counted(draws, threads, sort, true);
        size_t wrong = 0, first = 0;
        for (size_t i = 0; i < want.size(); ++i)
          if (got.overdraw[i] != want[i] && wrong++ == 0) first = i;
        EXPECT_EQ(wrong, 0u) << what << ": first at pixel (" << first % kW << ", " << first / kW << "): "
                             << got.overdraw[first] << " against " << want[first];
        EXPECT_EQ(got.stats.fragments_blended, total) << what;
        // Counting does not touch the picture.
        const Counted plain = render_counted(draws, threads, sort, false);
        EXPECT_EQ(0, std::memcmp(plain.color.data(), got.color.data(), got.color.size() * sizeof(float))) << what;
      }
  });
}

TEST(Overdraw, APixelOnASharedEdgeCountsOnce) {
  const Soup grid = quad_grid(9, 0.0f);
  const ConstantShader tint({0.2f, 0.4f, 0.9f, 0.5f});
  const DrawCall d = grid.draw(tint, BlendMode::AlphaOver);
  for_each_target([&](const std::string& target) {
    const Counted got = render_counted({&d, 1}, 1, SortMode::Tile, true);
    size_t covered = 0;
    for (uint32_t c : got.overdraw) {
      ASSERT_LE(c, 1u) << target;
      covered += c;
    }
    EXPECT_GT(covered, size_t(kW) * kH / 2) << target;  // the grid covers most of the frame
    EXPECT_EQ(covered, got.stats.fragments_blended) << target;
  });
}

// The translucent pass's colour (tile_kernels.cc: FlushBatch's src-over and additive blends, the
// exact sort's CompositeExact) against a scalar compositor over the reference rasterizer's
// per-pixel fragment lists: the opaque colour, then the translucent fragments that passed the
// depth test, in submission order (SortMode::None) or, for SortMode::Exact, the additive ones in
// submission order (they are blended as they come) and then the src-over ones farthest first,
// equal depths in submission order; for SortMode::Tile, all of them by the caller's sort keys
// (DrawCall::sort_keys, largest first, NaN first, ties in submission order). Every fragment has its triangle's own colour, so any change
// of order, any lost or doubled fragment, shows. Hard cases: alphas outside [0, 1] and NaN
// (clamped; NaN counts as 0), alpha 0 and 1, every triangle of one draw submitted twice (piles of
// equal depths), a pile of 66 layers (more than the 64 fragments the exact sort
// sorts in place), depth functions Less, LessEqual and Always, shaders with and without
// derivatives (which decide how triangles share a batch's blocks), partial tiles, two threads.
TEST(Overdraw, BlendedColourMatchesAPerPixelCompositorOnEveryTarget) {
  std::mt19937 rng(7);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Soup walls = random_triangles(rng, 30), glass = random_triangles(rng, 80), glow = random_triangles(rng, 40);
  const Soup grid = quad_grid(6, 0.1f);
  Soup twice = random_triangles(rng, 40);
  Soup pile;
  for (int k = 0; k < 66; ++k) {  // layers over a fifth of the frame; every fifth at the depth of the one before
    const float z = 0.5f - 0.01f * float(k - k / 5);
    for (const glm::vec3 v : {glm::vec3(-0.5f, -0.4f, z), glm::vec3(0.5f, -0.4f, z), glm::vec3(0, 0.5f, z)}) {
      pile.pos.push_back(v);
      pile.idx.push_back(uint32_t(pile.pos.size() - 1));
    }
  }
  const size_t once = twice.idx.size();
  for (size_t i = 0; i < once; ++i) twice.idx.push_back(twice.idx[i]);
  const PrimitiveShader opaque_sh(1, {1.0f}), glass_sh(2, {0.3f, 0.6f, 1.5f, -0.25f, nan, 0.0f, 1.0f});
  const PrimitiveShader glow_sh(3, {0.5f, 2.0f, nan, -1.0f}), grid_sh(4, {0.4f, 0.8f}, true);
  const PrimitiveShader twice_sh(5, {0.5f, 0.7f}, true), pile_sh(6, {0.05f, 0.1f, 0.2f});
  std::vector<DrawCall> draws = {walls.draw(opaque_sh, BlendMode::Opaque), glass.draw(glass_sh, BlendMode::AlphaOver),
                                 glow.draw(glow_sh, BlendMode::Additive), grid.draw(grid_sh, BlendMode::AlphaOver),
                                 twice.draw(twice_sh, BlendMode::AlphaOver), pile.draw(pile_sh, BlendMode::AlphaOver),
                                 glass.draw(glow_sh, BlendMode::Additive)};
  draws[2].state.depth_func = DepthFunc::Less;
  draws[3].state.depth_func = DepthFunc::Always;
  // The tile sort's keys, the caller's: ties, -0 against 0, NaN (first, in submission order).
  const float key_values[] = {0.5f, 0.25f, 0.0f, -0.0f, 1.0f, 2.0f, nan};
  std::vector<std::vector<float>> keys(draws.size());
  for (size_t k = 1; k < draws.size(); ++k) {
    for (uint32_t p = 0; p < draws[k].triangle_count; ++p) keys[k].push_back(key_values[rng() % std::size(key_values)]);
    draws[k].sort_keys = keys[k].data();
  }
  const PrimitiveShader* shaders[] = {&opaque_sh, &glass_sh, &glow_sh, &grid_sh, &twice_sh, &pile_sh, &glow_sh};

  // The reference's fragments: the opaque draw, then the translucent ones drawn as opaque
  // without depth writes (so each is tested against the opaque depth only).
  std::vector<DrawCall> as_opaque = draws;
  for (size_t k = 1; k < as_opaque.size(); ++k) {
    as_opaque[k].state.blend = BlendMode::Opaque;
    as_opaque[k].state.depth_write = false;
  }
  const ReferenceImage ref = reference_render(as_opaque, kW, kH, true);
  const glm::vec4 bg(0.05f, 0.1f, 0.2f, 0.75f);
  size_t most = 0;
  for (const auto& f : ref.fragments) most = std::max(most, f.size());
  ASSERT_GT(most, 64u) << "no pile takes the exact sort's long path";

  auto composite = [&](size_t pixel, SortMode sort) {
    glm::vec4 c = bg;
    if (ref.id[pixel] != 0) c = opaque_sh.colour(ref.id[pixel] - 1);
    std::vector<ReferenceFragment> frags;
    for (const ReferenceFragment& f : ref.fragments[pixel])
      if (f.draw != 0) frags.push_back(f);
    auto additive = [&](const ReferenceFragment& f) { return draws[f.draw].state.blend == BlendMode::Additive; };
    if (sort == SortMode::Exact) {
      std::stable_partition(frags.begin(), frags.end(), additive);
      const auto over = std::find_if_not(frags.begin(), frags.end(), additive);
      std::stable_sort(over, frags.end(), [](const auto& a, const auto& b) { return a.depth > b.depth; });
    }
    if (sort == SortMode::Tile)  // back_to_front_before (translucent_sort.h), ties in submission order
      std::stable_sort(frags.begin(), frags.end(), [&](const auto& a, const auto& b) {
        const float ka = keys[a.draw][a.primitive], kb = keys[b.draw][b.primitive];
        return ka != ka || kb != kb ? ka != ka && kb == kb : ka > kb;
      });
    for (const ReferenceFragment& f : frags) {
      const glm::vec4 s = shaders[f.draw]->colour(f.primitive);
      const float a = s[3] > 0.0f ? std::min(s[3], 1.0f) : 0.0f, keep = 1.0f - a;
      if (additive(f)) {
        for (int k = 0; k < 3; ++k) c[k] = c[k] + s[k] * a;
      } else {
        for (int k = 0; k < 3; ++k) c[k] = s[k] * a + c[k] * keep;
        c[3] = a + c[3] * keep;
      }
    }
    return c;
  };
  for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
    std::vector<glm::vec4> want(size_t(kW) * kH);
    for (size_t i = 0; i < want.size(); ++i) want[i] = composite(i, sort);
    for_each_target([&](const std::string& target) {
      const int threads = 2;  // the tiles in any order
      RenderOptions opt;
      opt.background = bg;
      opt.sort = sort;
      const Image img = render(draws, kW, kH, threads, opt);
      size_t wrong = 0;
      for (size_t i = 0; i < want.size(); ++i)
        for (int k = 0; k < 4; ++k) {
          const float got = img.color[i * 4 + k], w = want[i][k];
          // The blends are the compositor's float operations in its order (no fused
          // multiply-add): only a rounding's worth of slack.
          if (std::abs(got - w) <= 1e-6f * std::max(1.0f, std::abs(w))) continue;
          if (wrong++ < 5)
            ADD_FAILURE() << target << " sort " << int(sort) << " threads " << threads << " pixel (" << i % kW
                          << ", " << i / kW << ") channel " << k << ": " << got << " against " << w << " ("
                          << ref.fragments[i].size() << " fragments)";
        }
      EXPECT_EQ(wrong, 0u) << target << " sort " << int(sort) << " threads " << threads;
    });
  }
}

}  // namespace overdraw_test
}  // namespace pelt::raster::test
