#include "shading/normal_blur.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <tuple>
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
          if (std::equal(whole.pos.data() + 3 * u, whole.pos.data() + 3 * u + 3, split.pos.data() + 3 * v)) w = u;
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

// --- The searches against a brute force ----------------------------------------------------

// blur_normals as its header documents it, by brute force: the same welding, vertex areas and
// welded normals, then every vertex's edge-path distances from each source by Bellman-Ford
// (every edge relaxed until nothing changes, only to distances within 3 sigma), and the weights
// summed in (distance, vertex) order. A path's length is summed from the source outward, as a
// Dijkstra search sums it, and the shortest is the same double either way, so the result is
// the same bits, not just close: a search that missed a vertex, reached one beyond the cut-off,
// found a longer path or summed in another order would differ.
BlurredNormals brute_force_blur(const TestMesh& m, const float sigma[3]) {
  const size_t V = m.pos.size() / 3;
  auto key = [&](size_t v) {
    std::array<uint32_t, 3> k;
    for (int a = 0; a < 3; ++a) {
      float f = m.pos[3 * v + a];
      if (f == 0.0f) f = 0.0f;
      std::memcpy(&k[a], &f, 4);
    }
    return k;
  };
  std::map<std::array<uint32_t, 3>, uint32_t> ids;
  std::vector<uint32_t> rep(V), first;
  for (size_t v = 0; v < V; ++v) {
    auto [it, inserted] = ids.emplace(key(v), uint32_t(first.size()));
    if (inserted) first.push_back(uint32_t(v));
    rep[v] = it->second;
  }
  const size_t W = first.size();
  std::vector<double> area(W, 0.0), corner(V, 0.0);
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  for (size_t t = 0; t + 2 < m.idx.size(); t += 3) {
    const float* p0 = &m.pos[3 * m.idx[t]];
    const float* p1 = &m.pos[3 * m.idx[t + 1]];
    const float* p2 = &m.pos[3 * m.idx[t + 2]];
    const double e1[3] = {double(p1[0]) - p0[0], double(p1[1]) - p0[1], double(p1[2]) - p0[2]};
    const double e2[3] = {double(p2[0]) - p0[0], double(p2[1]) - p0[1], double(p2[2]) - p0[2]};
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                 cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double a3 = 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz) / 3.0;
    for (int k = 0; k < 3; ++k) {
      area[rep[m.idx[t + k]]] += a3;
      corner[m.idx[t + k]] += a3;
      const uint32_t a = rep[m.idx[t + k]], b = rep[m.idx[t + (k + 1) % 3]];
      if (a != b) edges.emplace_back(a, b);
    }
  }
  // Welded normals: copies that agree give their unit normal, copies that differ the mean of
  // their unit normals weighted by their own triangles' areas; a zero normal is left out.
  std::vector<double> nrm(3 * W, 0.0), mixed(3 * W, 0.0), mixed_area(W, 0.0);
  std::vector<int> state(W, 0);  // 0 none, 1 agree, 2 differ
  for (size_t v = 0; v < V; ++v) {
    const float* n = &m.nrm[3 * v];
    const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
    if (!(len > 0)) continue;
    const double u[3] = {n[0] / len, n[1] / len, n[2] / len};
    const uint32_t w = rep[v];
    if (state[w] == 0) {
      std::copy(u, u + 3, &nrm[3 * w]);
      state[w] = 1;
    } else if (!std::equal(u, u + 3, &nrm[3 * w])) {
      state[w] = 2;
    }
    for (int a = 0; a < 3; ++a) mixed[3 * w + a] += corner[v] * u[a];
    mixed_area[w] += corner[v];
  }
  for (size_t w = 0; w < W; ++w)
    if (state[w] == 2)
      for (int a = 0; a < 3; ++a) nrm[3 * w + a] = mixed_area[w] > 0 ? mixed[3 * w + a] / mixed_area[w] : 0.0;
  auto length = [&](uint32_t a, uint32_t b) {
    const float* p = &m.pos[3 * first[a]];
    const float* q = &m.pos[3 * first[b]];
    const double dx = double(p[0]) - q[0], dy = double(p[1]) - q[1], dz = double(p[2]) - q[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  };
  std::vector<double> edge_length;
  for (const auto& [a, b] : edges) edge_length.push_back(length(a, b));
  const double cutoff = 3.0 * std::max({double(sigma[0]), double(sigma[1]), double(sigma[2])});
  std::vector<double> blurred(9 * W, 0.0);
  for (size_t s = 0; s < W && cutoff > 0; ++s) {
    std::vector<double> d(W, INFINITY);
    d[s] = 0.0;
    for (bool changed = true; changed;) {
      changed = false;
      for (size_t e = 0; e < edges.size(); ++e)
        for (const auto& [x, y] : {edges[e], std::pair{edges[e].second, edges[e].first}}) {
          const double nd = d[x] + edge_length[e];
          if (nd <= cutoff && nd < d[y]) d[y] = nd, changed = true;
        }
    }
    std::vector<std::pair<double, uint32_t>> reached;
    for (size_t v = 0; v < W; ++v)
      if (d[v] <= cutoff) reached.emplace_back(d[v], uint32_t(v));
    std::sort(reached.begin(), reached.end());
    for (int c = 0; c < 3; ++c)
      for (const auto& [dv, v] : reached) {
        const double sg = sigma[c];
        if (sg <= 0.0 || dv > 3.0 * sg) continue;
        const double w = area[v] * std::exp(-dv * dv / (2.0 * sg * sg));
        for (int a = 0; a < 3; ++a) blurred[(c * W + s) * 3 + a] += w * nrm[3 * v + a];
      }
  }
  BlurredNormals out;
  for (int c = 0; c < 3; ++c) {
    out.channel[c].resize(3 * V);
    for (size_t v = 0; v < V; ++v) {
      const double* b = &blurred[(c * W + rep[v]) * 3];
      const double len = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
      for (int a = 0; a < 3; ++a)
        out.channel[c][3 * v + a] =
            sigma[c] <= 0.0f || !(len > 1e-300) ? m.nrm[3 * v + a] : float(b[a] / len);
    }
  }
  return out;
}

