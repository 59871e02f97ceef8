// Perspective-correct varyings against the analytic value on a tilted plane, and the
// translucent pass: compositing order and blending formulas with closed-form answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace {

TEST(Interpolation, TextureCoordinateOnATiltedPlaneIsPerspectiveCorrect) {
  // The plane z = -3 + 0.8 x in view space, u = x, v = y; camera at the origin.
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  for (float y : {-3.0f, 3.0f})
    for (float x : {-3.0f, 3.0f}) {
      pos.push_back({x, y, -3.0f + 0.8f * x});
      var.insert(var.end(), {x, y});
    }
  idx = {0, 1, 3, 0, 3, 2};
  const int w = 160, h = 120;
  const float fovy = glm::radians(60.0f), aspect = float(w) / h;
  const VaryingShader sh;
  DrawCall d;
  d.positions = pos.data();
  d.vertex_count = 4;
  d.indices = idx.data();
  d.triangle_count = 2;
  d.varyings = var.data();
  d.varying_count = 2;
  d.clip_from_object = glm::perspective(fovy, aspect, 0.5f, 20.0f);
  d.shader = &sh;
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, w, h);
    double worst = 0.0, worst_affine_gap = 0.0;
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        const size_t i = size_t(py) * w + px;
        if (img.id[i] == 0) continue;
        const double nx = (px + 0.5) / w * 2.0 - 1.0, ny = 1.0 - (py + 0.5) / h * 2.0;
        const double dx = nx * std::tan(fovy / 2) * aspect, dy = ny * std::tan(fovy / 2);
        const double t = 3.0 / (1.0 + 0.8 * dx);  // ray (dx, dy, -1) meets the plane
        const double u = t * dx, v = t * dy;
        worst = std::max({worst, std::abs(img.color[i * 4] - u), std::abs(img.color[i * 4 + 1] - v)});
        // Screen-linear interpolation would be off by this much: the test can tell.
        worst_affine_gap = std::max(worst_affine_gap, std::abs(u - (nx * 3.0)));
      }
    EXPECT_LT(worst, 2e-4) << target;
    EXPECT_GT(worst_affine_gap, 0.1);
  });
}

struct Layers {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  void add_quad(float z) {
    const uint32_t b = uint32_t(pos.size());
    for (float y : {-2.0f, 2.0f})
      for (float x : {-2.0f, 2.0f}) pos.push_back({x, y, z});
    idx.insert(idx.end(), {b, b + 1, b + 3, b, b + 3, b + 2});
  }
};

// src over dst, straight colour: what every translucent fragment does to its pixel.
glm::vec4 over(glm::vec4 src, glm::vec4 dst) {
  return glm::vec4(glm::vec3(src) * src.a + glm::vec3(dst) * (1 - src.a), src.a + dst.a * (1 - src.a));
}

// A 64 x 64 frame of `draws` over `bg`, translucent fragments in `sort`.
Image render_over(std::span<const DrawCall> draws, glm::vec4 bg, SortMode sort, int threads = 2) {
  RenderOptions opt;
  opt.background = bg;
  opt.sort = sort;
  return render(draws, 64, 64, threads, opt);
}

