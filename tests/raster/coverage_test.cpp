// The SIMD tile rasterizer against the scalar reference: coverage (through the visible
// triangle id) and depth must match bit for bit, for every Highway target.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/reference_raster.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace coverage_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Soup {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
};

// Random triangles of every kind the rasterizer must get exactly right.
Soup random_soup(std::mt19937& rng, int w, int h, int count) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto ndc_x = [&](float px) { return px / w * 2.0f - 1.0f; };
  auto ndc_y = [&](float py) { return 1.0f - py / h * 2.0f; };
  Soup s;
  for (int i = 0; i < count; ++i) {
    const int kind = i % 7;
    float px[3], py[3];
    const float cx = u(rng) * w, cy = u(rng) * h;
    float size = 0.0f;
    switch (kind) {
      case 0: size = 0.3f + u(rng) * 1.5f; break;    // tiny: at most a pixel or two
      case 1: size = 2.0f + u(rng) * 10.0f; break;   // small
      case 2: size = 10.0f + u(rng) * 100.0f; break; // medium
      case 3: size = 100.0f + u(rng) * 400.0f; break;// large, past the viewport
      default: size = 5.0f + u(rng) * 60.0f; break;
    }
    for (int k = 0; k < 3; ++k) {
      px[k] = cx + (u(rng) - 0.5f) * 2.0f * size;
      py[k] = cy + (u(rng) - 0.5f) * 2.0f * size;
    }
    if (kind == 4) {  // sliver: two vertices within a fraction of a pixel
      px[1] = px[0] + (u(rng) - 0.5f) * 0.4f;
      py[1] = py[0] + (u(rng) - 0.5f) * 0.4f;
    } else if (kind == 5) {  // nearly collinear
      const float t = u(rng);
      px[2] = px[0] + (px[1] - px[0]) * t + (u(rng) - 0.5f) * 0.05f;
      py[2] = py[0] + (py[1] - py[0]) * t + (u(rng) - 0.5f) * 0.05f;
    } else if (kind == 6) {  // vertices on pixel centres and half-pixels: edges through centres
      for (int k = 0; k < 3; ++k) {
        px[k] = std::floor(px[k]) + ((rng() & 1) ? 0.5f : 0.0f);
        py[k] = std::floor(py[k]) + ((rng() & 1) ? 0.5f : 0.0f);
      }
      if (rng() & 1) py[1] = py[0];  // axis-aligned edges: top/left rule cases
      if (rng() & 1) px[2] = px[0];
    }
    const float z = u(rng) * 1.8f - 0.9f;
    for (int k = 0; k < 3; ++k) {
      s.pos.push_back({ndc_x(px[k]), ndc_y(py[k]), z + (u(rng) - 0.5f) * 0.2f});
      s.idx.push_back(static_cast<uint32_t>(s.pos.size() - 1));
    }
  }
  return s;
}

DrawCall make_draw(const Soup& s, const Shader* sh, glm::mat4 m = glm::mat4(1.0f)) {
  DrawCall d;
  d.positions = s.pos.data();
  d.vertex_count = static_cast<uint32_t>(s.pos.size());
  d.indices = s.idx.data();
  d.triangle_count = static_cast<uint32_t>(s.idx.size() / 3);
  d.clip_from_object = m;
  d.shader = sh;
  return d;
}

void expect_same(const Image& got, const ReferenceImage& ref, const std::string& what) {
  size_t id_mismatch = 0, depth_mismatch = 0, first = SIZE_MAX;
  for (size_t i = 0; i < ref.id.size(); ++i) {
    if (got.id[i] != ref.id[i]) {
      ++id_mismatch;
      first = std::min(first, i);
    }
    if (std::memcmp(&got.depth[i], &ref.depth[i], sizeof(float)) != 0) {
      ++depth_mismatch;
      first = std::min(first, i);
    }
  }
  EXPECT_EQ(id_mismatch, 0u) << what << " first mismatch at pixel (" << first % ref.width << ", "
                             << first / ref.width << ") got id " << got.id[first % got.id.size()]
                             << " want " << ref.id[first % ref.id.size()];
  EXPECT_EQ(depth_mismatch, 0u) << what;
  for (uint32_t c : ref.count) ASSERT_NE(c, 0xDEADu) << "set-up dropped a triangle that covers a pixel";
}

TEST(Coverage, TenThousandRandomTrianglesMatchReferenceOnEveryTarget) {
  const int w = 203, h = 157;  // not multiples of the tile or block size
  std::mt19937 rng(20261122);
  const ConstantShader white({1, 1, 1, 1});
  std::vector<Soup> frames;
  for (int f = 0; f < 50; ++f) frames.push_back(random_soup(rng, w, h, 200));
  std::vector<ReferenceImage> refs;
  for (const Soup& s : frames) {
    const DrawCall d = make_draw(s, &white);
    refs.push_back(reference_render({&d, 1}, w, h));
  }
  int targets = 0;
  for_each_target([&](const std::string& target) {
    ++targets;
    for (size_t f = 0; f < frames.size(); ++f) {
      const DrawCall d = make_draw(frames[f], &white);
      const Image img = render({&d, 1}, w, h, 1);
      expect_same(img, refs[f], target + " frame " + std::to_string(f));
      uint64_t ref_frags = 0;
      for (uint32_t c : refs[f].count) ref_frags += c;
      EXPECT_EQ(img.stats.fragments_visible, ref_frags) << target;
    }
  });
  EXPECT_GE(targets, 2);  // at least the scalar fallback and one SIMD target
}

