#include "shading/normal_blur.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <thread>
#include <vector>

namespace pelt::shading {
namespace {

struct TestMesh {
  std::vector<float> pos, nrm;
  std::vector<uint32_t> idx;
  NormalBlurInput input() const { return {pos.data(), nrm.data(), pos.size() / 3, idx.data(), idx.size()}; }
};

// n x n grid on z = 0 spanning [0, size]^2, normals +z.
TestMesh plane(int n, float size) {
  TestMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.pos.insert(m.pos.end(), {size * i / n, size * j / n, 0.0f});
      m.nrm.insert(m.nrm.end(), {0.0f, 0.0f, 1.0f});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.idx.insert(m.idx.end(), {a, b, d, a, d, c});
    }
  return m;
}

// Unit icosphere subdivided `levels` times, normals radial.
TestMesh sphere(int levels) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<std::array<float, 3>> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3, 8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  auto norm = [](std::array<float, 3> a) {
    const float l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<float, 3>{a[0] / l, a[1] / l, a[2] / l};
  };
  for (auto& p : v) p = norm(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(norm({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2}));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<uint32_t> g;
    for (size_t i = 0; i < f.size(); i += 3) {
      const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = g;
  }
  TestMesh m;
  for (auto& p : v) {
    m.pos.insert(m.pos.end(), p.begin(), p.end());
    m.nrm.insert(m.nrm.end(), p.begin(), p.end());
  }
  m.idx = f;
  return m;
}

TEST(NormalBlur, FlatPlaneKeepsItsNormals) {
  const TestMesh m = plane(20, 2.0f);
  const float sigma[3] = {0.3f, 0.15f, 0.05f};
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  for (int c = 0; c < 3; ++c)
    for (size_t v = 0; v < m.pos.size() / 3; ++v) {
      EXPECT_NEAR(out.channel[c][3 * v + 0], 0.0f, 1e-6f);
      EXPECT_NEAR(out.channel[c][3 * v + 1], 0.0f, 1e-6f);
      EXPECT_NEAR(out.channel[c][3 * v + 2], 1.0f, 1e-6f);
    }
}

TEST(NormalBlur, SphereStaysUnitAndRadial) {
  const TestMesh m = sphere(3);
  const float sigma[3] = {0.4f, 0.2f, 0.1f};
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  for (int c = 0; c < 3; ++c)
    for (size_t v = 0; v < m.pos.size() / 3; ++v) {
      const float* b = &out.channel[c][3 * v];
      const float* p = &m.pos[3 * v];
      EXPECT_NEAR(std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]), 1.0f, 1e-5f);
      EXPECT_GT(b[0] * p[0] + b[1] * p[1] + b[2] * p[2], 1.0f - 2e-3f) << "channel " << c << " vertex " << v;
    }
}

TEST(NormalBlur, RadiusZeroReturnsTheInput) {
  TestMesh m = sphere(2);
  for (size_t i = 0; i < m.nrm.size(); ++i) m.nrm[i] *= 2.5f;  // not unit: returned as is
  const float sigma[3] = {0.0f, 0.0f, 0.0f};
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  for (int c = 0; c < 3; ++c) EXPECT_EQ(out.channel[c], m.nrm);
}

// Mean angle between the normals at the two ends of each edge.
double roughness(const TestMesh& m, const std::vector<float>& n) {
  double sum = 0;
  size_t count = 0;
  for (size_t t = 0; t < m.idx.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const float* a = &n[3 * m.idx[t + k]];
      const float* b = &n[3 * m.idx[t + (k + 1) % 3]];
      const double d = std::clamp(double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2], -1.0, 1.0);
      sum += std::acos(d);
      ++count;
    }
  return sum / double(count);
}

TEST(NormalBlur, WiderRadiusIsSmoother) {
  TestMesh m = plane(40, 4.0f);
  std::mt19937 rng(3);
  std::normal_distribution<float> nd(0.0f, 0.3f);
  for (size_t v = 0; v < m.nrm.size() / 3; ++v) {
    m.nrm[3 * v] = nd(rng);
    m.nrm[3 * v + 1] = nd(rng);
  }
  const float sigma[3] = {0.4f, 0.2f, 0.1f};  // red widest
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  const double r_in = roughness(m, m.nrm), r_b = roughness(m, out.channel[2]), r_g = roughness(m, out.channel[1]),
               r_r = roughness(m, out.channel[0]);
  EXPECT_LT(r_b, 0.7 * r_in);
  EXPECT_LT(r_g, 0.7 * r_b);
  EXPECT_LT(r_r, 0.7 * r_g);
}