// Constant-alpha layers submitted in a scrambled order composite, with per-tile sorting,
// to the closed-form back-to-front result.
TEST(Blending, TileSortCompositesLayersBackToFrontInAnyDrawOrder) {
  const int n = 6;
  std::vector<float> depth_of(n);
  std::vector<int> order = {3, 0, 5, 1, 4, 2};
  std::vector<std::unique_ptr<ConstantShader>> shaders;
  std::vector<Layers> layers(n);
  std::vector<DrawCall> draws;
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
  auto colour = [](int k) { return glm::vec4(0.1f + 0.15f * k, 1.0f - 0.12f * k, 0.5f, 0.3f + 0.1f * k); };
  for (int k : order) {
    layers[k].add_quad(-2.0f - 0.5f * k);  // layer k is farther for larger k
    shaders.push_back(std::make_unique<ConstantShader>(colour(k)));
  }
  for (size_t i = 0; i < order.size(); ++i) {
    const Layers& l = layers[order[i]];
    DrawCall d;
    d.positions = l.pos.data();
    d.vertex_count = 4;
    d.indices = l.idx.data();
    d.triangle_count = 2;
    d.clip_from_object = proj;
    d.shader = shaders[i].get();
    d.state.blend = BlendMode::AlphaOver;
    d.state.depth_write = false;
    draws.push_back(d);
  }
  glm::dvec4 expect(0.05, 0.1, 0.2, 1.0);
  for (int k = n - 1; k >= 0; --k) {
    const glm::dvec4 c = colour(k);
    expect = glm::dvec4(glm::dvec3(c) * c.a + glm::dvec3(expect) * (1.0 - c.a), c.a + expect.a * (1.0 - c.a));
  }
  RenderOptions opt;
  opt.background = glm::vec4(0.05f, 0.1f, 0.2f, 1.0f);
  opt.sort = SortMode::Tile;
  for_each_target([&](const std::string& target) {
    const Image img = render(draws, 96, 96, 2, opt);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(img.color[(48 * 96 + 48) * 4 + c], expect[c], 1e-5) << target;
    RenderOptions exact = opt;
    exact.sort = SortMode::Exact;
    const Image ex = render(draws, 96, 96, 2, exact);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(ex.color[(48 * 96 + 48) * 4 + c], expect[c], 1e-5) << target;
    // Without sorting, the scrambled order gives a different (wrong) colour.
    RenderOptions unsorted = opt;
    unsorted.sort = SortMode::None;
    const Image raw = render(draws, 96, 96, 2, unsorted);
    EXPECT_GT(std::abs(raw.color[(48 * 96 + 48) * 4] - expect[0]), 1e-3) << target;
  });
}

// Two translucent quads that cross each other: no triangle order is right everywhere,
// per-pixel sorting is. Left of the crossing quad A is nearer, right of it quad B.
TEST(Blending, ExactSortCompositesIntersectingLayersPerPixel) {
  std::vector<glm::vec3> pa = {{-2, -2, -2.0f}, {2, -2, -4.0f}, {-2, 2, -2.0f}, {2, 2, -4.0f}};
  std::vector<glm::vec3> pb = {{-2, -2, -4.0f}, {2, -2, -2.0f}, {-2, 2, -4.0f}, {2, 2, -2.0f}};
  std::vector<uint32_t> idx = {0, 1, 3, 0, 3, 2};
  const glm::vec4 ca(1, 0, 0, 0.6f), cb(0, 0, 1, 0.6f);
  const ConstantShader sa(ca), sb(cb);
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
  auto quad = [&](const std::vector<glm::vec3>& p, const Shader* sh) {
    DrawCall d;
    d.positions = p.data();
    d.vertex_count = 4;
    d.indices = idx.data();
    d.triangle_count = 2;
    d.clip_from_object = proj;
    d.shader = sh;
    d.state.blend = BlendMode::AlphaOver;
    d.state.depth_write = false;
    return d;
  };
  const DrawCall draws[2] = {quad(pa, &sa), quad(pb, &sb)};
  const glm::vec4 bg(0, 0, 0, 1);
  const glm::vec4 left = over(ca, over(cb, bg));   // A nearer: B first, then A
  const glm::vec4 right = over(cb, over(ca, bg));
  RenderOptions opt;
  opt.background = bg;
  opt.sort = SortMode::Exact;
  for_each_target([&](const std::string& target) {
    const Image img = render(draws, 64, 64, 2, opt);
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(img.color[(32 * 64 + 12) * 4 + c], left[c], 1e-6) << target;
      EXPECT_NEAR(img.color[(32 * 64 + 52) * 4 + c], right[c], 1e-6) << target;
    }
    opt.sort = SortMode::None;  // submission order is right on one side only
    const Image raw = render(draws, 64, 64, 2, opt);
    EXPECT_GT(std::abs(raw.color[(32 * 64 + 12) * 4] - left[0]), 0.05f) << target;
    opt.sort = SortMode::Exact;
  });
}

