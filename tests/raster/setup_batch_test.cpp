// setup_snapped_batch (SIMD, several triangles side by side) against setup_snapped (the
// scalar reference) on every compiled target: the same survivors in the same order, and
// bit-identical edges, bounds and planes, on random triangles of every size and on the
// hard ones (zero area, no pixel centre, the guard band's extremes, edges on pixel
// centres where the top-left rule decides, every cull mode and winding).
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "raster/config.h"
#include "raster/setup.h"
#include "tests/raster/render_helpers.h"

namespace pelt::raster {
namespace setup_batch_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Tri {
  SnappedVertex v[3];
};

// The scalar reference's survivors, as the front end used to produce them one by one.
struct Expected {
  std::vector<TriSetup> setups;
  std::vector<uint8_t> index;
};

Expected reference(const std::vector<Tri>& tris, const Viewport& vp, CullMode cull) {
  static constexpr double kB1[3] = {0.0, 1.0, 0.0}, kB2[3] = {0.0, 0.0, 1.0};
  Expected e;
  for (size_t i = 0; i < tris.size(); ++i) {
    TriSetup t{};
    if (!setup_snapped(tris[i].v[0], tris[i].v[1], tris[i].v[2], kB1, kB2, vp, cull, t)) continue;
    e.setups.push_back(t);
    e.index.push_back(static_cast<uint8_t>(i));
  }
  return e;
}

// Everything set-up writes: the edges, bounds and planes precede draw/primitive/sort_key
// and hold no padding, so bytes compare floats bit for bit (NaN and -0 included).
constexpr size_t kSetupBytes = offsetof(TriSetup, draw);

void expect_same(const std::vector<Tri>& tris, const Viewport& vp, CullMode cull, const std::string& what) {
  ASSERT_LE(tris.size(), kSetupBatch);
  const Expected e = reference(tris, vp, cull);
  SnappedBatch in;
  in.count = static_cast<uint32_t>(tris.size());
  for (size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      in.x[k][i] = tris[i].v[k].x;
      in.y[k][i] = tris[i].v[k].y;
      in.depth[k][i] = tris[i].v[k].depth;
      in.inv_w[k][i] = tris[i].v[k].inv_w;
    }
  test::for_each_target([&](const std::string& target) {
    std::vector<TriSetup> out(kSetupBatch);
    uint8_t index[kSetupBatch];
    const uint32_t n = setup_snapped_batch(in, vp, cull, out.data(), index);
    ASSERT_EQ(n, e.setups.size()) << what << " on " << target;
    for (uint32_t j = 0; j < n; ++j) {
      ASSERT_EQ(index[j], e.index[j]) << what << " on " << target << ", survivor " << j;
      ASSERT_EQ(std::memcmp(&out[j], &e.setups[j], kSetupBytes), 0)
          << what << " on " << target << ", triangle " << int(index[j]) << " (x0 " << out[j].x0 << " vs "
          << e.setups[j].x0 << ", z.ref " << out[j].z.ref << " vs " << e.setups[j].z.ref << ")";
    }
  });
}

constexpr CullMode kCulls[] = {CullMode::None, CullMode::Back, CullMode::Front};

SnappedVertex vertex(int32_t x, int32_t y, double depth = 0.5, double inv_w = 1.0) { return {x, y, depth, inv_w}; }

TEST(SetupBatch, RandomTrianglesOfEverySizeMatchTheScalarSetUp) {
  std::mt19937_64 rng(20261122);
  const Viewport viewports[] = {{1024, 768}, {1, 1}, {7, 5}, {kMaxImageSide, kMaxImageSide}};
  for (const Viewport& vp : viewports) {
    const int32_t lo_x = -kGuardBand * kSubPixelScale, hi_x = (vp.width + kGuardBand) * kSubPixelScale;
    const int32_t lo_y = -kGuardBand * kSubPixelScale, hi_y = (vp.height + kGuardBand) * kSubPixelScale;
    std::uniform_int_distribution<int32_t> any_x(lo_x, hi_x), any_y(lo_y, hi_y);
    std::uniform_int_distribution<int32_t> in_x(0, vp.width * kSubPixelScale), in_y(0, vp.height * kSubPixelScale);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_real_distribution<double> log_w(-3.0, 6.0);
    for (int round = 0; round < 400; ++round) {
      // Spans from sub-pixel slivers to the whole guard band.
      const int32_t span = int32_t(1) << std::uniform_int_distribution<int>(2, 23)(rng);
      std::uniform_int_distribution<int32_t> near(-span, span);
      std::vector<Tri> tris(std::uniform_int_distribution<size_t>(1, kSetupBatch)(rng));
      for (Tri& t : tris) {
        const bool wide = unit(rng) < 0.2;
        const int32_t cx = wide ? any_x(rng) : in_x(rng), cy = wide ? any_y(rng) : in_y(rng);
        for (SnappedVertex& v : t.v) {
          v.x = std::clamp(cx + near(rng), lo_x, hi_x);
          v.y = std::clamp(cy + near(rng), lo_y, hi_y);
          // Snapped positions on whole pixels or half pixels now and then: edges through
          // pixel centres, where the top-left rule decides.
          if (unit(rng) < 0.2) v.x &= ~(kSubPixelScale / 2 - 1);
          if (unit(rng) < 0.2) v.y &= ~(kSubPixelScale / 2 - 1);
          v.depth = unit(rng);
          v.inv_w = std::pow(10.0, log_w(rng));
        }
      }
      for (CullMode cull : kCulls)
        expect_same(tris, vp, cull, "viewport " + std::to_string(vp.width) + "x" + std::to_string(vp.height) +
                                        ", round " + std::to_string(round) + ", cull " + std::to_string(int(cull)));
    }
  }
}

TEST(SetupBatch, HardTrianglesMatchTheScalarSetUp) {
  const Viewport vp{1024, 768};
  const int32_t s = kSubPixelScale, h = kSubPixelScale / 2;
  const int32_t gx0 = -kGuardBand * s, gx1 = (vp.width + kGuardBand) * s;
  const int32_t gy0 = -kGuardBand * s, gy1 = (vp.height + kGuardBand) * s;
  std::vector<Tri> tris = {
      {{vertex(0, 0), vertex(0, 0), vertex(0, 0)}},                       // a point
      {{vertex(0, 0), vertex(100 * s, 100 * s), vertex(50 * s, 50 * s)}},  // collinear
      {{vertex(10 * s + 10, 10 * s + 10), vertex(10 * s + 60, 10 * s + 10), vertex(10 * s + 10, 10 * s + 60)}},  // no centre
      // Edges through pixel centres, both windings: the top-left rule owns each once.
      {{vertex(2 * s + h, 2 * s + h), vertex(6 * s + h, 2 * s + h), vertex(2 * s + h, 6 * s + h)}},
      {{vertex(2 * s + h, 2 * s + h), vertex(2 * s + h, 6 * s + h), vertex(6 * s + h, 2 * s + h)}},
      {{vertex(6 * s + h, 6 * s + h), vertex(2 * s + h, 6 * s + h), vertex(6 * s + h, 2 * s + h)}},
      // The whole guard band, both windings, and a sliver along it.
      {{vertex(gx0, gy0), vertex(gx1, gy0), vertex(gx0, gy1)}},
      {{vertex(gx0, gy0), vertex(gx0, gy1), vertex(gx1, gy1)}},
      {{vertex(gx0, gy0), vertex(gx1, gy1), vertex(gx1, gy1 - 1)}},
      // Outside the viewport: right, below, left and above.
      {{vertex(2000 * s, 10 * s), vertex(2100 * s, 10 * s), vertex(2000 * s, 90 * s)}},
      {{vertex(10 * s, 900 * s), vertex(90 * s, 900 * s), vertex(10 * s, 990 * s)}},
      {{vertex(-90 * s, 10 * s), vertex(-10 * s, 10 * s), vertex(-90 * s, 90 * s)}},
      {{vertex(10 * s, -90 * s), vertex(90 * s, -90 * s), vertex(10 * s, -10 * s)}},
      // The viewport's last pixel, depths at the ends of [0, 1], 1/w at the ends of its range
      // (clip w is a float of at least 1e-6).
      {{vertex(1023 * s, 767 * s, 0.0, 1e-38), vertex(1024 * s, 767 * s, 1.0, 1e6), vertex(1023 * s, 768 * s, 1.0, 1.0)}},
      {{vertex(0, 0, 1.0, 1e6), vertex(s, 0, 0.0, 1e-6), vertex(0, s, 0.5, 3.0)}},
  };
  for (CullMode cull : kCulls) expect_same(tris, vp, cull, "hard cases, cull " + std::to_string(int(cull)));
  // Every batch length around the vector widths (2, 4 and 8 doubles).
  for (size_t count : {size_t{1}, size_t{2}, size_t{3}, size_t{5}, size_t{7}, size_t{9}, size_t{15}}) {
    std::vector<Tri> some(tris.begin(), tris.begin() + std::min(count, tris.size()));
    while (some.size() < count) some.push_back(tris[some.size() % tris.size()]);
    expect_same(some, vp, CullMode::None, "batch of " + std::to_string(count));
  }
  expect_same({}, vp, CullMode::None, "empty batch");
}

}  // namespace setup_batch_test
}  // namespace pelt::raster