// Three threads taking every third item: the order items finish in is not the serial one.
const ParallelFor kThreeThreads = [](size_t count, const std::function<void(size_t)>& fn) {
  std::vector<std::thread> pool;
  for (int t = 0; t < 3; ++t)
    pool.emplace_back([&, t] {
      for (size_t k = size_t(t); k < count; k += 3) fn(k);
    });
  for (auto& th : pool) th.join();
};

// blur_normals, serial and on three threads, gives the brute force's bits for every radius.
void ExpectBruteForceBits(const TestMesh& m, const std::string& what) {
  const float radii[][3] = {{0.0f, 0.0f, 0.0f},    {1e-7f, 1e-7f, 1e-7f}, {0.05f, 0.02f, 0.0f},
                            {0.3f, 0.15f, 0.08f},   {1.0f, 0.5f, 0.25f},   {1e6f, 1e6f, 1e6f},
                            {1e6f, 0.1f, 0.0f}};
  for (const auto& sigma : radii) {
    const BlurredNormals expected = brute_force_blur(m, sigma);
    BlurredNormals serial, threaded;
    ASSERT_FALSE(blur_normals(m.input(), sigma, serial).has_value()) << what;
    ASSERT_FALSE(blur_normals(m.input(), sigma, threaded, kThreeThreads).has_value()) << what;
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(serial.channel[c], expected.channel[c]) << what << ", sigma " << sigma[0] << " " << sigma[1] << " "
                                                        << sigma[2] << ", channel " << c;
      EXPECT_EQ(threaded.channel[c], serial.channel[c]) << what << ", channel " << c;
    }
  }
}

