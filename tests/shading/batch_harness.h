// Test helper: owns 64-byte aligned SoA buffers for the shading kernels and compares kernel
// outputs with the double-precision reference for every compiled Highway target.
#pragma once

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shading/surface.h"

namespace pelt::shading::testing {

struct AlignedFree {
  void operator()(float* p) const { std::free(p); }
};
using Buffer = std::unique_ptr<float[], AlignedFree>;

inline Buffer make_buffer(size_t n) {
  const size_t bytes = ((n * sizeof(float) + 63) / 64) * 64;
  auto* p = static_cast<float*>(std::aligned_alloc(64, bytes == 0 ? 64 : bytes));
  for (size_t i = 0; i < n; ++i) p[i] = 0.0f;
  return Buffer(p);
}

// Inputs: pos, normal, albedo (3 each) and blurred normals (9).
struct Inputs {
  size_t n;
  std::vector<Buffer> in;  // 18 arrays
  explicit Inputs(size_t n_) : n(n_) {
    for (int k = 0; k < 18; ++k) in.push_back(make_buffer(n));
  }
  float* pos(int c) { return in[c].get(); }
  float* normal(int c) { return in[3 + c].get(); }
  float* albedo(int c) { return in[6 + c].get(); }
  float* blurred(int ch, int c) { return in[9 + 3 * ch + c].get(); }
  SurfaceSoA soa() {
    SurfaceSoA s{};
    s.n = n;
    for (int c = 0; c < 3; ++c) {
      s.pos[c] = pos(c);
      s.normal[c] = normal(c);
      s.albedo[c] = albedo(c);
      for (int a = 0; a < 3; ++a) s.blurred_normal[c][a] = blurred(c, a);
    }
    return s;
  }
};

// Outputs: rgb, alpha, sebum, epidermis, dermis (13 arrays).
struct Outputs {
  size_t n;
  std::vector<Buffer> out;
  explicit Outputs(size_t n_) : n(n_) {
    for (int k = 0; k < 13; ++k) out.push_back(make_buffer(n));
  }
  ShadeOutSoA soa() {
    ShadeOutSoA o{};
    for (int c = 0; c < 3; ++c) {
      o.rgb[c] = out[c].get();
      o.sebum[c] = out[4 + c].get();
      o.epidermis[c] = out[7 + c].get();
      o.dermis[c] = out[10 + c].get();
    }
    o.alpha = out[3].get();
    return o;
  }
  float at(int k, size_t i) const { return out[k][i]; }
};

// Outputs that passed only by the jitter criterion, summed over the process (printed by tests).
inline size_t& total_conditioned() {
  static size_t count = 0;
  return count;
}

inline const char* output_name(int k) {
  static const char* names[13] = {"rgb.r",       "rgb.g",       "rgb.b",       "alpha",    "sebum.r",
                                  "sebum.g",     "sebum.b",     "epidermis.r", "epidermis.g", "epidermis.b",
                                  "dermis.r",    "dermis.g",    "dermis.b"};
  return names[k];
}

// The tolerance: relative 1e-4 where the reference is >= 1e-3, absolute 1e-6 below.
inline bool close_enough(double ref, double got) {
  if (std::fabs(ref) >= 1e-3) return std::fabs(got - ref) <= 1e-4 * std::fabs(ref);
  return std::fabs(got - ref) <= 1e-6;
}

// The reference output k of lane i re-evaluated with its float inputs (positions, normals, eye,
// light vectors) jittered by a few ulps; `trial` selects the jitter.
using Jittered = std::function<double(size_t lane, int output, int trial)>;

inline constexpr int kJitterTrials = 24;
// Fraction of outputs allowed to need the jitter criterion (see below).
inline constexpr double kMaxJitteredFraction = 1e-3;

// Runs `body` once per compiled target this CPU supports, with dispatch forced to it (reset to
// the best target afterwards).
inline void for_each_target(const std::function<void(int64_t)>& body) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (int64_t t : targets) {
    hwy::SetSupportedTargetsForTest(t);
    SCOPED_TRACE(std::string("target ") + hwy::TargetName(t));
    body(t);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Runs `kernel` for every compiled and supported target and checks each output against `ref`:
// finite, non-negative, and within the tolerance (close_enough). Where a float kernel
// cannot meet that tolerance because the output is ill-conditioned in its inputs (near the
// critical angle for Eta < 1, in efresnel's steep ramp, at a strongly peaked phase lobe), the
// value passes if it lies within the tolerance of the range of the reference evaluated on inputs
// jittered by a few float ulps (a backward-error criterion). Such outputs are counted and must
// stay below kMaxJitteredFraction. Reports at most a few mismatches per target.
inline void expect_matches_reference_all_targets(const Outputs& ref, size_t n,
                                                 const std::function<void(Outputs&)>& kernel,
                                                 int outputs = 13,
                                                 const std::function<std::string(size_t)>& describe = {},
                                                 const Jittered& jittered = {}) {
  for_each_target([&](int64_t t) {
    Outputs got(n);
    kernel(got);
    int reported = 0;
    size_t bad = 0, conditioned = 0;
    for (int k = 0; k < outputs; ++k)
      for (size_t i = 0; i < n; ++i) {
        const double r = ref.at(k, i), g = got.at(k, i);
        bool ok = std::isfinite(g) && g >= 0.0 && close_enough(r, g);
        if (!ok && jittered && std::isfinite(g) && g >= 0.0) {
          double lo = r, hi = r;
          for (int trial = 0; trial < kJitterTrials; ++trial) {
            const double rj = jittered(i, k, trial);
            lo = std::min(lo, rj);
            hi = std::max(hi, rj);
          }
          ok = (g >= lo && g <= hi) || close_enough(lo, g) || close_enough(hi, g);
          if (ok) ++conditioned;
        }
        if (!ok) {
          ++bad;
          if (reported++ < 5) {
            std::string where;
            if (describe) where = describe(i);
            ADD_FAILURE() << "target " << hwy::TargetName(t) << " lane " << i << " " << output_name(k)
                          << ": kernel " << g << " reference " << r << " " << where;
          }
        }
      }
    EXPECT_EQ(bad, 0u) << "target " << hwy::TargetName(t);
    EXPECT_LE(double(conditioned), kMaxJitteredFraction * double(n) * outputs)
        << "target " << hwy::TargetName(t) << ": too many outputs needed the jitter criterion";
    total_conditioned() += conditioned;
  });
}

}  // namespace pelt::shading::testing
