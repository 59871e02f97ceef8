// transform_vertices (the SIMD vertex stage) against transform_vertices_reference (the
// scalar code it replaced), byte for byte (any NaN for a NaN, see same_float), on every
// Highway target this CPU runs, with and without the FTZ/DAZ mode of the renderer's workers.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "raster/config.h"
#include "raster/parallel.h"
#include "raster/vertex_kernels.h"
#include "tests/raster/render_helpers.h"

namespace pelt::raster::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kDenorm = 1e-40f;
const Viewport kViewports[] = {{1, 1}, {1024, 768}, {16384, 16384}};

// Positions copied to the end of a page followed by an inaccessible one: a kernel that
// reads past the last vertex faults instead of passing.
class GuardedPositions {
 public:
  explicit GuardedPositions(std::span<const glm::vec3> src) {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    const size_t data_bytes = src.size_bytes();
    bytes_ = (data_bytes + page - 1) / page * page + page;
    void* p = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    base_ = static_cast<char*>(p);
    mprotect(base_ + bytes_ - page, page, PROT_NONE);
    data_ = reinterpret_cast<glm::vec3*>(base_ + bytes_ - page - data_bytes);
    if (data_bytes) std::memcpy(data_, src.data(), data_bytes);
  }
  ~GuardedPositions() { munmap(base_, bytes_); }
  GuardedPositions(const GuardedPositions&) = delete;
  GuardedPositions& operator=(const GuardedPositions&) = delete;
  const glm::vec3* data() const { return data_; }

 private:
  char* base_ = nullptr;
  size_t bytes_ = 0;
  glm::vec3* data_ = nullptr;
};

template <class T>
std::string hex(const T& v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  std::string s;
  char buf[4];
  for (size_t i = 0; i < sizeof(T); ++i) {
    std::snprintf(buf, sizeof(buf), "%02x", b[i]);
    s += buf;
  }
  return s;
}

// Bit for bit, except that a NaN may be any NaN. Which NaN a + b returns when both are NaN
// is the first operand's on x86, and a compiler may swap the operands of a + b, so the
// scalar code's own NaN bits (Inf * 0 gives the negative default NaN, a NaN position its
// own) depend on register allocation. Such a vertex has code kNonFinite, which culls every
// triangle using it: its clip position and w are never read.
bool same_float(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0 || (std::isnan(a) && std::isnan(b));
}

struct Counts {
  size_t vertices = 0, snapped = 0, non_finite = 0, clipped = 0;
};