// A translucent quad over the whole view at view depth 3, tilted so its depth varies.
DrawCall translucent_quad(const Layers& l, const Shader* sh, BlendMode blend) {
  DrawCall d;
  d.positions = l.pos.data();
  d.vertex_count = uint32_t(l.pos.size());
  d.indices = l.idx.data();
  d.triangle_count = uint32_t(l.idx.size() / 3);
  d.clip_from_object = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
  d.shader = sh;
  d.state.blend = blend;
  d.state.depth_write = false;
  return d;
}

// renderer.h: Exact composites far to near, and fragments of equal depth in submission order,
// as the tile sort and no sort do (a coplanar decal drawn after its base lands on top). Two
// copies of one quad give every pixel two fragments of bit-identical depth. Kills the exact
// sort's tie-break reversed (tile_kernels.cc, CompositeExact).
TEST(Blending, EqualDepthsCompositeInSubmissionOrderInEverySortMode) {
  Layers l;
  l.add_quad(-3.0f);
  const glm::vec4 red(1, 0, 0, 0.5f), blue(0, 0, 1, 0.5f), bg(0.05f, 0.1f, 0.2f, 1.0f);
  const ConstantShader sr(red), sb(blue);
  const DrawCall draws[2] = {translucent_quad(l, &sr, BlendMode::AlphaOver),
                             translucent_quad(l, &sb, BlendMode::AlphaOver)};
  const glm::vec4 expect = over(blue, over(red, bg));
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
      const Image img = render_over(draws, bg, sort);
      for (size_t p : {size_t(32 * 64 + 32), size_t(5 * 64 + 60), size_t(60 * 64 + 3)})
        for (int c = 0; c < 4; ++c)
          EXPECT_NEAR(img.color[p * 4 + c], expect[c], 1e-6) << target << " sort " << int(sort) << " pixel " << p;
    }
  });
}

// The exact sort orders a pixel's pile the same way whatever its height: a short pile in place,
// one of more than 64 fragments through its indices (tile_kernels.cc, CompositeExact). Layers
// submitted in a scrambled order, every depth shared by two of them (submission order decides
// between those), composite farthest first.
TEST(Blending, ExactSortCompositesShortAndTallPilesFarthestFirst) {
  for (const int n : {20, 150}) {
    std::vector<int> order(n);
    for (int k = 0; k < n; ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), std::mt19937(11));
    std::vector<Layers> layers(n);
    std::vector<std::unique_ptr<ConstantShader>> shaders;
    std::vector<DrawCall> draws;
    auto colour = [](int k) {
      return glm::vec4(0.1f + 0.8f * float(k % 7) / 6.0f, 0.9f - 0.8f * float(k % 5) / 4.0f, 0.3f, 0.05f + 0.1f * float(k % 4));
    };
    auto depth = [](int k) { return -2.0f - 0.05f * float(k / 2); };  // layers 2j and 2j + 1 share a depth
    for (int i = 0; i < n; ++i) {
      const int k = order[i];
      layers[i].add_quad(depth(k));
      shaders.push_back(std::make_unique<ConstantShader>(colour(k)));
      draws.push_back(translucent_quad(layers[i], shaders.back().get(), BlendMode::AlphaOver));
    }
    // Farthest first; between equal depths, the one submitted first.
    std::vector<int> by_depth(order);
    std::stable_sort(by_depth.begin(), by_depth.end(), [&](int a, int b) { return depth(a) < depth(b); });
    const glm::vec4 bg(0.05f, 0.1f, 0.2f, 1.0f);
    glm::vec4 expect = bg;
    for (int k : by_depth) {
      expect = over(colour(k), expect);
    }
    for_each_target([&](const std::string& target) {
      const Image img = render_over(draws, bg, SortMode::Exact);
      for (size_t p : {size_t(32 * 64 + 32), size_t(5 * 64 + 60), size_t(60 * 64 + 3)})
        for (int c = 0; c < 4; ++c)
          EXPECT_NEAR(img.color[p * 4 + c], expect[c], 1e-5) << target << " layers " << n << " pixel " << p;
    });
  }
}

