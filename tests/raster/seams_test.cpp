// Shared edges and vertices: every pixel drawn exactly once, so blending never doubles a
// seam and never leaves a crack. Counted with additive blending of 1 per fragment.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace {

struct Mesh {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
};

DrawCall counting_draw(const Mesh& m, const Shader* sh, const glm::mat4& mvp, CullMode cull) {
  DrawCall d;
  d.positions = m.pos.data();
  d.vertex_count = uint32_t(m.pos.size());
  d.indices = m.idx.data();
  d.triangle_count = uint32_t(m.idx.size() / 3);
  d.clip_from_object = mvp;
  d.shader = sh;
  d.state.blend = BlendMode::Additive;
  d.state.depth_func = DepthFunc::Always;
  d.state.depth_write = false;
  d.state.cull = cull;
  return d;
}

std::vector<int> counts(const Image& img) {
  std::vector<int> c(size_t(img.width) * img.height);
  for (size_t i = 0; i < c.size(); ++i) c[i] = int(std::lround(img.color[i * 4]));
  return c;
}

RenderOptions black() {
  RenderOptions o;
  o.background = glm::vec4(0.0f);
  return o;
}

// A planar grid with jittered interior vertices and random diagonals.
Mesh jittered_grid(std::mt19937& rng, int n, float extent) {
  // Up to 0.2 of a cell: every quad stays convex, so either diagonal is a valid split.
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  Mesh m;
  const float step = 2.0f * extent / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      m.pos.push_back({-extent + step * (i + (border ? 0.0f : u(rng))), 0.0f,
                       -extent + step * (j + (border ? 0.0f : u(rng)))});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if (rng() & 1) m.idx.insert(m.idx.end(), {a, c, d, a, d, b});
      else m.idx.insert(m.idx.end(), {a, c, b, b, c, d});
    }
  return m;
}

TEST(Seams, JitteredGridSeenFromRandomCamerasCoversEveryPixelOnce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const ConstantShader one({1, 1, 1, 1});
  for (int trial = 0; trial < 12; ++trial) {
    const Mesh grid = jittered_grid(rng, 40, 20.0f);
    // Looking steeply down at the plane y = 0 from height 1: every view ray hits it well
    // inside the far plane, so the grid covers the whole image.
    const float yaw = u(rng) * 6.2831853f, pitch = glm::radians(65.0f + 20.0f * u(rng));
    const glm::vec3 eye(u(rng) - 0.5f, 1.0f, u(rng) - 0.5f);
    const glm::vec3 fwd(std::cos(pitch) * std::sin(yaw), -std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    const int w = 160 + trial * 7, h = 120 + trial * 5;
    const glm::mat4 mvp = glm::perspective(glm::radians(50.0f), float(w) / h, 0.05f, 100.0f) *
                          glm::lookAt(eye, eye + fwd, glm::vec3(0, 1, 0));
    const DrawCall d = counting_draw(grid, &one, mvp, CullMode::None);
    for_each_target([&](const std::string& target) {
      const std::vector<int> c = counts(render({&d, 1}, w, h, 2, black()));
      int bad = 0;
      for (int v : c) bad += v != 1;
      EXPECT_EQ(bad, 0) << target << " trial " << trial;
    });
  }
}

TEST(Seams, FanAroundAnInteriorVertexCoversEveryPixelOnce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const ConstantShader one({1, 1, 1, 1});
  for (int trial = 0; trial < 8; ++trial) {
    Mesh fan;
    const glm::vec3 centre(u(rng) - 0.5f, u(rng) - 0.5f, 0.0f);
    fan.pos.push_back(centre);
    const int k = 7 + trial * 13;
    for (int i = 0; i < k; ++i) {
      const float a = 6.2831853f * (i + 0.3f * u(rng)) / k;
      const float r = 2.0f + 3.0f * u(rng);  // outside the NDC square
      fan.pos.push_back(centre + glm::vec3(r * std::cos(a), r * std::sin(a), 0.0f));
    }
    for (int i = 0; i < k; ++i) fan.idx.insert(fan.idx.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % k)});
    const DrawCall d = counting_draw(fan, &one, glm::mat4(1.0f), CullMode::None);
    for_each_target([&](const std::string& target) {
      const std::vector<int> c = counts(render({&d, 1}, 97, 131, 1, black()));
      int bad = 0;
      for (int v : c) bad += v != 1;
      EXPECT_EQ(bad, 0) << target << " fan of " << k;
    });
  }
}

// A closed star-shaped mesh (a sphere with random radii): along any view ray it is
// entered as often as it is left, so front faces and back faces cover each pixel the
// same number of times. A crack or a doubled edge breaks that equality.
TEST(Seams, RandomClosedMeshHasEqualFrontAndBackCoverage) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const ConstantShader one({1, 1, 1, 1});
  for (int trial = 0; trial < 10; ++trial) {
    Mesh m;
    const int seg = 24, rings = 12;
    m.pos.push_back({0, 1, 0});
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < seg; ++s) {
        const float th = 3.14159265f * r / rings, ph = 6.2831853f * s / seg;
        const float rad = 0.6f + 0.4f * u(rng);
        m.pos.push_back({rad * std::sin(th) * std::cos(ph), rad * std::cos(th), rad * std::sin(th) * std::sin(ph)});
      }
    m.pos.push_back({0, -1, 0});
    const uint32_t south = uint32_t(m.pos.size() - 1);
    auto ring = [&](int r, int s) { return uint32_t(1 + (r - 1) * seg + (s % seg)); };
    for (int s = 0; s < seg; ++s) m.idx.insert(m.idx.end(), {0u, ring(1, s + 1), ring(1, s)});
    for (int r = 1; r + 1 < rings; ++r)
      for (int s = 0; s < seg; ++s)
        m.idx.insert(m.idx.end(), {ring(r, s), ring(r, s + 1), ring(r + 1, s + 1), ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
    for (int s = 0; s < seg; ++s) m.idx.insert(m.idx.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});

    const float yaw = u(rng) * 6.28f, pitch = (u(rng) - 0.5f) * 2.5f, dist = 2.2f + 2.0f * u(rng);
    const glm::vec3 eye = dist * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    const glm::mat4 mvp = glm::perspective(glm::radians(45.0f), 4.0f / 3.0f, 0.1f, 20.0f) *
                          glm::lookAt(eye, glm::vec3(0.1f * u(rng)), glm::vec3(0, 1, 0));
    for_each_target([&](const std::string& target) {
      const DrawCall front = counting_draw(m, &one, mvp, CullMode::Back);
      const DrawCall back = counting_draw(m, &one, mvp, CullMode::Front);
      const DrawCall both = counting_draw(m, &one, mvp, CullMode::None);
      const auto cf = counts(render({&front, 1}, 160, 120, 1, black()));
      const auto cb = counts(render({&back, 1}, 160, 120, 1, black()));
      const auto cn = counts(render({&both, 1}, 160, 120, 1, black()));
      int unequal = 0, covered = 0;
      for (size_t i = 0; i < cf.size(); ++i) {
        unequal += cf[i] != cb[i] || cn[i] != cf[i] + cb[i];
        covered += cf[i] > 0;
      }
      EXPECT_EQ(unequal, 0) << target << " trial " << trial;
      EXPECT_GT(covered, 500) << "the mesh should be in view";
    });
  }
}

}  // namespace
}  // namespace pelt::raster::test
