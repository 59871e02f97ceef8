// Double-precision scalar reference of every term of the skin shader and of the basic materials.
//
// This is the ground truth the SIMD kernels (skin_kernels.h) are tested against; it is written
// for clarity, not speed. Conventions: all cosines are with respect to the shading normal after
// it is turned toward the viewer; eta is the relative index inside / outside (SkinParams::Eta);
// light colours are irradiance-like (a white Lambert surface facing a light of colour 1 returns
// 1: no 1/pi). Deviations from the paper's listings are marked DEVIATION and collected in
// the README (section "Skin shader: deviations from the paper's listings").
#pragma once

#include <cstddef>

#include "shading/basic_params.h"
#include "shading/light.h"
#include "shading/skin_params.h"
#include "shading/surface.h"

namespace pelt::shading::ref {

inline constexpr double kPi = 3.14159265358979323846;

// Cosine of the refracted angle for an incident cosine cos_i in [0, 1]; false on total internal
// reflection. Computed as sqrt((cos_i^2 + (eta - 1)(eta + 1)) / eta^2), exact at eta = 1.
bool refract_cos(double cos_i, double eta, double& cos_t);

// Unpolarised dielectric Fresnel reflectance, (r_s^2 + r_p^2) / 2, 1 on total internal
// reflection. Bound: 0 <= F <= 1. At cos_i = 0 it is 1 (grazing).
double fresnel_exact(double cos_i, double eta);

// Pharr's efresnel boost: smoothstep(0, 0.5, Kr). Bound: 0 <= result <= 1.
double efresnel(double Kr);

// The paper's `fresnel` listing, literally: rParallel is identically 1 and the two squared terms
// are subtracted, so Kr = (1 - rPerp^2) / 2 with rPerp = (eta cos_i + cos_t) / (eta cos_i -
// cos_t) = 1 / r_p. Since |rPerp| >= 1 this is <= 0 everywhere and -infinity at Brewster's angle
// (r_p = 0); on total internal reflection the listing's T is zero and Kr = 0. Not used for
// shading; kept to document the bug (efresnel of it is 0, i.e. Kt = 1 everywhere).
double fresnel_paper(double cos_i, double eta);

// |g| is clamped to kMaxAbsG before use: at g = +-1 Henyey-Greenstein is a delta, not a function.
double clamp_g(double g);

// Henyey-Greenstein, (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5), cos of the scattering angle
// between propagation directions. The base is evaluated as (1-|g|)^2 + 2|g|(1 - sign(g) cos),
// which keeps its precision near the peak. Bound: p <= hg_bound(g) = (1+|g|) / (4 pi (1-|g|)^2),
// finite for the clamped g. Integrates to 1 over the sphere.
double hg_phase(double cos_theta, double g);
double hg_bound(double g);

// The paper's listing: (1 - g^2) / (1 - g^2 - 2 g cos)^1.5 (minus g^2 in the base, no 1/(4 pi)).
// Its base is negative for cos > (1 - g^2) / (2g) (a NaN in the listing); DEVIATION: the base is
// floored at the correct base's minimum (1-|g|)^2, so the result is finite and shares the bound
// hg_paper_bound(g) = (1+|g|) / (1-|g|)^2.
double hg_phase_paper(double cos_theta, double g);
double hg_paper_bound(double g);

// Hanrahan-Krueger single scattering with refracted cosines ci, co (> 0 or 0) and phase value p:
// a p (1 - exp(-d (1/ci + 1/co))) / (ci + co). Guards: 1/ci and 1/co use max(c, 1e-20) and the
// denominator max(ci + co, 1e-20), so a grazing refracted ray gives a large but finite value that
// the Fresnel transmission (0 there) multiplies away. Bound: <= a p min(1/(ci+co), d/(ci co)).
double single_scattering(double ci, double co, double p, double albedo, double thickness);

// The paper's epidermis fake without colour: I_ms / (|I.N| + l_c). DEVIATION: the denominator is
// floored at kClampFloor (ClampCoeff = 0 with I.N = 0 divides by zero in the paper). Bound:
// <= I_ms / kClampFloor.
double epidermis_fake(double cos_o, double ms_coeff, double clamp_coeff);

// Dipole total diffuse reflectance (Jensen et al. 2001), reduced albedo alpha in [0, 1]; see
// diffusion_reference.h. Bound: 0 <= Rd <= alpha.
double dipole_total_rd(double alpha, double eta);

// s^power for s clamped to [0, 1]; 0 for s <= 0. Bound: [0, 1].
double specular_lobe(double s, double power);

// Per-pixel inputs and outputs of the reference shaders.
struct Sample {
  double pos[3];
  double normal[3];
  double albedo[3];
  double blurred_normal[3][3];  // used by normal_blur only
};
struct Shaded {
  double rgb[3];
  double alpha;
  double sebum[3];
  double epidermis[3];
  double dermis[3];
};

// The per-pixel, per-light sum. Preconditions: validate(p) and validate_lights passed.
// Per channel, with Op = Opacity, A = albedo clamped to [0, 1], sum(Cl) over the non-ambient
// lights (sum over all lights for the paper's fake):
//   sebum     <= Op Specularity SheenColor sum(Cl)
//   epidermis <= Op DiffusionColor A I_ms sum(Cl) / kClampFloor  (paper fake)
//             <= Op DiffusionColor A I_ms sum(Cl)                (normal_blur, reference)
//   dermis    <= pi Op SSC SkinColor A sum(Cl) p_max 2 (eta + 1/eta) / eta^2 (correct: pi for the
//                light units, 1/eta^2 for the radiance leaving the layer, and cos_i Kt_in / ci_t is
//                at most 2 (eta + 1/eta)); <= Op SSC SkinColor A
//                sum(Cl) p_max eta for the paper's Kt = 1 with eta >= 1 (the listing's units: no
//                pi); for eta < 1 the paper's term is only finite.
//   rgb = Op AmbientCoeff SkinColor A sum(ambient Cl) + sebum + epidermis + dermis; alpha = Op.
// Every output is finite and >= 0.
Shaded shade_skin_pixel(const SkinParams& p, const Light* lights, size_t light_count, const double eye[3],
                        const Sample& s);
Shaded shade_unlit_pixel(const Sample& s);
Shaded shade_lambert_pixel(const Light* lights, size_t light_count, const double eye[3], const Sample& s);
Shaded shade_blinn_pixel(const BasicParams& p, const Light* lights, size_t light_count, const double eye[3],
                         const Sample& s);

}  // namespace pelt::shading::ref
