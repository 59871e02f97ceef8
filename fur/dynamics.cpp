#include "fur/dynamics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace pelt::fur {
namespace {

// FurParams::shells is at most 128 (validate), so a chain fits on the stack.
constexpr uint32_t kMaxChain = 128;

// Below this a cross product is treated as zero: the axis would be noise.
constexpr double kParallelSin = 1e-7;

// Rodrigues rotation of r about the unit axis a.
glm::dvec3 rotate(const glm::dvec3& r, const glm::dvec3& a, double c, double s) {
  return r * c + glm::cross(a, r) * s + a * (glm::dot(a, r) * (1.0 - c));
}

// Unit vector or zero (for zero, tiny or non-finite input).
glm::dvec3 unit_or_zero(const glm::dvec3& v) {
  const double len = glm::length(v);
  if (!(len > 1e-30) || !std::isfinite(len)) return glm::dvec3(0.0);
  return v / len;
}

// A unit vector perpendicular to the unit vector n.
glm::dvec3 any_perpendicular(const glm::dvec3& n) {
  const glm::dvec3 away = std::fabs(n.x) < 0.5 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(n, away));
}

// Keeps segment k of a chain of S nodes at least kMinFurElevation above the tangent plane of
// the unit surface normal n (fur/fur_geometry.h): a lower segment is raised along its heading,
// nodes k+1..S-1 turning rigidly about node k (lengths kept). A segment high enough, of zero
// length, or with no normal known (n = 0) is left alone, bit for bit. Called per node, in
// root-to-tip order, after that node's bend.
void keep_above_surface(std::span<glm::dvec3> p, uint32_t k, uint32_t S, const glm::dvec3& n) {
  const glm::dvec3 d = unit_or_zero(p[k + 1] - p[k]);
  if (d == glm::dvec3(0.0) || n == glm::dvec3(0.0)) return;
  const double e = glm::dot(d, n);
  if (e >= std::sin(kMinFurElevation)) return;
  // Turning about d x n raises d toward n along its heading; straight into the surface it has
  // none, and any axis in the tangent plane does.
  glm::dvec3 axis = glm::cross(d, n);
  const double cos_e = glm::length(axis);
  axis = cos_e > kParallelSin ? axis / cos_e : any_perpendicular(n);
  const double raise = kMinFurElevation - std::atan2(e, cos_e);
  const double c = std::cos(raise), s = std::sin(raise);
  for (uint32_t j = k + 1; j < S; ++j) p[j] = p[k] + rotate(p[j] - p[k], axis, c, s);
}

// Strength as apply_gravity reads it: non-finite or negative is none.
double gravity_strength(const GravityParams& gravity) {
  return std::isfinite(gravity.strength) ? std::max(0.0, double(gravity.strength)) : 0.0;
}

}  // namespace

bool gravity_bends(const GravityParams& gravity) {
  // Infinitely stiff fur, no gravity or no strength: theta would be 0 (or 0 * inf).
  const double stability = double(gravity.stability);
  return unit_or_zero(glm::dvec3(gravity.direction)) != glm::dvec3(0.0) && gravity_strength(gravity) != 0.0 &&
         !(std::isinf(stability) && stability > 0.0);
}

