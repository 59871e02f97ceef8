// Physically based reference for the epidermis (multiple scattering): Jensen et al. 2001, "A
// Practical Model for Subsurface Light Transport", dipole diffusion approximation.
//
// Slow and exact by construction; used to measure how far the paper's fake and the normal-blur
// fake are from a diffusion solution (the trade-off work), not at render time.
#pragma once

#include <cstddef>
#include <optional>

#include "shading/skin_params.h"

namespace pelt::shading::diffusion {

// Optical properties of one colour channel, in 1 / scene units.
struct Medium {
  double sigma_a;        // absorption coefficient, > 0
  double sigma_s_prime;  // reduced scattering coefficient, >= 0
  double eta;            // relative index of refraction, in [0.25, 4]
};

std::optional<ParamError> validate(const Medium& m);

// Internal diffuse reflection parameter A = (1 + F_dr) / (1 - F_dr), with Egan and Hilgeman's
// fit F_dr = -1.440 / eta^2 + 0.710 / eta + 0.668 + 0.0636 eta, clamped to [0, 0.99] (the fit
// turns negative for eta below about 1).
double internal_reflection_A(double eta);

// Diffuse reflectance profile R_d(r) (exitance per unit incident flux at distance r from the
// point of incidence, 1 / area):
//   alpha' / (4 pi) [z_r (sigma_tr d_r + 1) e^{-sigma_tr d_r} / d_r^3
//                    + z_v (sigma_tr d_v + 1) e^{-sigma_tr d_v} / d_v^3]
// with sigma_t' = sigma_a + sigma_s', alpha' = sigma_s' / sigma_t', sigma_tr = sqrt(3 sigma_a
// sigma_t'), z_r = 1 / sigma_t', z_v = z_r (1 + 4 A / 3), d = sqrt(r^2 + z^2).
double profile(double r, const Medium& m);

// Total diffuse reflectance, the integral of 2 pi r R_d(r) over r, in closed form:
//   (alpha' / 2) (1 + exp(-4/3 A sqrt(3 (1 - alpha')))) exp(-sqrt(3 (1 - alpha'))).
// Bound: 0 <= Rd <= alpha'.
double total_reflectance(double alpha_prime, double eta);

// Radiant exitance at `point` from irradiance E_i on surface samples (position, area):
// M = sum_i R_d(|point - x_i|) E_i A_i. The samples should cover the surface around the point out
// to several 1 / sigma_tr, each with the irradiance transmitted into the surface (the caller
// applies the entry Fresnel factor, and the exit one to M).
double exitance(const Medium& m, const double point[3], const float* positions_xyz, const float* areas,
                const float* irradiance, size_t count);

}  // namespace pelt::shading::diffusion