// Runs kernel and reference on vertices [first, first + count) of `pos` and compares all
// of both output arrays as bytes (NaNs as NaNs, see same_float). The arrays start filled with a pattern and reach past
// the range on both sides, so a write outside it shows as a difference too.
::testing::AssertionResult same_as_reference(const glm::mat4& m, std::span<const glm::vec3> pos,
                                             uint32_t first, uint32_t count, const Viewport& vp,
                                             Counts* counts = nullptr) {
  const GuardedPositions guarded(pos.subspan(0, size_t{first} + count));
  const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
  const size_t n = size_t{first} + count + 16;
  std::vector<glm::vec4> clip_ref(n), clip_simd(n);
  std::vector<FrontVertex> front_ref(n), front_simd(n);
  for (auto* v : {&clip_ref, &clip_simd}) std::memset(v->data(), 0xA5, n * sizeof(glm::vec4));
  for (auto* v : {&front_ref, &front_simd}) std::memset(v->data(), 0xA5, n * sizeof(FrontVertex));
  transform_vertices_reference(m, guarded.data(), first, count, vp, bounds, clip_ref.data(), front_ref.data());
  transform_vertices(m, guarded.data(), first, count, vp, bounds, clip_simd.data(), front_simd.data());

  int bad = 0;
  std::string msg;
  for (size_t v = 0; v < n; ++v) {
    bool same_clip = true;
    for (int k = 0; k < 4; ++k) same_clip &= same_float(clip_ref[v][k], clip_simd[v][k]);
    const bool same_front = std::memcmp(&front_ref[v], &front_simd[v], offsetof(FrontVertex, w)) == 0 &&
                            same_float(front_ref[v].w, front_simd[v].w);
    if (same_clip && same_front) continue;
    if (++bad > 8) continue;
    const FrontVertex &r = front_ref[v], &s = front_simd[v];
    const glm::vec3 p = v < size_t{first} + count ? pos[v] : glm::vec3(0.0f);
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "\n  vertex %zu (range [%u, %u)) position (%a, %a, %a) vp %dx%d:"
                  "\n    clip  ref %s simd %s"
                  "\n    code  ref %08x simd %08x  w ref %a simd %a"
                  "\n    snap  ref (%d, %d, %a, %a) simd (%d, %d, %a, %a)",
                  v, first, first + count, p.x, p.y, p.z, vp.width, vp.height,
                  hex(clip_ref[v]).c_str(), hex(clip_simd[v]).c_str(), r.code, s.code, r.w, s.w,
                  r.snap.x, r.snap.y, r.snap.depth, r.snap.inv_w, s.snap.x, s.snap.y, s.snap.depth,
                  s.snap.inv_w);
    msg += buf;
  }
  if (counts) {
    for (uint32_t v = first; v < first + count; ++v) {
      const uint32_t c = front_ref[v].code;
      ++counts->vertices;
      counts->non_finite += (c & kNonFinite) != 0;
      counts->clipped += (c & kNonFinite) == 0 && (c & kClipPlaneBits) != 0;
      counts->snapped += (c & (kNonFinite | kClipPlaneBits)) == 0;
    }
  }
  if (bad == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << bad << " of " << n << " records differ:" << msg;
}

// fn() once per Highway target, in the default floating-point mode and under FTZ/DAZ.
template <class Fn>
void for_each_target_and_mode(Fn&& fn) {
  for_each_target([&](const std::string& target) {
    for (const bool ftz : {false, true}) {
      SCOPED_TRACE(target + (ftz ? " FTZ/DAZ" : " IEEE"));
      std::optional<ScopedFlushToZero> mode;
      if (ftz) mode.emplace();
      fn();
    }
  });
}

// Object-space points whose clip positions under m lie in or around the view volume
// (NDC up to 1.3, sometimes out to the guard band and past it), so that most vertices snap
// and every plane is crossed; the rest uniform in a box of half-size `box`.
std::vector<glm::vec3> points_around_frustum(const glm::mat4& m, float w_lo, float w_hi, float box,
                                             const ClipBounds& bounds, size_t count, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  const glm::dmat4 inv = glm::inverse(glm::dmat4(m));
  std::vector<glm::vec3> pos(count);
  for (glm::vec3& p : pos) {
    if (u01(rng) < 0.15) {
      p = glm::vec3(u(rng), u(rng), u(rng)) * box;
      continue;
    }
    const bool guard = u01(rng) < 0.2;
    const double nx = u(rng) * (guard ? bounds.guard_x * 1.05 : 1.3);
    const double ny = u(rng) * (guard ? bounds.guard_y * 1.05 : 1.3);
    const double nz = u(rng) * 1.05;
    const double w = w_lo + (w_hi - w_lo) * u01(rng);
    const glm::dvec4 o = inv * glm::dvec4(nx * w, ny * w, nz * w, w);
    p = glm::vec3(glm::dvec3(o) / o.w);
  }
  return pos;
}

glm::mat4 random_perspective(std::mt19937& rng, float& near, float& far) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  const float fovy = glm::radians(10.0f + 110.0f * u01(rng));
  const float aspect = std::exp(u(rng) * 1.2f);
  near = std::pow(10.0f, -3.0f + 3.0f * u01(rng));
  far = near * std::pow(10.0f, 1.0f + 3.0f * u01(rng));
  const glm::mat4 proj = glm::perspective(fovy, aspect, near, far);
  const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.0f, 1e-3f));
  const glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(u(rng), u(rng), u(rng)) * far * 0.1f) *
                         glm::rotate(glm::mat4(1.0f), 3.14159f * u(rng), axis);
  return proj * view * glm::scale(glm::mat4(1.0f), glm::vec3(std::exp(u(rng) * 2.0f)));
}