void apply_gravity(std::span<const glm::vec3> rest, std::span<const glm::vec3> surface_normals,
                   uint32_t base_vertex_count, uint32_t layers, uint32_t authored_layers,
                   const GravityParams& gravity, GravityLaw law, std::span<glm::vec3> out, uint32_t begin,
                   uint32_t end) {
  const size_t N = base_vertex_count;
  const uint32_t S = std::min(layers, kMaxChain);
  const uint32_t A = std::min(authored_layers, kMaxChain);
  // Sum of RN over a chain of n nodes: n (n - 1) / 2; the ratio keeps the authored total.
  const double rn_scale = A >= 2 && A != S && S >= 2 ? double(A) * double(A - 1) / (double(S) * double(S - 1)) : 1.0;
  const glm::dvec3 G = unit_or_zero(glm::dvec3(gravity.direction));
  const double strength = gravity_strength(gravity);
  const double stability = double(gravity.stability);
  const bool no_force = !gravity_bends(gravity);
  std::array<glm::dvec3, kMaxChain> p;
  // Eq. 2 at node k: turns nodes k+1..S-1 about it toward G.
  auto bend_toward_gravity = [&](uint32_t k) {
    const glm::dvec3 V = unit_or_zero(p[k + 1] - p[k]);
    glm::dvec3 axis = glm::cross(V, G);
    const double sin_a = glm::length(axis);
    if (!(sin_a > kParallelSin)) return;  // along or against G (or a zero segment)
    axis /= sin_a;
    const double cos_a = glm::dot(V, G);
    const double to_g = std::atan2(sin_a, cos_a);  // angle from V to G, (0, pi)
    const double factor = law == GravityLaw::lever ? sin_a : cos_a;
    const double rn = double(S - 1 - k) * rn_scale;
    double theta;
    if (stability > 0.0) {
      theta = strength * factor * rn / stability;
    } else {  // zero or negative stability: no restoring force at all
      theta = factor > 0.0 ? to_g : 0.0;
    }
    if (!std::isfinite(theta)) theta = factor > 0.0 ? to_g : 0.0;
    theta = std::clamp(theta, 0.0, to_g);
    if (theta == 0.0) return;
    const double c = std::cos(theta), s = std::sin(theta);
    for (uint32_t j = k + 1; j < S; ++j) p[j] = p[k] + rotate(p[j] - p[k], axis, c, s);
  };
  for (uint32_t i = begin; i < end; ++i) {
    for (uint32_t k = 0; k < S; ++k) p[k] = glm::dvec3(rest[i + k * N]);
    if (!no_force) {
      const glm::dvec3 n = unit_or_zero(glm::dvec3(surface_normals[i]));
      for (uint32_t k = 0; k + 1 < S; ++k) {
        bend_toward_gravity(k);
        keep_above_surface(p, k, S, n);
      }
    }
    for (uint32_t k = 0; k < S; ++k) out[i + k * N] = glm::vec3(p[k]);
    for (uint32_t k = S; k < layers; ++k) out[i + k * N] = rest[i + k * N];
  }
}

WindField make_wind_field(const FurGeometry& geometry, const WindParams& wind) {
  WindField f;
  update_wind_field(geometry, wind, f);
  return f;
}

void update_wind_field(const FurGeometry& geometry, const WindParams& wind, WindField& f) {
  const glm::dvec3 d = unit_or_zero(glm::dvec3(wind.direction));
  const glm::vec3 direction = d == glm::dvec3(0.0) ? glm::vec3(0.0f) : glm::vec3(d);
  f.strength = std::isfinite(wind.strength) ? wind.strength : 0.0f;
  f.gust_frequency = std::isfinite(wind.gust_frequency) ? wind.gust_frequency : 0.0f;
  f.gust_scale = std::isfinite(wind.gust_scale) ? std::clamp(wind.gust_scale, 0.0f, 1.0f) : 0.0f;
  const size_t N = geometry.base_vertex_count;
  // Keyed on the direction as given, from which the phases are computed bit for bit: two inputs
  // whose unit vectors round to the same float would otherwise share phases made from either,
  // and a frame drawn alone could differ from the same frame in a sequence.
  if (f.phase.size() == N && f.phase_input == wind.direction) return;
  f.direction = direction;
  f.phase_input = wind.direction;
  const double L = geometry.bounds.radius > 0.0f ? 2.0 * double(geometry.bounds.radius) : 1.0;
  f.phase.resize(N);
  for (size_t i = 0; i < N; ++i) {
    const glm::dvec3 q = glm::dvec3(geometry.positions[i]) - glm::dvec3(geometry.bounds.centre);
    f.phase[i] = float(glm::dot(q, d) / L);
  }
}

void WindField::forces(double time_seconds, std::span<glm::vec3> out, uint32_t begin,
                       uint32_t end) const {
  // Only the fractional part of the temporal phase matters; keeping it small keeps the
  // float sine accurate after hours of animation.
  double cycles = double(gust_frequency) * time_seconds;
  cycles -= std::floor(cycles);
  if (!std::isfinite(cycles)) cycles = 0.0;
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  for (uint32_t i = begin; i < end; ++i) {
    const float g = 1.0f + gust_scale * std::sin(two_pi * (float(cycles) - phase[i]));
    out[i] = direction * (strength * g);
  }
}

