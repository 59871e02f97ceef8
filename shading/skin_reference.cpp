#include "shading/skin_reference.h"

#include "shading/diffusion_reference.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace pelt::shading::ref {
namespace {

struct V3 {
  double x, y, z;
};
double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Normalises v; false when |v|^2 is below kDegenerateNormal2 or would overflow a float (the
// kernels compute in float, and a lane must be classified the same way by both).
bool normalize_guarded(V3 v, V3& out) {
  const double len2 = dot(v, v);
  if (!(len2 >= double(kDegenerateNormal2)) || !(len2 <= double(FLT_MAX))) return false;
  const double inv = 1.0 / std::sqrt(len2);
  out = {v.x * inv, v.y * inv, v.z * inv};
  return true;
}

// Shading frame: unit normal n turned toward the viewer, unit view direction v, cos_o = n.v >= 0.
// A degenerate normal is replaced by the view direction and vice versa; both degenerate gives +z.
struct Frame {
  V3 n, v;
  double sign;  // -1 when the normal was flipped toward the viewer
  double co;
};

Frame make_frame(const Sample& s, const double eye[3]) {
  Frame f{};
  V3 n, v;
  const bool n_ok = normalize_guarded({s.normal[0], s.normal[1], s.normal[2]}, n);
  const bool v_ok = normalize_guarded({eye[0] - s.pos[0], eye[1] - s.pos[1], eye[2] - s.pos[2]}, v);
  if (!n_ok && !v_ok) n = v = {0.0, 0.0, 1.0};
  else if (!n_ok) n = v;
  else if (!v_ok) v = n;
  f.sign = dot(n, v) < 0.0 ? -1.0 : 1.0;
  f.n = {n.x * f.sign, n.y * f.sign, n.z * f.sign};
  f.v = v;
  f.co = std::clamp(dot(f.n, f.v), 0.0, 1.0);
  return f;
}

// Unit direction to a non-ambient light. A point light at the shaded point (or so far that the
// float difference overflows) shines along the normal.
V3 light_dir(const Light& l, const Sample& s, const V3& n) {
  V3 d;
  if (l.type == Light::Type::Directional) {
    normalize_guarded({l.vec[0], l.vec[1], l.vec[2]}, d);
    return d;
  }
  if (!normalize_guarded({l.vec[0] - s.pos[0], l.vec[1] - s.pos[1], l.vec[2] - s.pos[2]}, d)) return n;
  return d;
}

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

}  // namespace

bool refract_cos(double cos_i, double eta, double& cos_t) {
  const double k = (cos_i * cos_i + (eta - 1.0) * (eta + 1.0)) / (eta * eta);
  if (!(k > 0.0)) {
    cos_t = 0.0;
    return false;
  }
  cos_t = std::sqrt(k);
  return true;
}

double fresnel_exact(double cos_i, double eta) {
  cos_i = clamp01(cos_i);
  double ct;
  if (!refract_cos(cos_i, eta, ct)) return 1.0;
  const double rs = (cos_i - eta * ct) / (cos_i + eta * ct);
  const double rp = (eta * cos_i - ct) / (eta * cos_i + ct);
  return clamp01(0.5 * (rs * rs + rp * rp));
}

double efresnel(double Kr) {
  const double t = clamp01(Kr / 0.5);
  return t * t * (3.0 - 2.0 * t);
}

double fresnel_paper(double cos_i, double eta) {
  double ct;
  if (!refract_cos(cos_i, eta, ct)) return 0.0;  // the listing's refract returns T = 0
  const double r_parallel = 1.0;                 // ((N.I) - eta (N.T)) / ((N.I) - eta (N.T))
  const double r_perp = (eta * cos_i + ct) / (eta * cos_i - ct);
  return (r_parallel * r_parallel - r_perp * r_perp) / 2.0;
}

double clamp_g(double g) { return std::clamp(g, -double(kMaxAbsG), double(kMaxAbsG)); }

namespace {
double hg_base(double cos_theta, double g) {
  const double a = std::fabs(g);
  const double s = g < 0.0 ? -cos_theta : cos_theta;
  return (1.0 - a) * (1.0 - a) + 2.0 * a * (1.0 - std::clamp(s, -1.0, 1.0));
}
}  // namespace

double hg_phase(double cos_theta, double g) {
  g = clamp_g(g);
  const double b = hg_base(cos_theta, g);
  return (1.0 - g) * (1.0 + g) / (4.0 * kPi * b * std::sqrt(b));
}

double hg_bound(double g) {
  const double a = std::fabs(clamp_g(g));
  return (1.0 + a) / (4.0 * kPi * (1.0 - a) * (1.0 - a));
}

double hg_phase_paper(double cos_theta, double g) {
  g = clamp_g(g);
  const double a = std::fabs(g);
  const double floor = (1.0 - a) * (1.0 - a);
  const double b = std::max((1.0 - g) * (1.0 + g) - 2.0 * g * std::clamp(cos_theta, -1.0, 1.0), floor);
  return (1.0 - g) * (1.0 + g) / (b * std::sqrt(b));
}

double hg_paper_bound(double g) {
  const double a = std::fabs(clamp_g(g));
  return (1.0 + a) / ((1.0 - a) * (1.0 - a));
}

double single_scattering(double ci, double co, double p, double albedo, double thickness) {
  const double tiny = 1e-20;
  const double s = 1.0 / std::max(ci, tiny) + 1.0 / std::max(co, tiny);
  return albedo * p * -std::expm1(-thickness * s) / std::max(ci + co, tiny);
}

double epidermis_fake(double cos_o, double ms_coeff, double clamp_coeff) {
  return ms_coeff / std::max(std::fabs(cos_o) + clamp_coeff, double(kClampFloor));
}

double dipole_total_rd(double alpha, double eta) { return diffusion::total_reflectance(alpha, eta); }

double specular_lobe(double s, double power) {
  if (!(s > 0.0)) return 0.0;
  return std::pow(std::min(s, 1.0), power);
}

Shaded shade_skin_pixel(const SkinParams& p, const Light* lights, size_t light_count, const double eye[3],
                        const Sample& s) {
  Shaded out{};
  const Frame f = make_frame(s, eye);
  const double eta = p.Eta;
  double A[3], a[3], cd[3];
  for (int c = 0; c < 3; ++c) {
    A[c] = clamp01(s.albedo[c]);
    a[c] = double(p.SkinColor[c]) * A[c];
    cd[c] = double(p.DiffusionColor[c]) * A[c];
  }
  V3 nb[3];
  if (p.multiple_scattering == MultipleScattering::normal_blur)
    for (int c = 0; c < 3; ++c) {
      V3 b;
      if (normalize_guarded({s.blurred_normal[c][0], s.blurred_normal[c][1], s.blurred_normal[c][2]}, b))
        nb[c] = {b.x * f.sign, b.y * f.sign, b.z * f.sign};
      else
        nb[c] = f.n;
    }

  // Transmission out toward the viewer. DEVIATION (paper mode): the listing's Fresnel gives
  // Kr <= 0, which efresnel's smoothstep maps to Kr = 0, Kt = 1 at every angle; reproduced as 1.
  double cot = 0.0;
  const bool out_ok = refract_cos(f.co, eta, cot);
  const double F_out = fresnel_exact(f.co, eta);
  const double kt_out_exact = 1.0 - F_out;
  double kt_out = 1.0;
  if (p.single_scattering == SingleScattering::correct)
    kt_out = 1.0 - (p.fresnel == Fresnel::efresnel ? efresnel(F_out) : F_out);
  double rd[3];
  for (int c = 0; c < 3; ++c) rd[c] = dipole_total_rd(cd[c], eta);
  // Hanrahan-Krueger's BRDF is per steradian; in pelt's light units (no 1/pi: a white Lambert
  // surface returns 1, pi times its BRDF) the `correct` dermis is pi x BRDF x irradiance, like the
  // dipole epidermis, which drops Jensen's 1/pi. The layer's single scattering is radiance inside
  // the medium; leaving it, radiance is divided by eta^2 (the refracted solid angle widens by
  // eta^2 cos_t / cos_o), which the usual statement of the formula (and Pharr's shader) leaves
  // out: without it the dermis is eta^2 (1.96) times too bright. DEVIATION (paper mode): the
  // listing's arithmetic is kept as it stands, in its own units (RenderMan's, also without 1/pi,
  // with a phase function that lacks 1/(4 pi)), so it takes no factor: the paper variant looks as
  // the paper's code does.
  const double dermis_units = p.single_scattering == SingleScattering::correct ? kPi / (eta * eta) : 1.0;

  double ambient[3] = {0, 0, 0};
  for (size_t li = 0; li < light_count; ++li) {
    const Light& l = lights[li];
    const double cl[3] = {l.color[0], l.color[1], l.color[2]};
    if (p.multiple_scattering == MultipleScattering::paper) {
      const double fake = epidermis_fake(f.co, p.MultipleScatteringCoeff, p.ClampCoeff);
      for (int c = 0; c < 3; ++c) out.epidermis[c] += cd[c] * cl[c] * fake;
    }
    if (l.type == Light::Type::Ambient) {
      for (int c = 0; c < 3; ++c) ambient[c] += double(p.AmbientCoeff) * a[c] * cl[c];
      continue;
    }
    const V3 L = light_dir(l, s, f.n);
    const double ci = std::clamp(dot(f.n, L), -1.0, 1.0);
    if (p.multiple_scattering == MultipleScattering::normal_blur)
      for (int c = 0; c < 3; ++c) {
        const double w = p.normal_blur_mix[c];
        const double lit = (1.0 - w) * std::max(ci, 0.0) + w * std::max(dot(nb[c], L), 0.0);
        out.epidermis[c] += cd[c] * p.MultipleScatteringCoeff * cl[c] * lit;
      }
    if (!(ci > 0.0)) continue;  // light behind the surface: no sebum, dermis or dipole term

    const double LdotV = dot(L, f.v);
    double lobe;
    if (p.specular == Specular::phong) {
      lobe = specular_lobe(2.0 * ci * f.co - LdotV, p.Power);  // R.V, R = 2 (N.L) N - L
    } else {
      const V3 H = {L.x + f.v.x, L.y + f.v.y, L.z + f.v.z};
      const double h2 = dot(H, H);
      lobe = h2 > 1e-30 ? specular_lobe(dot(f.n, H) / std::sqrt(h2), p.Power) : 0.0;
    }
    for (int c = 0; c < 3; ++c) out.sebum[c] += double(p.Specularity) * p.SheenColor[c] * cl[c] * lobe;

    const double F_in = fresnel_exact(ci, eta);
    if (p.multiple_scattering == MultipleScattering::reference)
      for (int c = 0; c < 3; ++c)
        out.epidermis[c] += p.MultipleScatteringCoeff * cl[c] * ci * (1.0 - F_in) * rd[c] * kt_out_exact;

    double cit;
    if (p.single_scattering == SingleScattering::off || !out_ok || !refract_cos(ci, eta, cit)) continue;
    double kt_in = 1.0;
    if (p.single_scattering == SingleScattering::correct)
      kt_in = 1.0 - (p.fresnel == Fresnel::efresnel ? efresnel(F_in) : F_in);
    // Scattering angle between the refracted propagation directions t_i (down) and t_o (up):
    // t_i . t_o = (cos_i cos_o - L.V) / eta^2 - cos_it cos_ot.
    const double cos_theta = std::clamp((ci * f.co - LdotV) / (eta * eta) - cit * cot, -1.0, 1.0);
    const double ph = p.phase == Phase::correct ? hg_phase(cos_theta, p.g) : hg_phase_paper(cos_theta, p.g);
    for (int c = 0; c < 3; ++c) {
      const double ss = single_scattering(cit, cot, ph, a[c], p.Thickness);
      out.dermis[c] += dermis_units * double(p.SingleScatteringCoeff) * cl[c] * ci * kt_in * kt_out * ss;
    }
  }
  const double op = p.Opacity;
  out.alpha = op;
  for (int c = 0; c < 3; ++c) {
    out.sebum[c] *= op;
    out.epidermis[c] *= op;
    out.dermis[c] *= op;
    out.rgb[c] = op * ambient[c] + out.sebum[c] + out.epidermis[c] + out.dermis[c];
  }
  return out;
}

Shaded shade_unlit_pixel(const Sample& s) {
  Shaded out{};
  out.alpha = 1.0;
  for (int c = 0; c < 3; ++c) out.rgb[c] = clamp01(s.albedo[c]);
  return out;
}

namespace {
Shaded shade_basic(const BasicParams* bp, const Light* lights, size_t light_count, const double eye[3],
                   const Sample& s) {
  Shaded out{};
  out.alpha = 1.0;
  const Frame f = make_frame(s, eye);
  for (size_t li = 0; li < light_count; ++li) {
    const Light& l = lights[li];
    if (l.type == Light::Type::Ambient) {
      for (int c = 0; c < 3; ++c) out.rgb[c] += clamp01(s.albedo[c]) * l.color[c];
      continue;
    }
    const V3 L = light_dir(l, s, f.n);
    const double ci = std::clamp(dot(f.n, L), -1.0, 1.0);
    if (!(ci > 0.0)) continue;
    double lobe = 0.0;
    if (bp) {
      const V3 H = {L.x + f.v.x, L.y + f.v.y, L.z + f.v.z};
      const double h2 = dot(H, H);
      lobe = h2 > 1e-30 ? specular_lobe(dot(f.n, H) / std::sqrt(h2), bp->shininess) : 0.0;
    }
    for (int c = 0; c < 3; ++c)
      out.rgb[c] += l.color[c] * (clamp01(s.albedo[c]) * ci + (bp ? bp->specular[c] * lobe : 0.0));
  }
  return out;
}
}  // namespace

Shaded shade_lambert_pixel(const Light* lights, size_t light_count, const double eye[3], const Sample& s) {
  return shade_basic(nullptr, lights, light_count, eye, s);
}

Shaded shade_blinn_pixel(const BasicParams& p, const Light* lights, size_t light_count, const double eye[3],
                         const Sample& s) {
  return shade_basic(&p, lights, light_count, eye, s);
}

}  // namespace pelt::shading::ref