glm::mat4 random_general(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  glm::mat4 m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m[c][r] = u01(rng) < 0.1f ? 0.0f : u(rng) * std::pow(10.0f, 2.0f * u(rng));
  m[3][3] = 1.0f + 4.0f * u01(rng);  // mostly positive w, so that many vertices snap
  return m;
}

// One random draw: its matrix and its object-space positions.
struct Draw {
  glm::mat4 m;
  std::vector<glm::vec3> pos;
};

TEST(VertexKernels, RandomPerspectiveMatricesMatchReference) {
  for (const Viewport& vp : kViewports) {
    std::mt19937 rng(1234 + vp.width);
    const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
    std::vector<Draw> draws;
    for (int d = 0; d < 40; ++d) {
      float near, far;
      const glm::mat4 m = random_perspective(rng, near, far);
      draws.push_back({m, points_around_frustum(m, 0.5f * near, 1.1f * far, far, bounds, 2600, rng)});
    }
    Counts counts;
    for_each_target_and_mode([&] {
      for (size_t d = 0; d < draws.size(); ++d) {
        SCOPED_TRACE("draw " + std::to_string(d));
        // An odd first vertex: every load and store unaligned.
        ASSERT_TRUE(same_as_reference(draws[d].m, draws[d].pos, 1, uint32_t(draws[d].pos.size() - 1), vp, &counts));
      }
    });
    EXPECT_GE(counts.vertices / (2 * hwy::SupportedAndGeneratedTargets().size()), 100000u);
    EXPECT_GT(counts.snapped, counts.vertices / 2) << "too few vertices exercise snap_vertex";
    EXPECT_GT(counts.clipped, counts.vertices / 20) << "too few vertices exercise the outcode";
  }
}

TEST(VertexKernels, RandomGeneralMatricesMatchReference) {
  for (const Viewport& vp : kViewports) {
    std::mt19937 rng(99 + vp.height);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
    std::vector<Draw> draws;
    for (int d = 0; d < 40; ++d) {
      const glm::mat4 m = random_general(rng);
      std::vector<glm::vec3> pos = points_around_frustum(m, -0.5f, 10.0f, 10.0f, bounds, 2600, rng);
      // Some positions of any magnitude: float products that overflow, and tiny ones.
      for (size_t i = 0; i < pos.size(); i += 7)
        pos[i] = glm::vec3(u(rng), u(rng), u(rng)) * std::pow(10.0f, 38.0f * u(rng));
      draws.push_back({m, std::move(pos)});
    }
    Counts counts;
    for_each_target_and_mode([&] {
      for (size_t d = 0; d < draws.size(); ++d) {
        SCOPED_TRACE("draw " + std::to_string(d));
        ASSERT_TRUE(same_as_reference(draws[d].m, draws[d].pos, 0, uint32_t(draws[d].pos.size()), vp, &counts));
      }
    });
    EXPECT_GE(counts.vertices / (2 * hwy::SupportedAndGeneratedTargets().size()), 100000u);
    EXPECT_GT(counts.snapped, counts.vertices / 4) << "too few vertices exercise snap_vertex";
    EXPECT_GT(counts.non_finite, 0u);
  }
}

// clip = (x, y, z, w) for position (x, y, z) and a fixed w: every clip coordinate chosen.
glm::mat4 clip_with_w(float w) {
  glm::mat4 m(1.0f);
  m[3][3] = w;
  return m;
}

