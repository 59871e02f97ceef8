// The image is bit-identical for any thread count (and with threads = 0, inline).
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/parallel.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace {

// `count` random triangles in front of the camera, of side about `size` (0: each its own, in
// [0.05, 1.05]), with random colours: the first half drawn opaque, the second through glass
// (alpha 0.35, no depth write).
struct GlassSoup {
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  VaryingShader opaque_sh{1.0f}, glass_sh{0.35f};
  DrawCall opaque, glass;

  GlassSoup(unsigned seed, int count, float size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < count; ++i) {
      const glm::vec3 c(u(rng) * 3.0f, u(rng) * 3.0f, -5.0f + u(rng) * 3.0f);
      const float s = size > 0.0f ? size : 0.05f + 0.5f * (u(rng) + 1.0f);
      for (int k = 0; k < 3; ++k) {
        pos.push_back(c + s * glm::vec3(u(rng), u(rng), u(rng)));
        var.insert(var.end(), {0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng)});
        idx.push_back(uint32_t(pos.size() - 1));
      }
    }
    const uint32_t half = uint32_t(count / 2);
    opaque.positions = pos.data();
    opaque.vertex_count = uint32_t(pos.size());
    opaque.indices = idx.data();
    opaque.triangle_count = half;
    opaque.varyings = var.data();
    opaque.varying_count = 3;
    opaque.clip_from_object = glm::perspective(glm::radians(60.0f), 4.0f / 3.0f, 0.5f, 20.0f);
    opaque.shader = &opaque_sh;
    glass = opaque;
    glass.indices = idx.data() + 3 * size_t{half};
    glass.shader = &glass_sh;
    glass.state.blend = BlendMode::AlphaOver;
    glass.state.depth_write = false;
  }
  GlassSoup(const GlassSoup&) = delete;
  GlassSoup& operator=(const GlassSoup&) = delete;
};

TEST(Determinism, OneTwoAndEightThreadsGiveIdenticalImages) {
  const GlassSoup soup(42, 6000, 0.0f);
  const DrawCall draws[2] = {soup.opaque, soup.glass};
  for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
    RenderOptions opt;
    opt.sort = sort;
    const Image base = render(draws, 333, 222, 1, opt);
    EXPECT_GT(base.stats.fragments_blended, 10000u);
    for (int threads : {0, 2, 8}) {
      const Image img = render(draws, 333, 222, threads, opt);
      EXPECT_EQ(0, std::memcmp(img.color.data(), base.color.data(), base.color.size() * 4)) << threads;
      EXPECT_EQ(0, std::memcmp(img.depth.data(), base.depth.data(), base.depth.size() * 4)) << threads;
      EXPECT_EQ(img.id, base.id) << threads;
      EXPECT_EQ(img.stats.fragments_blended, base.stats.fragments_blended);
    }
  }
}

// Opaque shading packs the visible pixels of several triangles into one block unless the
// shader takes derivatives; both ways every visible pixel gets its own triangle's values.
TEST(Determinism, PackedAndPerTriangleOpaqueShadingAgree) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  for (int i = 0; i < 3000; ++i) {
    const glm::vec3 c(u(rng) * 3.0f, u(rng) * 3.0f, -5.0f + u(rng) * 3.0f);
    for (int k = 0; k < 3; ++k) {
      pos.push_back(c + 0.4f * glm::vec3(u(rng), u(rng), u(rng)));
      var.insert(var.end(), {u(rng), u(rng), u(rng)});
      idx.push_back(uint32_t(pos.size() - 1));
    }
  }
  const VaryingShader packed(1.0f, false), per_triangle(1.0f, true);
  DrawCall d;
  d.positions = pos.data();
  d.vertex_count = uint32_t(pos.size());
  d.indices = idx.data();
  d.triangle_count = 3000;
  d.varyings = var.data();
  d.varying_count = 3;
  d.clip_from_object = glm::perspective(glm::radians(60.0f), 4.0f / 3.0f, 0.5f, 20.0f);
  d.shader = &packed;
  for_each_target([&](const std::string& target) {
    const Image a = render({&d, 1}, 200, 150);
    DrawCall e = d;
    e.shader = &per_triangle;
    const Image b = render({&e, 1}, 200, 150);
    EXPECT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * 4)) << target;
    EXPECT_EQ(a.stats.pixels_shaded, b.stats.pixels_shaded) << target;
  });
}

// start_worker_threads only starts threads early: any width, called again, returns (its wait
// is bounded) and leaves pools computing every item exactly once, in their own slots.
TEST(Determinism, StartingWorkerThreadsEarlyLeavesPoolsAsTheyWere) {
  for (int threads : {0, 1, 2, 64, 2}) start_worker_threads(threads);
  for (int threads : {1, 2, 3}) {
    ThreadPool pool(threads);
    std::vector<std::atomic<int>> hits(1000);
    std::atomic<bool> slot_ok{true};
    pool.parallel_for(hits.size(), [&](size_t i, int slot) {
      hits[i].fetch_add(1);
      if (slot < 0 || slot >= pool.slots()) slot_ok = false;
    });
    for (size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << threads << " threads, item " << i;
    EXPECT_TRUE(slot_ok.load()) << threads << " threads";
  }
}

// A renderer is reused frame after frame (the CLI's animations, the benchmarks): a frame must
// come out the same, image and RasterStats counters, whether the renderer is fresh or has
// drawn other frames before, at any thread count. Kills a per-frame counter that is not reset
// (renderer.cpp: fragments_visible accumulating over frames).
TEST(Determinism, AReusedRendererGivesEachFrameItsOwnImageAndStats) {
  const GlassSoup soup(7, 800, 0.6f);
  const DrawCall frame[2] = {soup.opaque, soup.glass};
  const DrawCall other[1] = {soup.glass};  // a different frame drawn in between
  const int w = 200, h = 150;
  auto counters = [](const RasterStats& s) {
    return std::vector<uint64_t>{s.triangles_submitted, s.triangles_culled, s.triangles_clipped,
                                 s.triangles_setup,     s.bin_items,        s.fragments_visible,
                                 s.pixels_shaded,       s.fragments_blended, s.lanes_shaded};
  };
  for (int threads : {1, 2}) {
    RenderOptions opt;
    opt.sort = SortMode::Tile;
    const Image fresh = render(frame, w, h, threads, opt);
    ASSERT_GT(fresh.stats.fragments_visible, 1000u);
    Renderer r(threads);
    std::vector<float> color(size_t(w) * h * 4);
    std::vector<uint32_t> id(size_t(w) * h);
    const RenderTarget target{w, h, color.data(), nullptr, id.data()};
    RasterStats st;
    for (int k = 0; k < 3; ++k) {
      r.render(other, opt, target, &st);
      r.render(frame, opt, target, &st);
      EXPECT_EQ(counters(st), counters(fresh.stats)) << threads << " threads, frame " << k;
      EXPECT_EQ(0, std::memcmp(color.data(), fresh.color.data(), color.size() * 4)) << threads << " threads";
      EXPECT_EQ(id, fresh.id) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace pelt::raster::test