TEST(Coverage, PerspectiveTrianglesMatchReferenceWithCullingAndDepthFuncs) {
  const int w = 128, h = 96;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Soup s;
  for (int i = 0; i < 600; ++i)
    for (int k = 0; k < 3; ++k) {
      s.pos.push_back({u(rng) * 3.0f, u(rng) * 3.0f, -4.0f + u(rng) * 3.5f});
      s.idx.push_back(static_cast<uint32_t>(s.pos.size() - 1));
    }
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), float(w) / h, 0.5f, 10.0f);
  const ConstantShader white({1, 1, 1, 1});
  for (CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front})
    for (DepthFunc f : {DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always}) {
      DrawCall d = make_draw(s, &white, proj);
      d.state.cull = cull;
      d.state.depth_func = f;
      const ReferenceImage ref = reference_render({&d, 1}, w, h);
      for_each_target([&](const std::string& target) {
        expect_same(render({&d, 1}, w, h), ref, target);
      });
    }
}

// The llvmpipe harness's known answer: a square [-0.5, 0.5]^2 seen from z = 1 with a 90
// degree field of view at 64x64 covers exactly rows/columns 16..47; the first triangle
// gets the 32 pixels of the shared diagonal (528 pixels), the second 496.
TEST(Coverage, SquareSplitsItsDiagonalByTheTopLeftRule) {
  Soup s;
  s.pos = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
  s.idx = {0, 1, 2, 0, 2, 3};
  const glm::mat4 m = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 10.0f) *
                      glm::lookAt(glm::vec3(0, 0, 1), glm::vec3(0), glm::vec3(0, 1, 0));
  const ConstantShader white({1, 1, 1, 1});
  const DrawCall d = make_draw(s, &white, m);
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, 64, 64);
    int first = 0, second = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const uint32_t id = img.id[y * 64 + x];
        const bool inside = x >= 16 && x <= 47 && y >= 16 && y <= 47;
        EXPECT_EQ(id != 0, inside) << target << " pixel " << x << "," << y;
        first += id == 1;
        second += id == 2;
      }
    EXPECT_EQ(first, 528) << target;
    EXPECT_EQ(second, 496) << target;
    // Hand-computed depth of the plane z = 0 seen from 1 unit away with near 0.1, far 10.
    const float zc = img.depth[32 * 64 + 32];
    EXPECT_NEAR(zc, 0.909091f, 1e-5f) << target;
  });
}

// Two draws of one tilted quad have bit-identical depths at every pixel: Less keeps the
// first draw, LessEqual and Always let the second overwrite it (pipeline.h's DepthFunc; the
// fur's first shell sits on the base mesh and relies on LessEqual). Random triangles almost
// never tie, so the reference comparisons above cannot tell the two apart. Kills Less <-> LessEqual
// (tile_kernels.cc, DepthPass).
TEST(Coverage, EqualDepthsFollowTheDepthFunction) {
  std::vector<glm::vec3> pos = {{-2, -2, -3.5f}, {2, -2, -2.5f}, {-2, 2, -3.5f}, {2, 2, -2.5f}};
  std::vector<uint32_t> idx = {0, 1, 3, 0, 3, 2};
  const ConstantShader first({1, 0, 0, 1}), second({0, 1, 0, 1});
  DrawCall a;
  a.positions = pos.data();
  a.vertex_count = 4;
  a.indices = idx.data();
  a.triangle_count = 2;
  a.clip_from_object = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f);
  a.shader = &first;
  a.id_base = 0;
  for (DepthFunc func : {DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always}) {
    DrawCall b = a;
    b.shader = &second;
    b.id_base = 100;
    b.state.depth_func = func;
    const DrawCall draws[2] = {a, b};
    const bool second_wins = func != DepthFunc::Less;
    for_each_target([&](const std::string& target) {
      const Image img = render(draws, 64, 64, 1);
      size_t covered = 0, wrong = 0;
      for (size_t p = 0; p < img.id.size(); ++p) {
        if (img.id[p] == 0) continue;
        ++covered;
        const bool from_second = img.id[p] > 100;
        wrong += from_second != second_wins || img.color[p * 4 + 1] != (second_wins ? 1.0f : 0.0f);
      }
      EXPECT_GT(covered, 1000u) << target;
      EXPECT_EQ(wrong, 0u) << target << " depth func " << int(func);
    });
  }
}

}  // namespace coverage_test
}  // namespace pelt::raster::test