TEST(VertexKernels, NonFiniteInputsMatchReference) {
  const float bad[] = {kNaN, -kNaN, kInf, -kInf};
  const float ok[] = {0.0f, -0.5f, 0.25f, 3.0f};
  std::vector<glm::vec3> pos;
  for (float b : bad)
    for (int k = 0; k < 3; ++k)
      for (float o : ok) {
        glm::vec3 p(o, 0.5f * o, 0.75f);
        p[k] = b;
        pos.push_back(p);
      }
  pos.push_back(glm::vec3(kNaN, kInf, -kInf));
  pos.push_back(glm::vec3(3e38f, 3e38f, 3e38f));  // overflows to Inf in the matrix product
  for (int i = 0; i < 8; ++i) pos.push_back(glm::vec3(0.1f * i, -0.1f * i, 0.5f));
  for_each_target_and_mode([&] {
    for (const Viewport& vp : kViewports) {
      ASSERT_TRUE(same_as_reference(clip_with_w(1.0f), pos, 0, uint32_t(pos.size()), vp));
      // Every matrix entry non-finite in turn, on ordinary positions (and on bad ones).
      for (int e = 0; e < 16; ++e)
        for (float b : bad) {
          glm::mat4 m = glm::perspective(1.0f, 1.3f, 0.1f, 100.0f) * clip_with_w(1.0f);
          m[e / 4][e % 4] = b;
          SCOPED_TRACE("matrix entry " + std::to_string(e));
          ASSERT_TRUE(same_as_reference(m, pos, 0, uint32_t(pos.size()), vp));
        }
    }
  });
}

// Vertices exactly on, and one float step either side of, every plane: w = 0 and the
// smallest w kept (1e-6), near and far, the guard band; negative w; huge and denormal
// coordinates.
TEST(VertexKernels, PlaneBoundariesMatchReference) {
  const float w_min = static_cast<float>(kMinW);
  const float ws[] = {0.0f, -0.0f, kDenorm, -kDenorm, std::nextafter(w_min, 0.0f), w_min,
                      std::nextafter(w_min, 1.0f), std::nextafter(std::nextafter(w_min, 1.0f), 1.0f),
                      1e-5f, 0.5f, 1.0f, 3.0f, 1e6f, 1e30f, -1e-6f, -1.0f, -1e30f,
                      std::numeric_limits<float>::max()};
  for_each_target_and_mode([&] {
    for (const Viewport& vp : kViewports) {
      const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
      for (const float w : ws) {
        const float aw = std::abs(w);
        const auto to_float = [](double v) { return static_cast<float>(std::min(v, 3.4e38)); };
        const float gx = to_float(bounds.guard_x * aw), gy = to_float(bounds.guard_y * aw);
        std::vector<float> xs = {0.0f, -0.0f, aw, -aw, gx, -gx, 1e30f, -1e30f, kDenorm, 0.5f * aw};
        std::vector<float> ys = {0.0f, aw, -aw, gy, -gy, -1e30f, -kDenorm};
        std::vector<float> zs = {0.0f, aw, -aw, 1e30f, kDenorm};
        for (auto* v : {&xs, &ys, &zs}) {
          const size_t n = v->size();
          for (size_t i = 0; i < n; ++i)
            if ((*v)[i] != 0.0f) {
              v->push_back(std::nextafter((*v)[i], 0.0f));
              v->push_back(std::nextafter((*v)[i], 2.0f * (*v)[i]));
            }
        }
        std::vector<glm::vec3> pos;
        for (float x : xs)
          for (float y : ys)
            for (float z : zs) pos.push_back({x, y, z});
        SCOPED_TRACE("w " + std::to_string(w));
        ASSERT_TRUE(same_as_reference(clip_with_w(w), pos, 0, uint32_t(pos.size()), vp));
      }
    }
  });
}

