// The *_reference batch entry points of skin_kernels.h: the same validation as the kernels, then
// the double-precision per-pixel reference (skin_reference.h) lane by lane.
#include <cmath>
#include <stdexcept>
#include <string>

#include "shading/skin_kernels.h"
#include "shading/skin_reference.h"

namespace pelt::shading {
namespace {

void throw_if(const std::optional<ParamError>& e) {
  if (e) throw std::invalid_argument(e->message());
}

void check_common(const Light* lights, size_t count, const float eye[3], const SurfaceSoA& s,
                  const ShadeOutSoA& o, bool needs_blurred) {
  throw_if(validate_lights(lights, count));
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(eye[c])) throw std::invalid_argument("eye[" + std::to_string(c) + "]: must be finite");
  throw_if(validate_batch(s, o, needs_blurred));
}

ref::Sample load(const SurfaceSoA& s, size_t i, bool blurred) {
  ref::Sample r{};
  for (int c = 0; c < 3; ++c) {
    r.pos[c] = s.pos[c][i];
    r.normal[c] = s.normal[c][i];
    r.albedo[c] = s.albedo[c][i];
    if (blurred)
      for (int a = 0; a < 3; ++a) r.blurred_normal[c][a] = s.blurred_normal[c][a][i];
  }
  return r;
}

void store(const ref::Shaded& r, const ShadeOutSoA& o, size_t i, bool layers) {
  for (int c = 0; c < 3; ++c) {
    o.rgb[c][i] = float(r.rgb[c]);
    if (!layers) continue;
    if (o.sebum[c]) o.sebum[c][i] = float(r.sebum[c]);
    if (o.epidermis[c]) o.epidermis[c][i] = float(r.epidermis[c]);
    if (o.dermis[c]) o.dermis[c][i] = float(r.dermis[c]);
  }
  o.alpha[i] = float(r.alpha);
}

}  // namespace

void shade_skin_reference(const SkinParams& params, const Light* lights, size_t light_count,
                          const float eye[3], const SurfaceSoA& surface, const ShadeOutSoA& out) {
  throw_if(validate(params));
  const bool blurred = params.multiple_scattering == MultipleScattering::normal_blur;
  check_common(lights, light_count, eye, surface, out, blurred);
  const double e[3] = {eye[0], eye[1], eye[2]};
  for (size_t i = 0; i < surface.n; ++i)
    store(ref::shade_skin_pixel(params, lights, light_count, e, load(surface, i, blurred)), out, i, true);
}

void shade_unlit_reference(const Light* lights, size_t light_count, const float eye[3],
                           const SurfaceSoA& surface, const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  for (size_t i = 0; i < surface.n; ++i) store(ref::shade_unlit_pixel(load(surface, i, false)), out, i, false);
}

void shade_lambert_reference(const Light* lights, size_t light_count, const float eye[3],
                             const SurfaceSoA& surface, const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  const double e[3] = {eye[0], eye[1], eye[2]};
  for (size_t i = 0; i < surface.n; ++i)
    store(ref::shade_lambert_pixel(lights, light_count, e, load(surface, i, false)), out, i, false);
}

void shade_blinn_reference(const BasicParams& params, const Light* lights, size_t light_count,
                           const float eye[3], const SurfaceSoA& surface, const ShadeOutSoA& out) {
  throw_if(validate(params));
  check_common(lights, light_count, eye, surface, out, false);
  const double e[3] = {eye[0], eye[1], eye[2]};
  for (size_t i = 0; i < surface.n; ++i)
    store(ref::shade_blinn_pixel(params, lights, light_count, e, load(surface, i, false)), out, i, false);
}

}  // namespace pelt::shading
