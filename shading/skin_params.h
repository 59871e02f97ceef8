// The parameters of the layered skin shader (sebum, epidermis, dermis) and its model switches.
//
// Member names are the paper's (Yoo, Lee, Jahng 2004, section 3.3) and double as the JSON keys of
// the scene's `skin` material, so an error message names the key the user wrote. Section 3.3 lists
// the parameters without values; only g = 0.8 (from Hanrahan-Krueger, quoted in 3.1) and Eta = 1.4
// (3.3) are given. The other defaults follow Pharr's "Layered Media for Surface Shaders" skin shader
// (the paper's source: Ka = 0.5, sheen colour white, thickness 0.5) or were chosen for the head
// scan in shared/data; each is marked below.
//
// Units: colours are linear RGB; Thickness is in mean free paths (optical depth), not scene units;
// normal_blur_radius is in scene units.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pelt::shading {

// Dermis (single scattering).
enum class SingleScattering : uint32_t {
  off,
  paper,    // the paper's listing: its Fresnel (rParallel == 1, terms subtracted) through efresnel
  correct,  // Hanrahan-Krueger with exact (or efresnel) Fresnel transmission in and out
};
// Epidermis (multiple scattering).
enum class MultipleScattering : uint32_t {
  off,
  paper,        // C_ms = C_d * I_ms / (|I.N| + l_c), per light, no cosine (the paper's fake)
  normal_blur,  // per channel mix of max(0, N.L) and max(0, N_blur.L) (Normal Blur SSS)
  reference,    // dipole total diffuse reflectance times the local irradiance (flat-surface limit
                // of diffusion_reference; the full mesh integral is diffusion_reference.h)
};
enum class Fresnel : uint32_t { exact, efresnel };  // efresnel: Kr = smoothstep(0, 0.5, Kr)
enum class Phase : uint32_t { correct, paper };      // paper: 1 - g^2 - 2g cos in the denominator
enum class Specular : uint32_t { phong, blinn };

struct SkinParams {
  // Dermis: single-scattering colour (the scattering albedo a of Hanrahan-Krueger), in [0, 1].
  float SkinColor[3] = {0.85f, 0.55f, 0.45f};  // chosen: a light skin tone
  // Sebum: colour of the specular sheen, in [0, 1]. Pharr: white.
  float SheenColor[3] = {1.0f, 1.0f, 1.0f};
  // Output alpha, in [0, 1].
  float Opacity = 1.0f;
  // Ambient lights times SkinColor, in [0, 1]. Pharr: Ka = 0.5.
  float AmbientCoeff = 0.5f;
  // Dermis optical depth d, in [0, 1e6] (1e6: semi-infinite). Pharr: 0.5.
  float Thickness = 0.5f;
  // Relative index of refraction skin / outside, in [0.25, 4]; < 1 gives total internal reflection.
  float Eta = 1.4f;
  // Scale of the dermis term, in [0, 100]. Chosen: 6.272, because the correctly normalised
  // Henyey-Greenstein lobe (1/(4 pi)) backscatters little at g = 0.8 and would be faint at 1. It
  // was 10 while the `correct` dermis lacked the factor pi of the light units, then 3.2 (about
  // 10 / pi) while it lacked the 1/Eta^2 of the radiance leaving the layer; 6.272 = 3.2 x 1.4^2
  // keeps the head scan's look at the default Eta.
  float SingleScatteringCoeff = 6.272f;
  // Epidermis colour C_d, in [0, 1]. Chosen: a warmer, redder tone than SkinColor.
  float DiffusionColor[3] = {0.9f, 0.45f, 0.35f};
  // Epidermis strength I_ms, in [0, 100]. Chosen: 0.25.
  float MultipleScatteringCoeff = 0.25f;
  // l_c, in [0, 100]; the fake's denominator |I.N| + l_c is floored at kClampFloor.
  float ClampCoeff = 0.5f;
  // Sebum exponent, in [1, 256] (Maya's Phong cosine power runs 2..100). Chosen: 20.
  float Power = 20.0f;
  // Sebum strength, in [0, 100]. Chosen: 0.2.
  float Specularity = 0.2f;
  // Henyey-Greenstein asymmetry, in [-1, 1]; used clamped to +-kMaxAbsG. Paper/H-K: 0.8.
  float g = 0.8f;

  SingleScattering single_scattering = SingleScattering::correct;
  MultipleScattering multiple_scattering = MultipleScattering::paper;
  Fresnel fresnel = Fresnel::exact;
  Phase phase = Phase::correct;
  Specular specular = Specular::phong;

  // Normal Blur SSS: Gaussian sigma per channel (r, g, b), scene units, each in [0, 1e6]; red
  // widest by convention (light travels farther in skin at long wavelengths). Chosen for the head
  // scan (about 8.5 units tall, so 0.2 units is about 6 mm).
  float normal_blur_radius[3] = {0.2f, 0.1f, 0.05f};
  // Weight of dot(N_blur, L) against dot(N, L) per channel, in [0, 1].
  float normal_blur_mix[3] = {0.9f, 0.6f, 0.4f};
};

// Numerical guards shared by the reference and the kernels (see the README, "Skin shader: deviations").
inline constexpr float kMaxAbsG = 1.0f - 1e-6f;   // |g| = 1 is a delta; clamp to a finite lobe
inline constexpr float kClampFloor = 1e-3f;       // floor of |I.N| + ClampCoeff
inline constexpr float kDegenerateNormal2 = 1e-30f;  // |N|^2 below this (or infinite): degenerate

struct ParamError {
  std::string field;   // the JSON key, e.g. "Eta" or "SkinColor[1]"
  std::string reason;  // e.g. "must be in [0.25, 4], got 0"
  std::string message() const { return field + ": " + reason; }
};

// A number as a ParamError's reason shows it: 6 significant digits, as printf's %g writes them.
std::string format_number(double v);

// First out-of-range or non-finite field, or nullopt when every field is valid.
std::optional<ParamError> validate(const SkinParams& p);

// Switch names as written in the scene JSON ("off", "paper", "correct", "normal_blur", ...).
std::string_view to_string(SingleScattering v);
std::string_view to_string(MultipleScattering v);
std::string_view to_string(Fresnel v);
std::string_view to_string(Phase v);
std::string_view to_string(Specular v);

// Parse `text` into `out` (unchanged on error). The error names `field` and lists the valid names.
std::optional<ParamError> parse(std::string_view field, std::string_view text, SingleScattering& out);
std::optional<ParamError> parse(std::string_view field, std::string_view text, MultipleScattering& out);
std::optional<ParamError> parse(std::string_view field, std::string_view text, Fresnel& out);
std::optional<ParamError> parse(std::string_view field, std::string_view text, Phase& out);
std::optional<ParamError> parse(std::string_view field, std::string_view text, Specular& out);

}  // namespace pelt::shading