TEST(VertexKernels, DenormalsMatchReference) {
  std::vector<glm::vec3> pos;
  for (float a : {kDenorm, -kDenorm, 1e-45f, 1e-38f, 0.0f, 0.5f})
    for (float b : {kDenorm, -3e-39f, 0.25f}) pos.push_back({a, b, a * 0.5f});
  for_each_target_and_mode([&] {
    for (const Viewport& vp : kViewports) {
      glm::mat4 m = glm::perspective(1.0f, 1.0f, 0.1f, 10.0f);
      ASSERT_TRUE(same_as_reference(m, pos, 0, uint32_t(pos.size()), vp));
      for (int e = 0; e < 16; ++e) {
        glm::mat4 md = m;
        md[e / 4][e % 4] = e % 2 ? kDenorm : -kDenorm;
        ASSERT_TRUE(same_as_reference(md, pos, 0, uint32_t(pos.size()), vp));
      }
      // Products that underflow into denormals, and w itself denormal.
      ASSERT_TRUE(same_as_reference(glm::scale(glm::mat4(1.0f), glm::vec3(1e-30f)) * clip_with_w(1e-38f), pos, 0,
                                    uint32_t(pos.size()), vp));
    }
  });
}

// Snapped positions exactly halfway between two sub-pixel steps, both parities and signs
// (lrint rounds them to even, round-half-away would not), and just either side of halfway.
TEST(VertexKernels, RoundingTiesMatchReference) {
  for_each_target_and_mode([&] {
    for (const Viewport& vp : kViewports) {
      std::vector<glm::vec3> pos;
      // sx * 256 = (x / 2 + 0.5) * width * 256 = n + 0.5  <=>  x = (2n + 1) / (width * 256) - 1.
      const double steps_x = double(vp.width) * kSubPixelScale, steps_y = double(vp.height) * kSubPixelScale;
      for (int n = -40; n < 40; ++n) {
        const int nn = n < 0 ? n : n + static_cast<int>(steps_x / 2) - 20;  // near both ends too
        const float x = static_cast<float>((2.0 * nn + 1.0) / steps_x - 1.0);
        const float y = static_cast<float>(1.0 - (2.0 * (n + 3) + 1.0) / steps_y);
        for (float xx : {x, std::nextafter(x, -2.0f), std::nextafter(x, 2.0f)}) pos.push_back({xx, y, 0.25f});
      }
      ASSERT_TRUE(same_as_reference(clip_with_w(1.0f), pos, 0, uint32_t(pos.size()), vp));
      // The same points with w != 1: 1/w rounds, so the products land near, not on, halves.
      ASSERT_TRUE(same_as_reference(clip_with_w(3.0f) * glm::scale(glm::mat4(1.0f), glm::vec3(3.0f)), pos, 0,
                                    uint32_t(pos.size()), vp));
      ASSERT_TRUE(same_as_reference(clip_with_w(0.1f) * glm::scale(glm::mat4(1.0f), glm::vec3(0.1f)), pos, 0,
                                    uint32_t(pos.size()), vp));
    }
  });
}

// Every count around the vector widths (1, 2, 4, 8 doubles) at odd and even first
// vertices: the partial last vector never reads or writes outside its range.
TEST(VertexKernels, CountsAndOffsetsMatchReference) {
  std::mt19937 rng(7);
  const Viewport vp{1024, 768};
  const glm::mat4 m = glm::perspective(1.0f, 4.0f / 3.0f, 0.5f, 50.0f) *
                      glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -5.0f));
  const std::vector<glm::vec3> pos = points_around_frustum(m, 0.5f, 50.0f, 10.0f, make_clip_bounds(vp.width, vp.height), 64, rng);
  for_each_target_and_mode([&] {
    for (uint32_t first : {0u, 1u, 2u, 3u, 5u, 8u, 13u})
      for (uint32_t count : {0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 11u, 15u, 16u, 17u, 31u, 33u}) {
        SCOPED_TRACE("first " + std::to_string(first) + " count " + std::to_string(count));
        ASSERT_TRUE(same_as_reference(m, pos, first, count, vp));
      }
  });
}

}  // namespace
}  // namespace pelt::raster::test
