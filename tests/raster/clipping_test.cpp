// Near-plane crossings, geometry behind the eye, w near zero and coordinates far outside
// the guard band: never a crash or a NaN, and coverage equal to the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/reference_raster.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace clipping_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Soup {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
  DrawCall draw(const Shader* sh, const glm::mat4& m) const {
    DrawCall d;
    d.positions = pos.data();
    d.vertex_count = uint32_t(pos.size());
    d.indices = idx.data();
    d.triangle_count = uint32_t(idx.size() / 3);
    d.clip_from_object = m;
    d.shader = sh;
    return d;
  }
  void add(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    for (const glm::vec3& p : {a, b, c}) {
      pos.push_back(p);
      idx.push_back(uint32_t(pos.size() - 1));
    }
  }
};

void expect_matches_reference(const DrawCall& d, int w, int h) {
  const ReferenceImage ref = reference_render({&d, 1}, w, h);
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, w, h);
    size_t diff = 0;
    for (size_t i = 0; i < ref.id.size(); ++i) diff += img.id[i] != ref.id[i] || img.depth[i] != ref.depth[i];
    EXPECT_EQ(diff, 0u) << target;
    for (float v : img.color) ASSERT_TRUE(std::isfinite(v)) << target;
    for (float v : img.depth) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << target;
  });
}

TEST(Clipping, TrianglesCrossingTheNearPlaneAndBehindTheEye) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Soup s;
  for (int i = 0; i < 800; ++i) {
    // View space: z from -6 (in front) to +3 (behind the eye); near = 0.25.
    auto p = [&] { return glm::vec3(u(rng) * 4.0f, u(rng) * 4.0f, -1.5f + u(rng) * 4.5f); };
    s.add(p(), p(), p());
  }
  s.add({-1, -1, 2}, {1, -1, 2}, {0, 1, 2});  // wholly behind the eye
  const VaryingShader sh;
  const glm::mat4 proj = glm::perspective(glm::radians(70.0f), 1.5f, 0.25f, 8.0f);
  expect_matches_reference(s.draw(&sh, proj), 150, 100);
}

// A surface more than about 2^24 x near away has a window depth that rounds to exactly 1, the far
// plane's. Against a clear of 1 it failed every depth test and vanished; it is drawn (at depth 1),
// as the reference draws it, and the depth image still reads at most 1.
TEST(Clipping, ASurfaceWhoseDepthRoundsToTheFarPlaneIsDrawn) {
  Soup s;
  s.add({-1, -1, -5}, {1, -1, -5}, {0, 1, -5});  // 5 units off, near 1e-7: 1 - near/d rounds to 1
  const VaryingShader sh;
  const glm::mat4 proj = glm::perspective(glm::radians(45.0f), 1.5f, 1e-7f, 100.0f);
  const DrawCall d = s.draw(&sh, proj);
  expect_matches_reference(d, 60, 40);
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, 60, 40);
    size_t covered = 0;
    for (size_t i = 0; i < img.id.size(); ++i) covered += img.id[i] != 0;
    EXPECT_GT(covered, 100u) << target;
    EXPECT_EQ(*std::max_element(img.depth.begin(), img.depth.end()), 1.0f) << target;
  });
}

TEST(Clipping, WNearZeroAndVerticesOnTheEyePlane) {
  Soup s;
  const float tiny = 1e-7f;
  s.add({0, 0, -tiny}, {1, 0, -1}, {0, 1, -1});
  s.add({0, 0, 0}, {-1, 0, -1}, {0, -1, -1});
  s.add({-1, -1, tiny}, {1, -1, -2}, {0, 1, -2});
  s.add({1e-30f, 1e-30f, -1e-30f}, {1, 1, -1}, {-1, 1, -1});
  const VaryingShader sh;
  expect_matches_reference(s.draw(&sh, glm::perspective(glm::radians(60.0f), 1.0f, 0.1f, 10.0f)), 64, 64);
  // A hand-made matrix whose w can be zero or negative without any near plane.
  glm::mat4 m(1.0f);
  m[2][3] = -1.0f;  // w = -z
  m[3][3] = 0.0f;
  expect_matches_reference(s.draw(&sh, m), 64, 64);
}

