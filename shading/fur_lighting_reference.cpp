// The double-precision references of fur_lighting.h: the same validation as the kernels, then the
// model lane by lane, written for clarity. This is the specification the kernels are tested
// against; every rule of the header's "Numerical rules" appears here once.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

#include "shading/fur_lighting.h"

namespace pelt::shading {
namespace {

struct D3 {
  double x, y, z;
};

double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
D3 add(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }

// The header's degeneracy rule: squared length below kDegenerateNormal2 or above FLT_MAX.
bool normalize_guarded(const D3& v, D3& out) {
  const double len2 = dot(v, v);
  if (!(len2 >= double(kDegenerateNormal2) && len2 <= double(FLT_MAX))) return false;
  const double inv = 1.0 / std::sqrt(len2);
  out = {v.x * inv, v.y * inv, v.z * inv};
  return true;
}

// sin^2 of the angle between a and b (neither zero), in the scale-free form of the header.
double sin2_between(const D3& a, const D3& b) {
  const D3 c = cross(a, b);
  const double s = dot(c, c), d = dot(a, b);
  return s / (d * d + s);
}

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

void throw_if(const std::optional<ParamError>& e) {
  if (e) throw std::invalid_argument(e->message());
}

void check_eye(const float eye[3]) {
  if (!eye) throw std::invalid_argument("eye: must not be null");
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(eye[c])) throw std::invalid_argument("eye[" + std::to_string(c) + "]: must be finite");
}

D3 load3(const float* const p[3], size_t i) { return {p[0][i], p[1][i], p[2][i]}; }

struct FurPixel {
  double rgb[3];
  double a;
};

FurPixel shade_fur_pixel(const FurLightParams& p, const Light* lights, size_t light_count, const D3& eye,
                         const FurSurfaceSoA& s, size_t i) {
  const D3 pos = load3(s.pos, i);
  D3 N{}, V{0.0, 0.0, 0.0}, T{};
  const bool n_ok = normalize_guarded(load3(s.normal, i), N);
  const bool v_ok = normalize_guarded({eye.x - pos.x, eye.y - pos.y, eye.z - pos.z}, V);
  if (!v_ok) V = {0.0, 0.0, 0.0};
  const D3 fallback = n_ok ? N : v_ok ? V : D3{0.0, 0.0, 1.0};
  if (!normalize_guarded(load3(s.tangent, i), T)) T = fallback;

  const double h = clamp01(s.height[i]);
  const double aor = p.ambient_occlusion_root;
  const double ao = h + (1.0 - h) * aor;
  const double wrap = p.backlight_wrap;
  const double exponent = double(p.shininess) * 0.5;  // sin^shininess = (sin^2)^exponent

  double ambient[3] = {0, 0, 0}, dsum[3] = {0, 0, 0}, ssum[3] = {0, 0, 0};
  for (size_t li = 0; li < light_count; ++li) {
    const Light& l = lights[li];
    if (l.type == Light::Type::Ambient) {
      for (int c = 0; c < 3; ++c) ambient[c] += l.color[c];
      continue;
    }
    D3 L{};
    if (l.type == Light::Type::Directional) {
      normalize_guarded({l.vec[0], l.vec[1], l.vec[2]}, L);  // validated non-zero
    } else if (!normalize_guarded({l.vec[0] - pos.x, l.vec[1] - pos.y, l.vec[2] - pos.z}, L)) {
      L = fallback;  // the light sits at the fragment
    }
    const double ndl = n_ok ? std::clamp(dot(N, L), -1.0, 1.0) : 1.0;
    const double ndl_pos = std::max(ndl, 0.0);
    const double diffuse = double(p.diffuse) * std::sqrt(sin2_between(T, L)) * (wrap + (1.0 - wrap) * ndl_pos);
    double specular = 0.0;
    const D3 half = add(L, V);
    if (dot(half, half) >= double(kDegenerateHalf2))
      specular = double(p.specular) * std::pow(sin2_between(T, half), exponent) * ndl_pos;
    for (int c = 0; c < 3; ++c) {
      dsum[c] += double(l.color[c]) * diffuse;
      ssum[c] += double(l.color[c]) * specular;
    }
  }
  FurPixel out{};
  for (int c = 0; c < 3; ++c)
    out.rgb[c] = ao * (clamp01(s.texel[c][i]) * (ambient[c] + dsum[c]) + ssum[c]);
  out.a = clamp01(s.texel[3][i]);
  return out;
}

void store(const FurPixel& px, const FurOutSoA& o, size_t i) {
  for (int c = 0; c < 3; ++c) o.rgba[c][i] = float(px.rgb[c]);
  o.rgba[3][i] = float(px.a);
}

}  // namespace

void shade_fur_reference(const FurLightParams& params, const Light* lights, size_t light_count,
                         const float eye[3], const FurSurfaceSoA& surface, const FurOutSoA& out) {
  throw_if(validate(params));
  throw_if(validate_lights(lights, light_count));
  check_eye(eye);
  throw_if(validate_batch(surface, out, true));
  const D3 e{eye[0], eye[1], eye[2]};
  for (size_t i = 0; i < surface.n; ++i) store(shade_fur_pixel(params, lights, light_count, e, surface, i), out, i);
}

void shade_fur_match_llvmpipe_reference(const float light_dir[3], const FurSurfaceSoA& surface,
                                        const FurOutSoA& out) {
  throw_if(validate_light_dir(light_dir));
  throw_if(validate_batch(surface, out, false));
  D3 L{};
  normalize_guarded({light_dir[0], light_dir[1], light_dir[2]}, L);
  for (size_t i = 0; i < surface.n; ++i) {
    D3 N{};
    const double ndl = normalize_guarded(load3(surface.normal, i), N) ? dot(N, L) : 1.0;
    const double k = 0.35 + 0.65 * std::max(ndl, 0.0);
    FurPixel px{};
    for (int c = 0; c < 3; ++c) px.rgb[c] = clamp01(surface.texel[c][i]) * k;
    px.a = clamp01(surface.texel[3][i]);
    store(px, out, i);
  }
}

}  // namespace pelt::shading