// A jittered n x n patch, curved a little, with normals scattered about +z.
TestMesh random_patch(int n, std::mt19937& rng) {
  TestMesh m = plane(n, 1.0f);
  std::uniform_real_distribution<float> jitter(-0.3f / n, 0.3f / n);
  std::normal_distribution<float> tilt(0.0f, 0.4f);
  for (size_t v = 0; v < m.pos.size() / 3; ++v) {
    if (m.pos[3 * v] > 0.0f && m.pos[3 * v] < 1.0f) m.pos[3 * v] += jitter(rng);
    if (m.pos[3 * v + 1] > 0.0f && m.pos[3 * v + 1] < 1.0f) m.pos[3 * v + 1] += jitter(rng);
    m.pos[3 * v + 2] = 0.3f * m.pos[3 * v] * m.pos[3 * v] + jitter(rng);
    m.nrm[3 * v] = tilt(rng);
    m.nrm[3 * v + 1] = tilt(rng);
  }
  return m;
}

TEST(NormalBlurSearch, RandomPatchesMatchTheBruteForce) {
  std::mt19937 rng(11);
  for (int i = 0; i < 4; ++i) ExpectBruteForceBits(random_patch(6 + 3 * i, rng), "patch " + std::to_string(i));
}

// Random triangles over random points: degenerate triangles (a corner repeated), vertices in
// no triangle, several components, zero normals, distances tied on no grid.
TEST(NormalBlurSearch, RandomSoupsMatchTheBruteForce) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f);
  for (int i = 0; i < 6; ++i) {
    TestMesh m;
    const int V = 10 + 15 * i;
    for (int v = 0; v < V; ++v) {
      for (int a = 0; a < 3; ++a) m.pos.push_back(coord(rng));
      for (int a = 0; a < 3; ++a) m.nrm.push_back(v % 7 == 3 ? 0.0f : coord(rng));
    }
    std::uniform_int_distribution<uint32_t> vertex(0, uint32_t(V - 1));
    for (int t = 0; t < V; ++t) m.idx.insert(m.idx.end(), {vertex(rng), vertex(rng), vertex(rng)});
    ExpectBruteForceBits(m, "soup " + std::to_string(i));
  }
}

// Coincident copies (seams with one normal, creases with two, -0 beside +0), the sphere the
// other tests use (closed: at radius 1e6 its normals nearly cancel), a single vertex with and
// without a triangle, and no vertices at all.
TEST(NormalBlurSearch, HardCasesMatchTheBruteForce) {
  const float right[3] = {0.6f, 0.0f, 0.8f};
  ExpectBruteForceBits(split_column(8, 3, 2), "seam copies");
  ExpectBruteForceBits(split_column(8, 3, 3, right), "crease copies");
  TestMesh signed_zero = plane(4, 1.0f);
  for (size_t v = 0; v < signed_zero.pos.size() / 3; v += 2) signed_zero.pos[3 * v + 2] = -0.0f;
  ExpectBruteForceBits(signed_zero, "-0 and +0");
  ExpectBruteForceBits(sphere(2), "sphere");
  TestMesh one;
  one.pos = {0.5f, 0.25f, 0.0f};
  one.nrm = {0.0f, 0.0f, 2.0f};
  ExpectBruteForceBits(one, "one vertex");
  one.idx = {0, 0, 0};
  ExpectBruteForceBits(one, "one vertex in a degenerate triangle");
  TestMesh stacked = one;  // three copies of one position, one triangle
  stacked.pos.insert(stacked.pos.end(), {0.5f, 0.25f, 0.0f, 0.5f, 0.25f, 0.0f});
  stacked.nrm.insert(stacked.nrm.end(), {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f});
  stacked.idx = {0, 1, 2};
  ExpectBruteForceBits(stacked, "three copies of one position");
  ExpectBruteForceBits(TestMesh{}, "no vertices");
}