// Items run in any order and on any threads give the same bits as the serial loop: each item
// writes only its own vertices.
TEST(NormalBlur, ParallelItemsInAnyOrderGiveTheSameBits) {
  TestMesh m = plane(60, 4.0f);  // 3721 vertices: 30 items of 128
  std::mt19937 rng(5);
  std::normal_distribution<float> nd(0.0f, 0.3f);
  for (size_t v = 0; v < m.nrm.size() / 3; ++v) m.nrm[3 * v] = nd(rng);
  const float sigma[3] = {0.3f, 0.15f, 0.0f};
  BlurredNormals serial, reversed, threaded;
  ASSERT_FALSE(blur_normals(m.input(), sigma, serial).has_value());
  size_t calls = 0;
  const ParallelFor backwards = [&](size_t count, const std::function<void(size_t)>& fn) {
    for (size_t k = count; k-- > 0;) fn(k);
    calls += count;
  };
  ASSERT_FALSE(blur_normals(m.input(), sigma, reversed, backwards).has_value());
  EXPECT_GT(calls, 1u);
  const ParallelFor threads = [](size_t count, const std::function<void(size_t)>& fn) {
    std::vector<std::thread> pool;
    for (int t = 0; t < 3; ++t)
      pool.emplace_back([&, t] {
        for (size_t k = size_t(t); k < count; k += 3) fn(k);
      });
    for (auto& th : pool) th.join();
  };
  ASSERT_FALSE(blur_normals(m.input(), sigma, threaded, threads).has_value());
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(serial.channel[c], reversed.channel[c]) << "channel " << c;
    EXPECT_EQ(serial.channel[c], threaded.channel[c]) << "channel " << c;
  }
}

TEST(NormalBlur, UvSeamCopiesGetTheSameNormal) {
  // Two halves of a bumpy plane share no vertex index along x = 1, only positions.
  TestMesh a = plane(10, 1.0f), b = plane(10, 1.0f);
  const uint32_t offset = uint32_t(a.pos.size() / 3);
  for (size_t v = 0; v < b.pos.size() / 3; ++v) b.pos[3 * v] += 1.0f;
  TestMesh m;
  m.pos = a.pos;
  m.pos.insert(m.pos.end(), b.pos.begin(), b.pos.end());
  m.nrm = a.nrm;
  m.nrm.insert(m.nrm.end(), b.nrm.begin(), b.nrm.end());
  for (size_t v = 0; v < m.nrm.size() / 3; ++v) m.nrm[3 * v] = std::sin(7.0f * m.pos[3 * v]);
  m.idx = a.idx;
  for (uint32_t i : b.idx) m.idx.push_back(i + offset);
  const float sigma[3] = {0.2f, 0.2f, 0.2f};
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  for (int j = 0; j <= 10; ++j) {
    const size_t left = size_t(j) * 11 + 10, right = offset + size_t(j) * 11;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(out.channel[0][3 * left + k], out.channel[0][3 * right + k]);
  }
}

// A bumpy plane(n, 1) whose column `column` is split like a UV seam: the cells to its right use
// `copies` extra copies of its vertices (same positions; cell row j uses copy j % copies), with
// normal `right` when given (a crease) or the column's own normal (a plain seam).
TestMesh split_column(int n, int column, int copies, const float* right = nullptr) {
  TestMesh m = plane(n, 1.0f);
  for (size_t v = 0; v < m.nrm.size() / 3; ++v) {
    m.nrm[3 * v] = std::sin(7.0f * m.pos[3 * v]);
    m.nrm[3 * v + 1] = 0.5f * std::cos(5.0f * m.pos[3 * v + 1]);
  }
  const auto id = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
  std::vector<std::vector<uint32_t>> copy(copies, std::vector<uint32_t>(n + 1));
  for (int c = 0; c < copies; ++c)
    for (int j = 0; j <= n; ++j) {
      copy[c][j] = uint32_t(m.pos.size() / 3);
      const uint32_t v = id(column, j);
      for (int a = 0; a < 3; ++a) m.pos.push_back(m.pos[3 * v + a]);
      for (int a = 0; a < 3; ++a) m.nrm.push_back(right ? right[a] : m.nrm[3 * v + a]);
    }
  if (copies > 0)
    for (int j = 0; j < n; ++j) {
      uint32_t* cell = &m.idx[6 * size_t(j * n + column)];  // plane's cell (column, j): a b d a d c
      const std::vector<uint32_t>& c = copy[j % copies];
      for (int k = 0; k < 6; ++k) {
        if (cell[k] == id(column, j)) cell[k] = c[j];
        if (cell[k] == id(column, j + 1)) cell[k] = c[j + 1];
      }
    }
  return m;
}