// pipeline.h: Additive is C = Cd + Cs a, A = Ad: the source is weighted by its alpha (a
// quarter-transparent glow adds a quarter of its colour) and leaves the target's alpha alone.
// Kills the additive blend dropping the alpha weight (tile_kernels.cc, FlushBatch).
TEST(Blending, AdditiveAddsTheColourWeightedByAlpha) {
  Layers l;
  l.add_quad(-3.0f);
  const glm::vec4 glow(0.8f, 0.4f, 0.2f, 0.25f), bg(0.1f, 0.2f, 0.3f, 0.5f);
  const ConstantShader sh(glow);
  const DrawCall draws[2] = {translucent_quad(l, &sh, BlendMode::Additive), translucent_quad(l, &sh, BlendMode::Additive)};
  const glm::vec4 expect(0.1f + 2 * 0.2f, 0.2f + 2 * 0.1f, 0.3f + 2 * 0.05f, 0.5f);
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
      const Image img = render_over(draws, bg, sort);
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(img.color[(32 * 64 + 32) * 4 + c], expect[c], 1e-6) << target << " sort " << int(sort);
    }
  });
}

// A pixel with one translucent fragment has nothing to order: every sort mode must blend it
// the same, including a shader alpha outside [0, 1], which the blend clamps (tile_kernels.cc:
// an overshoot must not push the framebuffer out of range). Kills the per-pixel sort's
// composite using the unclamped alpha (tile_kernels.cc, CompositeExact).
TEST(Blending, OneFragmentBlendsTheSameInEverySortModeEvenWithAlphaOutOfRange) {
  Layers l;
  l.add_quad(-3.0f);
  const glm::vec4 bg(0.05f, 0.1f, 0.2f, 1.0f);
  // A NaN alpha (a shader's 0/0) is no alpha: the sort mode changes only the order.
  for (const float alpha : {1.5f, -0.25f, std::numeric_limits<float>::quiet_NaN()}) {
    const ConstantShader sh({0.2f, 0.4f, 0.6f, alpha});
    const DrawCall d = translucent_quad(l, &sh, BlendMode::AlphaOver);
    const float a = alpha > 0.0f ? std::min(alpha, 1.0f) : 0.0f;
    const glm::vec4 expect(0.2f * a + bg.r * (1 - a), 0.4f * a + bg.g * (1 - a), 0.6f * a + bg.b * (1 - a),
                           a + bg.a * (1 - a));
    for_each_target([&](const std::string& target) {
      for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
        const Image img = render_over({&d, 1}, bg, sort, 1);
        for (int c = 0; c < 4; ++c)
          EXPECT_NEAR(img.color[(32 * 64 + 32) * 4 + c], expect[c], 1e-6)
              << target << " sort " << int(sort) << " alpha " << alpha;
      }
    });
  }
}

TEST(Blending, TranslucentFragmentsBehindOpaqueGeometryAreRejected) {
  Layers front, back;
  front.add_quad(-2.0f);  // opaque, nearer
  back.add_quad(-4.0f);   // translucent, farther: hidden
  const ConstantShader red({1, 0, 0, 1}), green({0, 1, 0, 0.5f});
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
  DrawCall a, b;
  a.positions = front.pos.data(); a.vertex_count = 4; a.indices = front.idx.data(); a.triangle_count = 2;
  a.clip_from_object = proj; a.shader = &red;
  b = a;
  b.positions = back.pos.data(); b.indices = back.idx.data(); b.shader = &green;
  b.state.blend = BlendMode::AlphaOver; b.state.depth_write = false;
  const DrawCall draws[2] = {b, a};  // translucent submitted first: still tested against the opaque depth
  for_each_target([&](const std::string& target) {
    const Image img = render(draws, 64, 64);
    EXPECT_EQ(img.color[(32 * 64 + 32) * 4 + 0], 1.0f) << target;
    EXPECT_EQ(img.color[(32 * 64 + 32) * 4 + 1], 0.0f) << target;
    EXPECT_EQ(img.stats.fragments_blended, 0u) << target;
    EXPECT_EQ(img.stats.pixels_shaded, img.stats.fragments_visible) << "a single opaque layer";
  });
}

}  // namespace
}  // namespace pelt::raster::test