// --- The budget of (source, neighbour) pairs ------------------------------------------------

void ExpectReasonHas(const ParamError& e, const std::vector<std::string>& parts) {
  EXPECT_EQ(e.field, "normal_blur_radius");
  for (const std::string& p : parts) EXPECT_NE(e.reason.find(p), std::string::npos) << "`" << p << "` in " << e.reason;
}

// At radius 1e6 every one of the sphere's 642 vertices reaches every other: 642^2 pairs. The
// sampled vertices settle 642 each, so the estimate is exact, and a budget one pair short refuses
// before any blur, naming the count, the budget and the flag.
TEST(NormalBlurBudget, EveryPairAtTheBudgetAcceptedOneLessRefused) {
  const TestMesh m = sphere(3);
  ASSERT_EQ(m.pos.size() / 3, 642u);
  const float sigma[3] = {1e6f, 0.5f, 0.0f};
  BlurredNormals free, out;
  ASSERT_FALSE(blur_normals(m.input(), sigma, free).has_value());
  // The estimate is made, and reported, under any budget: `pelt info` prints it.
  EXPECT_EQ(free.pair_estimate, 642u * 642u);
  ASSERT_FALSE(blur_normals(m.input(), sigma, out, {}, {642u * 642u, "--max-blur-pairs"}).has_value());
  EXPECT_EQ(out.pair_estimate, 642u * 642u);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(out.channel[c], free.channel[c]);
  for (const ParallelFor& parallel : {ParallelFor{}, kThreeThreads}) {
    const auto e = blur_normals(m.input(), sigma, out, parallel, {642u * 642u - 1, "--max-blur-pairs"});
    ASSERT_TRUE(e.has_value());
    ExpectReasonHas(*e, {"reaches about 412164 (source, neighbour) vertex pairs",
                         "more than the budget of 412163 pairs (raise it with --max-blur-pairs)",
                         "3 x 1e+06", "settles about 642 of its 642 welded vertices"});
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(out.channel[c].empty());
    EXPECT_EQ(out.pair_estimate, 642u * 642u);  // the figure refused
  }
  // Without a flag the reason ends at the budget.
  const auto e = blur_normals(m.input(), sigma, out, {}, {1000, ""});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->reason.find("raise it"), std::string::npos) << e->reason;
}

// estimate_only (pelt info) gives the same estimate and the same refusal as the blur's own
// check, and no channel: the blur's searches are not run.
TEST(NormalBlurBudget, EstimateOnlyEstimatesAsTheBlurAndBlursNothing) {
  const TestMesh m = sphere(3);
  const float sigma[3] = {0.4f, 0.2f, 0.0f};
  BlurredNormals full, estimate;
  ASSERT_FALSE(blur_normals(m.input(), sigma, full).has_value());
  NormalBlurBudget only;
  only.estimate_only = true;
  for (const ParallelFor& parallel : {ParallelFor{}, kThreeThreads}) {
    ASSERT_FALSE(blur_normals(m.input(), sigma, estimate, parallel, only).has_value());
    EXPECT_EQ(estimate.pair_estimate, full.pair_estimate);
    EXPECT_GT(estimate.pair_estimate, 642u);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(estimate.channel[c].empty());
  }
  only.max_pairs = full.pair_estimate - 1;
  const auto e = blur_normals(m.input(), sigma, estimate, {}, only);
  ASSERT_TRUE(e.has_value());
  ExpectReasonHas(*e, {"reaches about " + std::to_string(full.pair_estimate) + " (source, neighbour) vertex pairs"});
  // Radius 0 everywhere: nothing to search, nothing to estimate, still no channel.
  const float none[3] = {0.0f, 0.0f, 0.0f};
  only.max_pairs = UINT64_MAX;
  ASSERT_FALSE(blur_normals(m.input(), none, estimate, {}, only).has_value());
  EXPECT_EQ(estimate.pair_estimate, 0u);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(estimate.channel[c].empty());
}