TEST(Clipping, CoordinatesUpToAMillionPixelsUseTheGuardBand) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Soup s;
  const int w = 120, h = 90;
  // NDC of 1e4 is ~6e5 pixels; 2e4 is ~1.2e6.
  for (int i = 0; i < 300; ++i) {
    const float r = (i % 3 == 0) ? 2e4f : (i % 3 == 1) ? 50.0f : 2.0f;
    s.add({u(rng) * r, u(rng) * r, u(rng) * 0.9f}, {u(rng) * r, u(rng) * r, u(rng) * 0.9f},
          {u(rng) * 1.2f, u(rng) * 1.2f, u(rng) * 0.9f});
  }
  const VaryingShader sh;
  expect_matches_reference(s.draw(&sh, glm::mat4(1.0f)), w, h);

  // One triangle with vertices a million pixels away that contains the whole viewport.
  Soup big;
  big.add({-2e4f, -2e4f, 0.0f}, {2e4f, -2e4f, 0.0f}, {0.0f, 2e4f, 0.0f});
  const ConstantShader white({1, 1, 1, 1});
  for_each_target([&](const std::string& target) {
    const DrawCall d = big.draw(&white, glm::mat4(1.0f));
    const Image img = render({&d, 1}, w, h);
    for (uint32_t id : img.id) ASSERT_EQ(id, 1u) << target;
  });
}

TEST(Clipping, NonFiniteAndDegenerateInputIsDroppedQuietly) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  Soup s;
  s.add({nan, 0, 0}, {1, 0, 0}, {0, 1, 0});
  s.add({inf, 0, 0}, {1, 0, 0}, {0, 1, 0});
  s.add({0.2f, 0.2f, 0}, {0.2f, 0.2f, 0}, {0.2f, 0.2f, 0});  // a point
  s.add({-0.5f, 0, 0}, {0, 0, 0}, {0.5f, 0, 0});             // a line
  s.add({-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0, 0.5f, 0});  // one good triangle
  const ConstantShader white({1, 1, 1, 1});
  const DrawCall d = s.draw(&white, glm::mat4(1.0f));
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, 32, 32);
    int covered = 0;
    for (uint32_t id : img.id) {
      EXPECT_TRUE(id == 0 || id == 5) << target;
      covered += id == 5;
    }
    EXPECT_GT(covered, 50) << target;
    EXPECT_EQ(img.stats.triangles_culled, 4u) << target;
  });
}

// A ground plane cut by a clip plane: the near plane (the plane runs from behind the eye
// into the view) or the far plane (it runs past the far distance). Its depth at every pixel
// must still be the projection's depth of the point the pixel sees: the vertices clipping
// makes lie on the near plane (depth 0) or the far plane (depth 1). The reference rasterizer
// clips with the same code, so only an analytic answer can tell. Kills the near-plane
// vertex's z set to +w instead of -w, and the far-plane vertex's to -w instead of +w (clip.cpp).
TEST(Clipping, ANearOrFarPlaneCutKeepsTheProjectionsDepth) {
  const float n = 0.5f, f = 20.0f, fovy = glm::radians(60.0f);
  const ConstantShader sh({1, 1, 1, 1});
  const int w = 64, h = 64;
  for (const glm::vec2 z_range : {glm::vec2(2.0f, -10.0f), glm::vec2(-2.0f, -60.0f)}) {
    Soup s;  // y = -1, x in [-5, 5] (wider far away), z over z_range
    const float near_x = 5.0f, far_x = 5.0f * -z_range.y / 10.0f;
    const glm::vec3 a(-near_x, -1, z_range.x), b(near_x, -1, z_range.x), c(far_x, -1, z_range.y), e(-far_x, -1, z_range.y);
    s.add(a, b, c);
    s.add(a, c, e);
    const DrawCall d = s.draw(&sh, glm::perspective(fovy, 1.0f, n, f));
    for_each_target([&](const std::string& target) {
      const Image img = render({&d, 1}, w, h);
      EXPECT_GT(img.stats.triangles_clipped, 0u) << target;
      double worst = 0.0;
      size_t covered = 0;
      for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
          const size_t i = size_t(py) * w + px;
          if (img.id[i] == 0) continue;
          ++covered;
          const double ny = 1.0 - (py + 0.5) / h * 2.0, dy = ny * std::tan(fovy / 2);
          const double zv = 1.0 / dy;  // the ray (dx, dy, -1) meets y = -1 at z = 1 / dy (dy < 0)
          const double ndc = (double(f) + n) / (double(f) - n) + 2.0 * f * n / ((double(f) - n) * zv);
          worst = std::max(worst, std::abs(img.depth[i] - (0.5 * ndc + 0.5)));
        }
      EXPECT_GT(covered, size_t(w * h / 4)) << target << " z from " << z_range.x;
      // Float planes from 1/256-pixel snapped vertices stay within a few 1e-6 here; a wrong
      // clip-plane depth is off by tenths.
      EXPECT_LT(worst, 5e-5) << target << " z from " << z_range.x;
    });
  }
}

}  // namespace clipping_test
}  // namespace pelt::raster::test