// Every blurred normal of `split` matches that of `whole` at the same position.
void ExpectSameBlur(const TestMesh& whole, const TestMesh& split, float tolerance) {
  const float sigma[3] = {0.3f, 0.15f, 0.05f};
  BlurredNormals expected, got;
  ASSERT_FALSE(blur_normals(whole.input(), sigma, expected).has_value());
  ASSERT_FALSE(blur_normals(split.input(), sigma, got).has_value());
  const size_t n = whole.pos.size() / 3;
  for (int c = 0; c < 3; ++c) {
    float worst = 0.0f;
    size_t worst_vertex = 0;
    for (size_t v = 0; v < split.pos.size() / 3; ++v) {
      size_t w = v;  // the vertex of `whole` at the same position
      if (v >= n)
        for (size_t u = 0; u < n; ++u)
          if (std::equal(&whole.pos[3 * u], &whole.pos[3 * u + 3], &split.pos[3 * v])) w = u;
      for (int a = 0; a < 3; ++a) {
        const float d = std::abs(got.channel[c][3 * v + a] - expected.channel[c][3 * w + a]);
        if (d > worst) worst = d, worst_vertex = v;
      }
    }
    EXPECT_LE(worst, tolerance) << "channel " << c << " vertex " << worst_vertex << " at ("
                                << split.pos[3 * worst_vertex] << ", " << split.pos[3 * worst_vertex + 1] << ")";
  }
}

// A seam is not a boundary and a position counts once: splitting a column into seam copies
// changes no blurred normal, near the seam or far from it.
TEST(NormalBlur, SeamCopiesDoNotChangeTheBlur) {
  const TestMesh whole = split_column(20, 7, 0);
  ExpectSameBlur(whole, split_column(20, 7, 1), 1e-6f);
  ExpectSameBlur(whole, split_column(20, 7, 3), 1e-6f);
}

// At a crease the copies' normals differ; each weighs by the area of its own triangles, so
// splitting one side's copy further changes nothing.
TEST(NormalBlur, CreaseCopiesWeighByTheirTriangles) {
  const float right[3] = {0.6f, 0.0f, 0.8f};
  ExpectSameBlur(split_column(20, 7, 1, right), split_column(20, 7, 2, right), 1e-6f);
}

TEST(NormalBlur, BadInputNamesTheField) {
  TestMesh m = plane(2, 1.0f);
  m.idx[4] = 99;
  const float sigma[3] = {0.1f, 0.1f, 0.1f};
  BlurredNormals out;
  auto e = blur_normals(m.input(), sigma, out);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "indices");
  m = plane(2, 1.0f);
  const float bad[3] = {0.1f, -1.0f, 0.1f};
  e = blur_normals(m.input(), bad, out);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "normal_blur_radius[1]");
}

// The documented weights, by hand, at one vertex: exp(-d^2 / (2 sigma^2)) times the vertex's area
// (a third of its triangles' areas), for every vertex within 3 sigma along the edges, then
// normalised. Vertex 0 has neighbours at edge distances 1 (areas 1/6 and 1/2, normals +x, +y) and
// 2 (area 1/3, normal -x); the three sigmas put those distances on each side of 2 sigma and 3
// sigma, so a changed exponent, cut-off or area weight each moves the result.
TEST(NormalBlur, WeightsAreGaussianInEdgeDistanceTimesVertexArea) {
  TestMesh m;
  m.pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, -2, 0, 0};
  m.nrm = {0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0};
  m.idx = {0, 1, 2, 0, 2, 3};  // areas 1/2 and 1
  const double area[4] = {0.5, 0.5 / 3, 0.5, 1.0 / 3}, dist[4] = {0, 1, 1, 2};
  const double n[4][3] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  const float sigma[3] = {0.8f, 0.4f, 0.3f};
  BlurredNormals out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, out).has_value());
  for (int c = 0; c < 3; ++c) {
    const double s = sigma[c];
    double sum[3] = {0, 0, 0};
    for (int v = 0; v < 4; ++v) {
      if (dist[v] > 3 * s) continue;
      const double w = area[v] * std::exp(-dist[v] * dist[v] / (2 * s * s));
      for (int a = 0; a < 3; ++a) sum[a] += w * n[v][a];
    }
    const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(out.channel[c][a], sum[a] / len, 1e-6) << "channel " << c << " axis " << a;
  }
  EXPECT_NE(out.channel[1][0], 0.0f) << "sigma 0.4 reaches the neighbours at distance 1";
  EXPECT_EQ(out.channel[2][0], 0.0f) << "sigma 0.3 reaches no neighbour";
  EXPECT_EQ(out.channel[2][2], 1.0f);
}

}  // namespace
}  // namespace pelt::shading
