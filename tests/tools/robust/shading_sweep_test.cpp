// Stability sweeps of the shading kernels: over ten million random lanes each for shade_skin and
// shade_fur, drawn from the hard ranges (grazing and back-facing angles, g near +-1, Eta near 1
// and below 1, Thickness 0..1e6, zero/tiny/huge normals and tangents, point lights at tiny and
// huge distances). Every output must be finite, non-negative and inside the bound the kernel's
// header documents (skin_reference.h, fur_lighting.h). Runs the dispatched (best) target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "shading/fur_lighting.h"
#include "shading/skin_kernels.h"
#include "shading/skin_reference.h"

namespace pelt::shading {
namespace {

constexpr size_t kLanes = 4096;
constexpr size_t kMinLanes = 10'000'000;
constexpr size_t kBatches = (kMinLanes + kLanes - 1) / kLanes;
// Bounds are checked with this relative slack: the kernels are float, the bounds double.
constexpr double kSlack = 1e-3;

struct Free {
  void operator()(float* p) const { std::free(p); }
};
using Buffer = std::unique_ptr<float[], Free>;
Buffer make_buffer() { return Buffer(static_cast<float*>(std::aligned_alloc(64, kLanes * sizeof(float)))); }

struct Rng {
  std::mt19937_64 gen;
  explicit Rng(uint64_t seed) : gen(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(gen); }
  double log_uniform(double lo_exp, double hi_exp) { return std::pow(10.0, uniform(lo_exp, hi_exp)); }
  void unit(double v[3]) {
    double len2;
    do {
      for (int c = 0; c < 3; ++c) v[c] = uniform(-1.0, 1.0);
      len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (len2 > 1.0 || len2 < 1e-6);
    for (int c = 0; c < 3; ++c) v[c] /= std::sqrt(len2);
  }
  // A unit vector whose cosine with unit `n` is `cos`: grazing, back-facing and exact cases.
  void at_cosine(const double n[3], double cos, double out[3]) {
    double t[3];
    unit(t);
    const double d = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
    for (int c = 0; c < 3; ++c) t[c] -= d * n[c];
    const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    const double s = std::sqrt(std::max(0.0, 1.0 - cos * cos));
    for (int c = 0; c < 3; ++c) out[c] = cos * n[c] + s * t[c] / tl;
  }
  double hard_cosine() {
    static const double kCos[] = {0.0, 1e-7, -1e-7, 1e-3, -1e-3, 1.0, -1.0, 0.9999999, -0.9999999, 0.5, -0.5};
    return pick(3) == 0 ? uniform(-1.0, 1.0) : kCos[pick(int(std::size(kCos)))];
  }
  // A length for a normal or tangent: unit, zero, tiny, denormal or huge.
  double hard_scale() {
    static const double kScale[] = {1.0, 0.0, 1e-20, 1e-40, 1e-16, 1e18, 3.0};
    return pick(2) == 0 ? 1.0 : kScale[pick(int(std::size(kScale)))];
  }
};

// 1-4 lights: directional (any direction), point lights near the batch's first lane (tiny
// distance) or far away (huge distance), ambient. Colours mostly modest, sometimes 1e6.
std::vector<Light> random_lights(Rng& r, const float near_point[3]) {
  std::vector<Light> lights(1 + r.pick(4));
  for (Light& l : lights) {
    l.type = static_cast<Light::Type>(r.pick(3));
    double v[3];
    r.unit(v);
    const double dist = l.type == Light::Type::Point ? (r.pick(2) ? r.log_uniform(-30, -3) : r.log_uniform(3, 7)) : 1.0;
    for (int c = 0; c < 3; ++c) {
      l.vec[c] = l.type == Light::Type::Point ? float(near_point[c] + v[c] * dist) : float(v[c]);
      l.color[c] = r.pick(8) == 0 ? 1e6f : float(r.uniform(0.0, 4.0));
    }
  }
  return lights;
}

struct LightSums {
  double direct[3] = {0, 0, 0}, ambient[3] = {0, 0, 0};
};
LightSums sums(const std::vector<Light>& lights) {
  LightSums s;
  for (const Light& l : lights)
    for (int c = 0; c < 3; ++c) (l.type == Light::Type::Ambient ? s.ambient : s.direct)[c] += l.color[c];
  return s;
}

SkinParams random_skin(Rng& r) {
  SkinParams p;
  for (int c = 0; c < 3; ++c) {
    p.SkinColor[c] = float(r.uniform(0, 1));
    p.SheenColor[c] = float(r.uniform(0, 1));
    p.DiffusionColor[c] = float(r.uniform(0, 1));
    p.normal_blur_mix[c] = float(r.uniform(0, 1));
  }
  p.Opacity = r.pick(4) == 0 ? 1.0f : float(r.uniform(0, 1));
  p.AmbientCoeff = float(r.uniform(0, 1));
  static const float kThick[] = {0.0f, 1e-6f, 0.5f, 1e6f};
  p.Thickness = r.pick(2) ? kThick[r.pick(4)] : float(r.log_uniform(-4, 6));
  static const float kEta[] = {1.0f, 1.0f + 1e-6f, 1.0f - 1e-6f, 0.25f, 4.0f, 0.999f, 1.001f};
  const int e = r.pick(4);
  p.Eta = e == 0 ? kEta[r.pick(7)] : e == 1 ? float(r.uniform(0.25, 1.0)) : e == 2 ? float(r.uniform(0.95, 1.05)) : float(r.uniform(1.0, 4.0));
  static const float kG[] = {1.0f, -1.0f, 0.9999999f, -0.9999999f, 0.999f, -0.999f, 0.0f};
  p.g = r.pick(2) ? kG[r.pick(7)] : float(r.uniform(-1, 1));
  p.SingleScatteringCoeff = float(r.uniform(0, 100));
  p.MultipleScatteringCoeff = float(r.uniform(0, 100));
  p.ClampCoeff = r.pick(3) == 0 ? 0.0f : float(r.uniform(0, 100));
  p.Power = float(r.uniform(1, 256));
  p.Specularity = float(r.uniform(0, 100));
  p.single_scattering = static_cast<SingleScattering>(r.pick(3));
  p.multiple_scattering = static_cast<MultipleScattering>(r.pick(4));
  p.fresnel = static_cast<Fresnel>(r.pick(2));
  p.phase = static_cast<Phase>(r.pick(2));
  p.specular = static_cast<Specular>(r.pick(2));
  return p;
}

// The per-lane bounds of skin_reference.h's shade_skin_pixel, in double.
struct SkinBounds {
  double sebum[3], epidermis[3], dermis[3];  // dermis < 0: finite is all that is promised
  double ambient[3];
};
SkinBounds skin_bounds(const SkinParams& p, const LightSums& s, const double albedo[3]) {
  SkinBounds b;
  const double g = ref::clamp_g(p.g);
  const double pmax = p.phase == Phase::paper ? ref::hg_paper_bound(g) : ref::hg_bound(g);
  const double eta = p.Eta;
  for (int c = 0; c < 3; ++c) {
    const double a = std::clamp(albedo[c], 0.0, 1.0), op = p.Opacity;
    b.sebum[c] = op * p.Specularity * p.SheenColor[c] * s.direct[c];
    const double ms = op * p.DiffusionColor[c] * a * p.MultipleScatteringCoeff;
    switch (p.multiple_scattering) {
      case MultipleScattering::off: b.epidermis[c] = 0; break;
      case MultipleScattering::paper: b.epidermis[c] = ms * (s.direct[c] + s.ambient[c]) / kClampFloor; break;
      default: b.epidermis[c] = ms * s.direct[c]; break;
    }
    const double ss = op * p.SingleScatteringCoeff * p.SkinColor[c] * a * s.direct[c] * pmax;
    switch (p.single_scattering) {
      case SingleScattering::off: b.dermis[c] = 0; break;
      case SingleScattering::correct:  // pi: light units; 1/eta^2: the radiance leaving the layer
        b.dermis[c] = ref::kPi * ss * 2 * (eta + 1 / eta) / (eta * eta);
        break;
      case SingleScattering::paper: b.dermis[c] = eta >= 1 ? ss * eta : -1; break;
    }
    b.ambient[c] = op * p.AmbientCoeff * p.SkinColor[c] * a * s.ambient[c];
  }
  return b;
}

bool within(double v, double bound) { return v <= bound * (1 + kSlack) + 1e-30; }

TEST(ShadingSweep, SkinStaysFiniteAndBounded) {
  Rng r(0x5eed5c1f);
  std::vector<Buffer> in(18), out(13);
  for (auto& b : in) b = make_buffer();
  for (auto& b : out) b = make_buffer();
  SurfaceSoA s{};
  s.n = kLanes;
  ShadeOutSoA o{};
  for (int c = 0; c < 3; ++c) {
    s.pos[c] = in[c].get();
    s.normal[c] = in[3 + c].get();
    s.albedo[c] = in[6 + c].get();
    for (int a = 0; a < 3; ++a) s.blurred_normal[c][a] = in[9 + 3 * c + a].get();
    o.rgb[c] = out[c].get();
    o.sebum[c] = out[4 + c].get();
    o.epidermis[c] = out[7 + c].get();
    o.dermis[c] = out[10 + c].get();
  }
  o.alpha = out[3].get();

  size_t lanes = 0, values = 0, non_finite = 0, negative = 0, out_of_bounds = 0, unbounded_dermis = 0;
  for (size_t batch = 0; batch < kBatches; ++batch) {
    const SkinParams p = random_skin(r);
    ASSERT_FALSE(validate(p).has_value()) << validate(p)->message();
    float eye[3];
    for (float& e : eye) e = float(r.uniform(-10, 10));
    for (size_t i = 0; i < kLanes; ++i) {
      double n[3], v[3];
      r.unit(n);
      r.at_cosine(n, r.hard_cosine(), v);
      const double dist = r.log_uniform(-4, 5), scale = r.hard_scale();
      for (int c = 0; c < 3; ++c) {
        in[c][i] = float(eye[c] - v[c] * dist);
        in[3 + c][i] = float(n[c] * scale);
        in[6 + c][i] = float(r.uniform(-0.25, 1.25));
      }
      for (int ch = 0; ch < 3; ++ch) {
        double b[3];
        r.at_cosine(n, r.uniform(-1, 1), b);
        for (int c = 0; c < 3; ++c) in[9 + 3 * ch + c][i] = float(b[c] * r.hard_scale());
      }
    }
    const float first[3] = {in[0][0], in[1][0], in[2][0]};
    const std::vector<Light> lights = random_lights(r, first);
    ASSERT_FALSE(validate_lights(lights.data(), lights.size()).has_value());
    shade_skin(p, lights.data(), lights.size(), eye, s, o);

    const LightSums ls = sums(lights);
    for (size_t i = 0; i < kLanes; ++i) {
      const double albedo[3] = {in[6][i], in[7][i], in[8][i]};
      const SkinBounds b = skin_bounds(p, ls, albedo);
      bool bad = false;
      for (int k = 0; k < 13; ++k) {
        const float x = out[k][i];
        ++values;
        if (!std::isfinite(x)) ++non_finite, bad = true;
        else if (x < 0.0f) ++negative, bad = true;
      }
      if (std::fabs(out[3][i] - p.Opacity) > 1e-6f) ++out_of_bounds, bad = true;
      for (int c = 0; c < 3; ++c) {
        double total = b.ambient[c] + b.sebum[c] + b.epidermis[c];
        if (!within(out[4 + c][i], b.sebum[c])) ++out_of_bounds, bad = true;
        if (!within(out[7 + c][i], b.epidermis[c])) ++out_of_bounds, bad = true;
        if (b.dermis[c] >= 0) {
          if (!within(out[10 + c][i], b.dermis[c])) ++out_of_bounds, bad = true;
          total += b.dermis[c];
          if (!within(out[c][i], total)) ++out_of_bounds, bad = true;
        } else {
          ++unbounded_dermis;
        }
      }
      if (bad && non_finite + negative + out_of_bounds <= 5)
        ADD_FAILURE() << "batch " << batch << " lane " << i << ": rgb " << out[0][i] << " " << out[1][i] << " "
                      << out[2][i] << " alpha " << out[3][i] << " sebum " << out[4][i] << " epidermis " << out[7][i]
                      << " dermis " << out[10][i] << " (bounds " << b.sebum[0] << " " << b.epidermis[0] << " "
                      << b.dermis[0] << "), Eta " << p.Eta << " g " << p.g << " Thickness " << p.Thickness;
      ++lanes;
    }
  }
  std::printf("shade_skin sweep: %zu lanes in %zu batches, %zu values checked; %zu non-finite, %zu negative, "
              "%zu out of bounds; %zu dermis values bounded only by finiteness (paper, Eta < 1)\n",
              lanes, size_t(kBatches), values, non_finite, negative, out_of_bounds, unbounded_dermis);
  EXPECT_GE(lanes, kMinLanes);
  EXPECT_EQ(non_finite, 0u);
  EXPECT_EQ(negative, 0u);
  EXPECT_EQ(out_of_bounds, 0u);
}

TEST(ShadingSweep, FurStaysFiniteAndBounded) {
  Rng r(0xf0f0beef);
  std::vector<Buffer> in(14), out(4);
  for (auto& b : in) b = make_buffer();
  for (auto& b : out) b = make_buffer();
  FurSurfaceSoA s{};
  s.n = kLanes;
  for (int c = 0; c < 3; ++c) {
    s.pos[c] = in[c].get();
    s.tangent[c] = in[3 + c].get();
    s.normal[c] = in[6 + c].get();
  }
  s.height = in[9].get();
  for (int c = 0; c < 4; ++c) s.texel[c] = in[10 + c].get();
  FurOutSoA o{};
  for (int c = 0; c < 4; ++c) o.rgba[c] = out[c].get();

  size_t lanes = 0, values = 0, non_finite = 0, negative = 0, out_of_bounds = 0;
  for (size_t batch = 0; batch < kBatches; ++batch) {
    FurLightParams p;
    p.ambient_occlusion_root = float(r.uniform(0, 1));
    p.diffuse = r.pick(4) == 0 ? 100.0f : float(r.uniform(0, 100));
    p.specular = r.pick(4) == 0 ? 100.0f : float(r.uniform(0, 100));
    static const float kShine[] = {1.0f, 2.0f, 3.0f, 40.0f, 511.0f, 512.0f, 7.5f};
    p.shininess = r.pick(2) ? kShine[r.pick(7)] : float(r.uniform(1, 512));
    p.backlight_wrap = float(r.uniform(0, 1));
    ASSERT_FALSE(validate(p).has_value()) << validate(p)->message();
    float eye[3];
    for (float& e : eye) e = float(r.uniform(-10, 10));
    for (size_t i = 0; i < kLanes; ++i) {
      double n[3], v[3], t[3];
      r.unit(n);
      r.at_cosine(n, r.hard_cosine(), v);
      r.at_cosine(v, r.hard_cosine(), t);  // strands along, across and against the view
      const double dist = r.pick(16) == 0 ? 0.0 : r.log_uniform(-4, 5);
      const double ns = r.hard_scale(), ts = r.hard_scale();
      for (int c = 0; c < 3; ++c) {
        in[c][i] = float(eye[c] - v[c] * dist);
        in[3 + c][i] = float(t[c] * ts);
        in[6 + c][i] = float(n[c] * ns);
      }
      in[9][i] = float(r.uniform(-0.5, 1.5));
      for (int c = 0; c < 4; ++c) in[10 + c][i] = float(r.uniform(-0.25, 1.25));
    }
    const float first[3] = {in[0][0], in[1][0], in[2][0]};
    const std::vector<Light> lights = random_lights(r, first);
    shade_fur(p, lights.data(), lights.size(), eye, s, o);

    const LightSums ls = sums(lights);
    for (size_t i = 0; i < kLanes; ++i) {
      bool bad = false;
      for (int c = 0; c < 4; ++c) {
        const float x = out[c][i];
        ++values;
        if (!std::isfinite(x)) ++non_finite, bad = true;
        else if (x < 0.0f) ++negative, bad = true;
      }
      // ao <= 1, sin <= 1, wrap term <= 1, texels clamped to [0, 1].
      for (int c = 0; c < 3; ++c)
        if (!within(out[c][i], ls.ambient[c] + (p.diffuse + p.specular) * ls.direct[c])) ++out_of_bounds, bad = true;
      if (out[3][i] != std::clamp(in[13][i], 0.0f, 1.0f)) ++out_of_bounds, bad = true;
      if (bad && non_finite + negative + out_of_bounds <= 5)
        ADD_FAILURE() << "batch " << batch << " lane " << i << ": rgba " << out[0][i] << " " << out[1][i] << " "
                      << out[2][i] << " " << out[3][i];
      ++lanes;
    }
  }
  std::printf("shade_fur sweep: %zu lanes in %zu batches, %zu values checked; %zu non-finite, %zu negative, "
              "%zu out of bounds\n", lanes, size_t(kBatches), values, non_finite, negative, out_of_bounds);
  EXPECT_GE(lanes, kMinLanes);
  EXPECT_EQ(non_finite, 0u);
  EXPECT_EQ(negative, 0u);
  EXPECT_EQ(out_of_bounds, 0u);
}

}  // namespace
}  // namespace pelt::shading