void apply_wind(std::span<const glm::vec3> pose, std::span<const glm::vec3> normals,
                std::span<const glm::vec3> surface_normals, std::span<const glm::vec3> forces,
                uint32_t base_vertex_count, uint32_t layers, std::span<glm::vec3> out, uint32_t begin,
                uint32_t end) {
  const size_t N = base_vertex_count;
  const uint32_t S = std::min(layers, kMaxChain);
  std::array<glm::dvec3, kMaxChain> p;
  for (uint32_t i = begin; i < end; ++i) {
    const glm::dvec3 F(forces[i]);
    const double m = glm::length(F);
    const glm::dvec3 n = unit_or_zero(glm::dvec3(normals[i]));
    glm::dvec3 axis(0.0);
    double sin_a = 0.0, cos_a = 1.0;
    if (m > 0.0 && std::isfinite(m)) {
      const glm::dvec3 f = F / m;
      axis = glm::cross(n, f);
      sin_a = glm::length(axis);
      cos_a = glm::dot(n, f);
    }
    if (!(sin_a > kParallelSin)) {
      if (out.data() != pose.data()) {
        for (uint32_t k = 0; k < layers; ++k) out[i + k * N] = pose[i + k * N];
      }
      continue;
    }
    axis /= sin_a;
    const double phi = std::atan2(sin_a, cos_a);
    const double theta = phi * (1.0 - std::exp(-m));
    const double c = std::cos(theta), s = std::sin(theta);
    const glm::dvec3 root(pose[i]);
    for (uint32_t k = 0; k < S; ++k) p[k] = root + rotate(glm::dvec3(pose[i + k * N]) - root, axis, c, s);
    const glm::dvec3 surface = unit_or_zero(glm::dvec3(surface_normals[i]));
    for (uint32_t k = 0; k + 1 < S; ++k) keep_above_surface(p, k, S, surface);
    out[i] = pose[i];
    for (uint32_t k = 1; k < S; ++k) out[i + k * N] = glm::vec3(p[k]);
    for (uint32_t k = S; k < layers; ++k) {
      const size_t I = i + k * N;
      out[I] = glm::vec3(root + rotate(glm::dvec3(pose[I]) - root, axis, c, s));
    }
  }
}

void lerp_poses(std::span<const glm::vec3> a, std::span<const glm::vec3> b, float t,
                std::span<glm::vec3> out, size_t begin, size_t end) {
  // a*(1-t) + b*t is exact at both ends (a + (b-a)*t is not at t = 1 in floats). A coordinate
  // equal in both poses is copied: a*(1-t) + a*t can be an ulp off a, and the roots (layer 0,
  // never moved by gravity or wind) must stay bit for bit on the base mesh, or shell 0 fails its
  // less-equal depth test against the base in stripes where the rounding goes outward.
  const float u = 1.0f - t;
  auto mix = [&](float x, float y) { return x == y ? x : x * u + y * t; };
  for (size_t I = begin; I < end; ++I)
    out[I] = glm::vec3(mix(a[I].x, b[I].x), mix(a[I].y, b[I].y), mix(a[I].z, b[I].z));
}

float animation_t(double x, double period) {
  if (!(period > 0.0) || !std::isfinite(period) || !std::isfinite(x)) return 0.0f;
  double cycles = x / period;
  cycles -= std::floor(cycles);
  return float(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * cycles));
}

void strand_tangents(std::span<const glm::vec3> pose, std::span<const glm::vec3> growth,
                     uint32_t base_vertex_count, uint32_t layers, std::span<glm::vec3> out,
                     uint32_t begin, uint32_t end) {
  const size_t N = base_vertex_count;
  for (uint32_t i = begin; i < end; ++i) {
    for (uint32_t k = 0; k < layers; ++k) {
      const uint32_t lo = k == 0 ? 0 : k - 1;
      const uint32_t hi = k + 1 < layers ? k + 1 : k;
      const glm::vec3 d = pose[i + hi * N] - pose[i + lo * N];
      const float len = glm::length(d);
      out[i + k * N] = (len > 1e-20f && std::isfinite(len)) ? d / len : growth[i];
    }
  }
}

void llvmpipe_poses(const FurGeometry& geometry, std::span<glm::vec3> p0, std::span<glm::vec3> p1) {
  // The harness's float expressions, in its order.
  const uint32_t N = geometry.base_vertex_count, S = geometry.layers;
  const float R = geometry.bounds.radius;
  const float fur_len = geometry.fur_length;
  const glm::vec3 g(0.0f, -1.0f, 0.0f);
  const glm::vec3 w = glm::normalize(glm::vec3(1.0f, 0.2f, 0.6f));
  auto tang = [](const glm::vec3& a, const glm::vec3& n) { return a - n * glm::dot(a, n); };
  for (uint32_t s = 0; s < S; ++s) {
    const float f = float(s) / float(S - 1);
    const float bend = f * f * fur_len;
    for (uint32_t i = 0; i < N; ++i) {
      const size_t I = i + size_t(s) * N;
      const glm::vec3 n = geometry.base_normals[i];
      const glm::vec3 q = geometry.positions[i] - geometry.bounds.centre;
      const glm::vec3 shell = geometry.positions[I];
      p0[I] = shell + tang(g, n) * (0.4f * bend);
      const float gust = 0.75f + 0.25f * std::sin(3.0f * (q.x + q.z) / R);
      p1[I] = shell + tang(w, n) * (0.8f * bend * gust);
    }
  }
}

float llvmpipe_animation_t(int frame) { return 0.5f + 0.5f * std::sin(0.1f * float(frame)); }

}  // namespace pelt::fur
