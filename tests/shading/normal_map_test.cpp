// The normal mapping kernel (shading/normal_map.h) against its double-precision reference, for
// every compiled Highway target: a million random lanes (frames near degenerate included), the
// hard cases, any lane count and alignment, the frame's known values, and the validation.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "shading/normal_map.h"
#include "tests/shading/batch_harness.h"
#include "tests/shading/random_inputs.h"

namespace pelt::shading {
namespace normal_map_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::Buffer;
using testing::for_each_target;
using testing::make_buffer;
using testing::Rng;

// normal (3), tangent (4), texel (3) and out (3) arrays of n floats, each starting `offset`
// floats into its buffer (an offset not a multiple of 16 makes every pointer unaligned). A call
// reads one Lanes' inputs and writes another's outputs.
struct Lanes {
  size_t n, offset;
  std::vector<Buffer> a;
  explicit Lanes(size_t n_, size_t offset_ = 0) : n(n_), offset(offset_) {
    for (int k = 0; k < 13; ++k) a.push_back(make_buffer(n + offset + 16));
  }
  float* at(int k) const { return a[k].get() + offset; }
  float* normal(int c) const { return at(c); }
  float* tangent(int c) const { return at(3 + c); }
  float* texel(int c) const { return at(7 + c); }
  float* out(int c) const { return at(10 + c); }
  NormalMapSoA soa() const {
    return NormalMapSoA{n,
                        {normal(0), normal(1), normal(2)},
                        {tangent(0), tangent(1), tangent(2), tangent(3)},
                        {texel(0), texel(1), texel(2)}};
  }
  void set(size_t i, const std::array<float, 3>& nrm, const std::array<float, 4>& tan,
           const std::array<float, 3>& tex) {
    for (int c = 0; c < 3; ++c) normal(c)[i] = nrm[c], texel(c)[i] = tex[c];
    for (int c = 0; c < 4; ++c) tangent(c)[i] = tan[c];
  }
  std::string describe(size_t i) const {
    char buf[320];
    std::snprintf(buf, sizeof buf, "N %.9g %.9g %.9g T %.9g %.9g %.9g w %.9g tex %.9g %.9g %.9g", normal(0)[i],
                  normal(1)[i], normal(2)[i], tangent(0)[i], tangent(1)[i], tangent(2)[i], tangent(3)[i],
                  texel(0)[i], texel(1)[i], texel(2)[i]);
    return buf;
  }
};

void run_kernel(const Lanes& in, const Lanes& dst) {
  float* const out[3] = {dst.out(0), dst.out(1), dst.out(2)};
  perturb_normals(in.soa(), out);
}
void run_reference(const Lanes& in, const Lanes& dst) {
  float* const out[3] = {dst.out(0), dst.out(1), dst.out(2)};
  perturb_normals_reference(in.soa(), out);
}

double length(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

// The header's precision: each component within 1e-5 of the reference relative, or 2^-21 of the
// reference's length absolute (a float sum of terms of size |m| rounds to a few ulps of |m|,
// which is a large relative error of a component where they cancel). Also the worst errors seen,
// for the log: in ulps of |ref| (2^-23 |ref|, an ulp of a unit vector), and relative where a
// component is >= 1e-3.
struct Errors {
  double worst_ulps = 0.0, worst_relative = 0.0;
  size_t strict_misses = 0;  // components outside relative 1e-5 (>= 1e-3) / absolute 1e-6 (below)
  size_t components = 0;
};

size_t expect_close(const Lanes& in, const Lanes& ref, const Lanes& got, Errors& err) {
  size_t bad = 0;
  for (size_t i = 0; i < in.n; ++i) {
    const double len = length(ref.out(0)[i], ref.out(1)[i], ref.out(2)[i]);
    for (int c = 0; c < 3; ++c) {
      const double r = ref.out(c)[i], g = got.out(c)[i], e = std::fabs(g - r);
      ++err.components;
      if (len > 0.0) err.worst_ulps = std::max(err.worst_ulps, e / (0x1p-23 * len));
      if (std::fabs(r) >= 1e-3) err.worst_relative = std::max(err.worst_relative, e / std::fabs(r));
      if (std::fabs(r) >= 1e-3 ? e > 1e-5 * std::fabs(r) : e > 1e-6) ++err.strict_misses;
      if (std::isfinite(g) && e <= std::max(1e-5 * std::fabs(r), 0x1p-21 * len)) continue;
      if (bad++ < 5)
        ADD_FAILURE() << "lane " << i << " component " << c << ": kernel " << g << " reference " << r << " "
                      << in.describe(i);
    }
  }
  return bad;
}

// The header's bounds: out = N bit for bit where T vanishes (`passes`), else
// |out| <= |m| (1 + 2^-20). Returns the worst |out| / |m| - 1 seen.
double expect_bounded(const Lanes& in, const Lanes& got, const std::function<bool(size_t)>& passes) {
  double worst = 0.0;
  size_t bad = 0;
  for (size_t i = 0; i < in.n; ++i) {
    const double g[3] = {got.out(0)[i], got.out(1)[i], got.out(2)[i]};
    for (int c = 0; c < 3; ++c) {
      if (std::isfinite(g[c])) continue;
      if (bad++ < 5) ADD_FAILURE() << "lane " << i << ": non-finite output " << in.describe(i);
    }
    if (passes(i)) {
      for (int c = 0; c < 3; ++c)
        if (std::memcmp(&got.out(c)[i], &in.normal(c)[i], sizeof(float)) != 0 && bad++ < 5)
          ADD_FAILURE() << "lane " << i << ": not passed through " << in.describe(i);
      continue;
    }
    double m[3];
    for (int c = 0; c < 3; ++c) m[c] = 2.0 * std::clamp(double(in.texel(c)[i]), 0.0, 1.0) - 1.0;
    const double lm = length(m[0], m[1], m[2]), lo = length(g[0], g[1], g[2]);
    if (lm > 0.0) worst = std::max(worst, lo / lm - 1.0);
    if (lo <= lm * (1.0 + 0x1p-20)) continue;
    if (bad++ < 5) ADD_FAILURE() << "lane " << i << ": |out| " << lo << " > |m| " << lm << " " << in.describe(i);
  }
  EXPECT_EQ(bad, 0u);
  return worst;
}

// A random frame: the normal any direction and length in [1e-3, 1e3]; the tangent a random
// direction, or (a quarter of the lanes) +-N turned by a random angle down to 1e-7 radians, the
// range where the kernel switches between its float and double evaluations; any handedness;
// one lane in 512 with a zero normal, one in 512 with a zero tangent.
void random_lanes(Rng& r, Lanes& in) {
  for (size_t i = 0; i < in.n; ++i) {
    float n[3], t[3];
    r.unit(n);
    r.unit(t);
    const float nl = r.logu(1e-3f, 1e3f), tl = r.logu(1e-3f, 1e3f);
    if (r.pick(4) == 0) {
      const float turn = r.logu(1e-7f, 1.0f), sign = r.pick(2) ? 1.0f : -1.0f;
      for (int c = 0; c < 3; ++c) t[c] = sign * n[c] + turn * t[c];
    }
    static constexpr float kHandedness[] = {1.0f, -1.0f, 0.0f, -0.0f, 0.3f, -7.0f};
    for (int c = 0; c < 3; ++c) {
      in.normal(c)[i] = n[c] * nl;
      in.tangent(c)[i] = t[c] * tl;
      // 8-bit texels (the usual map) and continuous ones (filtered, or a float map)
      in.texel(c)[i] = r.pick(2) ? float(r.pick(256)) / 255.0f : r.uni(0.0f, 1.0f);
    }
    in.tangent(3)[i] = kHandedness[r.pick(6)];
    if (r.pick(512) == 0)
      for (int c = 0; c < 3; ++c) in.normal(c)[i] = 0.0f;
    if (r.pick(512) == 0)
      for (int c = 0; c < 3; ++c) in.tangent(c)[i] = 0.0f;
  }
}

// A zero tangent is the only way a random lane passes N through.
bool zero_tangent(const Lanes& in, size_t i) {
  return in.tangent(0)[i] == 0.0f && in.tangent(1)[i] == 0.0f && in.tangent(2)[i] == 0.0f;
}

TEST(NormalMapKernel, MatchesReferenceOnAMillionRandomLanes) {
  Rng r(0x40a1);
  const size_t n = 16384;
  const int batches = 64;  // 1,048,576 lanes
  Lanes in(n), ref(n), got(n);
  std::vector<Errors> errors(hwy::SupportedAndGeneratedTargets().size());
  double worst_norm = 0.0;
  for (int b = 0; b < batches; ++b) {
    random_lanes(r, in);
    run_reference(in, ref);
    SCOPED_TRACE("batch " + std::to_string(b));
    size_t k = 0;
    for_each_target([&](int64_t) {
      run_kernel(in, got);
      EXPECT_EQ(expect_close(in, ref, got, errors[k++]), 0u);
      worst_norm = std::max(worst_norm, expect_bounded(in, got, [&](size_t i) { return zero_tangent(in, i); }));
    });
  }
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  for (size_t k = 0; k < targets.size(); ++k)
    std::printf("%s: worst error %.2f ulps of |ref|, worst relative %.3g (components >= 1e-3); %zu of %zu "
                "components outside relative 1e-5 / absolute 1e-6\n",
                hwy::TargetName(targets[k]), errors[k].worst_ulps, errors[k].worst_relative,
                errors[k].strict_misses, errors[k].components);
  std::printf("worst |out| / |m| - 1: %.3g\n", worst_norm);
}

// One lane per case, each with every texel of a small set; 37 lanes a batch, so the last
// partial vector of every target is exercised too.
TEST(NormalMapKernel, HardCasesMatchReferenceAndStayFinite) {
  struct Frame {
    std::array<float, 3> n;
    std::array<float, 4> t;
    bool passes;  // the model passes N through: T vanishes after Gram-Schmidt
  };
  const float den = 1e-40f, big = 1e30f, max = FLT_MAX;
  const std::vector<Frame> frames = {
      {{0, 0, 1}, {1, 0, 0, 1}, false},                  // plain
      {{0, 0, 0}, {1, 2, 3, 1}, false},                  // zero normal: out = m.x Tu
      {{0, 0, 1}, {0, 0, 0, 1}, true},                   // zero tangent
      {{0, 0, 0}, {0, 0, 0, -1}, true},                  // both zero
      {{0.3f, -2, 5}, {0, 0, 0, 1}, true},               // zero tangent, unnormalised N passes through
      {{0, 0, 2}, {0, 0, -3, 1}, true},                  // T along -N, exactly
      {{1, 2, 3}, {-2, -4, -6, 1}, true},                // T = -2 N, exactly
      {{0.3f, -0.7f, 0.2f}, {0.93f, -2.17f, 0.62f, 1}, false},  // T = 3.1 N up to rounding
      {{0.3f, -0.7f, 0.2f}, {0.3f, -0.7f, 0.2001f, 1}, false},  // T within 1e-4 of N
      {{0, 0, 1}, {1e-30f, 0, 1, 1}, false},             // T along N but for 1e-30
      {{1, 0, 0}, {1, 1e-30f, 0, -1}, false},            // the same, the remainder's square underflows
      {{den, 0, den}, {0, den, 0, 1}, false},            // denormal normal and tangent
      {{den, -den, 0}, {1, 0.5f, 0, 1}, false},          // denormal normal (the old loop lost it)
      {{0, 1, 0}, {den, 0, -den, -1}, false},            // denormal tangent
      {{1.4e-45f, 0, 0}, {0, 1.4e-45f, 0, 1}, false},    // the smallest denormals
      {{big, big, -big}, {big, 0, big, 1}, false},       // huge (the old loop gave NaN)
      {{big, 1e-30f, 0}, {1e-30f, big, 0, 1}, false},    // huge and tiny components together
      {{1e-30f, 0, 0}, {0, 1e-30f, 1e-30f, 1}, false},   // tiny
      {{max, -max, max}, {-max, max, max, -1}, false},   // the largest floats
      {{max, max, max}, {0, 0, 0, 1}, true},             // ... passed through
      {{0, 0, 1}, {1, 0, 0, 0.0f}, false},               // handedness 0
      {{0, 0, 1}, {1, 0, 0, -0.0f}, false},              // -0 counts as +1
      {{0, 0, 1}, {1, 0, 0, -1}, false},
      {{0, 0, 1}, {1, 0, 0, -1e-30f}, false},
      {{0.2f, 0.9f, -0.4f}, {3, -1, 7, 1}, false},       // skewed, unnormalised
      {{0.2f, 0.9f, -0.4f}, {3, -1, 7, -1}, false},
  };
  const std::vector<std::array<float, 3>> texels = {
      {0.5f, 0.5f, 1.0f}, {0, 0, 0}, {1, 1, 1}, {0.5f, 0.5f, 0.5f}, {1, 0.5f, 0.5f}, {0.5f, 0, 0.5f},
      {0.2f, 0.7f, 0.9f}, {-1, 2, 0.5f}, {1e30f, -1e30f, 1e-30f}, {den, 1 - 0x1p-24f, 0.5f + 0x1p-24f}};
  const size_t n = 37;
  std::vector<bool> passes;
  std::vector<Lanes> batches;
  {
    Lanes in(n);
    size_t i = 0;
    for (const Frame& f : frames)
      for (const auto& tex : texels) {
        in.set(i, f.n, f.t, tex);
        passes.push_back(f.passes);
        if (++i == n) {
          batches.push_back(std::move(in));
          in = Lanes(n);
          i = 0;
        }
      }
    for (; i < n; ++i) in.set(i, {0, 1, 0}, {0, 0, 1, 1}, {0.5f, 0.5f, 1}), passes.push_back(false);
    batches.push_back(std::move(in));
  }
  Errors err;
  for (size_t b = 0; b < batches.size(); ++b) {
    const Lanes& in = batches[b];
    Lanes ref(n), got(n);
    run_reference(in, ref);
    SCOPED_TRACE("batch " + std::to_string(b));
    expect_bounded(in, ref, [&](size_t i) { return passes[b * n + i]; });
    for_each_target([&](int64_t) {
      run_kernel(in, got);
      EXPECT_EQ(expect_close(in, ref, got, err), 0u);
      expect_bounded(in, got, [&](size_t i) { return passes[b * n + i]; });
    });
  }
}

// Lane i's output depends on lane i alone, wherever it sits: any n (0 included), any
// alignment, nothing written past n.
TEST(NormalMapKernel, AnyLaneCountAndAlignment) {
  Rng r(0x77);
  const size_t kMaxN = 70;
  Lanes all(kMaxN);
  random_lanes(r, all);
  Lanes want(kMaxN);
  run_reference(all, want);
  for_each_target([&](int64_t) {
    Lanes full(kMaxN);
    run_kernel(all, full);
    for (size_t offset : {size_t{0}, size_t{1}, size_t{3}, size_t{16}})
      for (size_t n = 0; n <= kMaxN; ++n) {
        Lanes in(n, offset), got(n, offset);
        for (int k = 0; k < 10; ++k) std::copy(all.at(k), all.at(k) + n, in.at(k));
        for (int c = 0; c < 3; ++c) std::fill(got.out(c), got.out(c) + n + 16, -123.0f);
        run_kernel(in, got);
        for (int c = 0; c < 3; ++c) {
          for (size_t i = 0; i < n; ++i)
            ASSERT_EQ(got.out(c)[i], full.out(c)[i]) << "n " << n << " offset " << offset << " lane " << i;
          for (size_t i = n; i < n + 16; ++i) ASSERT_EQ(got.out(c)[i], -123.0f) << "wrote past n " << n;
        }
      }
  });
}

// An orthonormal frame on the axes decodes the texel exactly: out = m, y mirrored for a
// negative handedness. And a flat texel gives the unit normal.
TEST(NormalMapKernel, AxisFrameDecodesTheTexelExactly) {
  const size_t n = 4;
  Lanes in(n), got(n), ref(n);
  const std::array<float, 3> tex = {0.8f, 0.1f, 0.75f};
  in.set(0, {0, 0, 1}, {1, 0, 0, 1}, tex);
  in.set(1, {0, 0, 1}, {1, 0, 0, -1}, tex);
  in.set(2, {0, 0, 5}, {4, 0, 0, 1}, tex);       // lengths do not matter
  in.set(3, {0, 3, 4}, {7, 0, 0, 1}, {0.5f, 0.5f, 1.0f});  // flat: the unit normal
  const float m[3] = {2 * tex[0] - 1, 2 * tex[1] - 1, 2 * tex[2] - 1};
  run_reference(in, ref);
  for_each_target([&](int64_t) {
    run_kernel(in, got);
    for (const Lanes* l : {&got, &ref}) {
      for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(l->out(0)[i], m[0]) << "lane " << i;
        EXPECT_EQ(l->out(1)[i], i == 1 ? -m[1] : m[1]) << "lane " << i;
        EXPECT_EQ(l->out(2)[i], m[2]) << "lane " << i;
      }
      EXPECT_EQ(l->out(0)[3], 0.0f);
      EXPECT_NEAR(l->out(1)[3], 0.6f, 1e-7f);
      EXPECT_NEAR(l->out(2)[3], 0.8f, 1e-7f);
    }
  });
}

// The kernel's power-of-two scaling is exact: scaling N and T by 2^k changes no output bit
// (lanes where N passes through scale with it).
TEST(NormalMapKernel, ScalingTheFrameChangesNothing) {
  Rng r(0x5ca1e);
  const size_t n = 4096;
  Lanes in(n), base(n), got(n);
  random_lanes(r, in);
  for_each_target([&](int64_t) {
    run_kernel(in, base);
    for (int k : {-40, -7, 9, 40}) {
      Lanes scaled(n);
      for (int a = 0; a < 10; ++a) std::copy(in.at(a), in.at(a) + n, scaled.at(a));
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n; ++i) {
          scaled.normal(c)[i] = std::ldexp(in.normal(c)[i], k);
          scaled.tangent(c)[i] = std::ldexp(in.tangent(c)[i], -k / 2);
        }
      run_kernel(scaled, got);
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n; ++i) {
          const float want = zero_tangent(in, i) ? std::ldexp(base.out(c)[i], k) : base.out(c)[i];
          ASSERT_EQ(got.out(c)[i], want) << "2^" << k << " lane " << i;
        }
    }
  });
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(NormalMapKernel, BadInputsNameTheField) {
  Lanes in(16), got(16);
  float* out[3] = {got.out(0), got.out(1), got.out(2)};
  for (auto* f : {&perturb_normals, &perturb_normals_reference}) {
    EXPECT_EQ(error_of([&] { f(in.soa(), out); }), "(no error)");
    NormalMapSoA s = in.soa();
    s.tangent[3] = nullptr;
    EXPECT_EQ(error_of([&] { f(s, out); }), "tangent[w]: must not be null");
    s = in.soa();
    s.normal[1] = nullptr;
    EXPECT_EQ(error_of([&] { f(s, out); }), "normal[y]: must not be null");
    s = in.soa();
    s.texel[2] = nullptr;
    EXPECT_EQ(error_of([&] { f(s, out); }), "texel[2]: must not be null");
    out[0] = nullptr;
    EXPECT_EQ(error_of([&] { f(in.soa(), out); }), "out[x]: must not be null");
    out[0] = got.out(0);
    EXPECT_EQ(error_of([&] { f(in.soa(), nullptr); }), "out: must not be null");
  }
}

}  // namespace normal_map_test
}  // namespace pelt::shading
