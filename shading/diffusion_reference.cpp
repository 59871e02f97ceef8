#include "shading/diffusion_reference.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace pelt::shading::diffusion {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::optional<ParamError> validate(const Medium& m) {
  if (!std::isfinite(m.sigma_a) || !(m.sigma_a > 0.0)) return ParamError{"sigma_a", "must be finite and > 0"};
  if (!std::isfinite(m.sigma_s_prime) || m.sigma_s_prime < 0.0)
    return ParamError{"sigma_s_prime", "must be finite and >= 0"};
  if (!std::isfinite(m.eta) || m.eta < 0.25 || m.eta > 4.0) return ParamError{"eta", "must be in [0.25, 4]"};
  return std::nullopt;
}

double internal_reflection_A(double eta) {
  const double fdr = std::clamp(-1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta, 0.0, 0.99);
  return (1.0 + fdr) / (1.0 - fdr);
}

double profile(double r, const Medium& m) {
  const double st = m.sigma_a + m.sigma_s_prime;
  const double alpha = m.sigma_s_prime / st;
  const double str = std::sqrt(3.0 * m.sigma_a * st);
  const double zr = 1.0 / st;
  const double zv = zr * (1.0 + 4.0 / 3.0 * internal_reflection_A(m.eta));
  const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
  const double real = zr * (str * dr + 1.0) * std::exp(-str * dr) / (dr * dr * dr);
  const double virt = zv * (str * dv + 1.0) * std::exp(-str * dv) / (dv * dv * dv);
  return alpha / (4.0 * kPi) * (real + virt);
}

double total_reflectance(double alpha_prime, double eta) {
  const double a = std::clamp(alpha_prime, 0.0, 1.0);
  const double s = std::sqrt(3.0 * (1.0 - a));
  return 0.5 * a * (1.0 + std::exp(-4.0 / 3.0 * internal_reflection_A(eta) * s)) * std::exp(-s);
}

double exitance(const Medium& m, const double point[3], const float* positions_xyz, const float* areas,
                const float* irradiance, size_t count) {
  double sum = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const double dx = point[0] - positions_xyz[3 * i], dy = point[1] - positions_xyz[3 * i + 1],
                 dz = point[2] - positions_xyz[3 * i + 2];
    sum += profile(std::sqrt(dx * dx + dy * dy + dz * dz), m) * double(irradiance[i]) * double(areas[i]);
  }
  return sum;
}

}  // namespace pelt::shading::diffusion