// A radius that reaches no neighbour: every source settles itself alone, W pairs in all.
// Radius 0 searches nothing and so fits any budget.
TEST(NormalBlurBudget, EachSourceCountsItself) {
  const TestMesh m = plane(30, 1.0f);  // 961 vertices 1/30 apart
  const size_t W = m.pos.size() / 3;
  const float tiny[3] = {0.001f, 0.001f, 0.0f};
  BlurredNormals out;
  EXPECT_FALSE(blur_normals(m.input(), tiny, out, {}, {W, ""}).has_value());
  const auto e = blur_normals(m.input(), tiny, out, {}, {W - 1, ""});
  ASSERT_TRUE(e.has_value());
  ExpectReasonHas(*e, {"reaches about " + std::to_string(W) + " ", "settles about 1 of its 961"});
  EXPECT_FALSE(blur_normals(m.input(), tiny, out).has_value());
  EXPECT_EQ(out.pair_estimate, W);
  const float zero[3] = {0.0f, 0.0f, 0.0f};
  EXPECT_FALSE(blur_normals(m.input(), zero, out, {}, {1, ""}).has_value());
  EXPECT_EQ(out.pair_estimate, 0u);
}

// A sample that alone would put the estimate over the budget stops there ("at least").
TEST(NormalBlurBudget, ASampleStopsOnceItAloneIsOverTheBudget) {
  const TestMesh m = plane(60, 1.0f);  // 3721 vertices
  const float sigma[3] = {1e6f, 1e6f, 1e6f};
  BlurredNormals out;
  const auto e = blur_normals(m.input(), sigma, out, {}, {100000, ""});
  ASSERT_TRUE(e.has_value());
  // The budget is 26 pairs a vertex, so each sample stops at (26 + 1) x 64 = 1728 vertices.
  ExpectReasonHas(*e, {"reaches at least " + std::to_string(3721 * 1728) + " ", "settles at least 1728 of its 3721"});
}

// The samples (64 evenly spaced welded vertices) can miss a small dense part of a mesh: here a
// 11 x 11 patch, all within reach of each other, whose 121 vertices come before the first sample,
// and 5200 separate small triangles. The estimate (3 pairs a vertex) fits the budget; the
// searches themselves count 121^2 + 5200 x 9 = 61441 pairs and refuse past it, on any thread
// count, and a budget of exactly that many accepts.
TEST(NormalBlurBudget, TheSearchesRefuseWhatTheSamplesMissed) {
  TestMesh m = plane(10, 1.0f);
  for (uint32_t t = 0; t < 5200; ++t) {
    const uint32_t base = uint32_t(m.pos.size() / 3);
    const float x = 10.0f + 10.0f * float(t);
    m.pos.insert(m.pos.end(), {x, 0.0f, 0.0f, x + 0.01f, 0.0f, 0.0f, x, 0.01f, 0.0f});
    m.nrm.insert(m.nrm.end(), {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f});
    m.idx.insert(m.idx.end(), {base, base + 1, base + 2});
  }
  ASSERT_EQ(m.pos.size() / 3, 15721u);  // the first sample is vertex 15721 / 128 = 122
  const float sigma[3] = {1.0f, 1.0f, 1.0f};
  BlurredNormals out;
  for (const ParallelFor& parallel : {ParallelFor{}, kThreeThreads}) {
    EXPECT_FALSE(blur_normals(m.input(), sigma, out, parallel, {61441, ""}).has_value());
    const auto e = blur_normals(m.input(), sigma, out, parallel, {50000, "--max-blur-pairs"});
    ASSERT_TRUE(e.has_value());
    ExpectReasonHas(*e, {"than the estimate from sampled vertices said", "budget of 50000 pairs"});
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(out.channel[c].empty());
  }
}

}  // namespace
}  // namespace pelt::shading
