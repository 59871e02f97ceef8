// Validation of the batch interface's plain data (lights, SoA pointers, basic parameters).
#include <cmath>
#include <cstdint>
#include <string>

#include "shading/basic_params.h"
#include "shading/param_checks.h"
#include "shading/light.h"
#include "shading/surface.h"

namespace pelt::shading {
using checks::pointer;
using checks::range;

std::optional<ParamError> validate_lights(const Light* lights, size_t count) {
  if (count > 0 && !lights) return ParamError{"lights", "null with a non-zero count"};
  for (size_t i = 0; i < count; ++i) {
    const Light& l = lights[i];
    const auto base = [i] { return "lights[" + std::to_string(i) + "]"; };
    if (l.type != Light::Type::Directional && l.type != Light::Type::Point &&
        l.type != Light::Type::Ambient)
      return ParamError{base() + ".type", "must be Directional, Point or Ambient"};
    for (int c = 0; c < 3; ++c)
      if (auto e = range([&] { return base() + ".color[" + std::to_string(c) + "]"; }, l.color[c], 0.0, 1e6))
        return e;
    if (l.type == Light::Type::Ambient) continue;
    // 1e30 as a float (1.0000000150e30): a scene's 1e30, the documented bound, arrives rounded to it.
    constexpr double kMaxCoordinate = double(1e30f);
    for (int c = 0; c < 3; ++c)
      if (auto e = range([&] { return base() + ".vec[" + std::to_string(c) + "]"; }, l.vec[c], -kMaxCoordinate,
                         kMaxCoordinate))
        return e;
    if (l.type == Light::Type::Directional) {
      const double len2 = double(l.vec[0]) * l.vec[0] + double(l.vec[1]) * l.vec[1] +
                          double(l.vec[2]) * l.vec[2];
      if (!(len2 > 1e-12)) return ParamError{base() + ".vec", "a directional light needs a non-zero direction"};
    }
  }
  return std::nullopt;
}

std::optional<ParamError> validate_batch(const SurfaceSoA& s, const ShadeOutSoA& o, bool needs_blurred) {
  if (s.n % 16 != 0) return ParamError{"n", "must be a multiple of 16, got " + std::to_string(s.n)};
  static constexpr const char* kXyz[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    const auto named = [c](const char* what) { return [=] { return std::string(what) + "[" + kXyz[c] + "]"; }; };
    const auto indexed = [c](const char* what) { return [=] { return std::string(what) + "[" + std::to_string(c) + "]"; }; };
    if (auto e = pointer(named("pos"), s.pos[c], true)) return e;
    if (auto e = pointer(named("normal"), s.normal[c], true)) return e;
    if (auto e = pointer(indexed("albedo"), s.albedo[c], true)) return e;
    if (auto e = pointer(indexed("rgb"), o.rgb[c], true)) return e;
    if (auto e = pointer(indexed("sebum"), o.sebum[c], false)) return e;
    if (auto e = pointer(indexed("epidermis"), o.epidermis[c], false)) return e;
    if (auto e = pointer(indexed("dermis"), o.dermis[c], false)) return e;
    if (needs_blurred)
      for (int a = 0; a < 3; ++a)
        if (auto e = pointer([&] { return "blurred_normal[" + std::to_string(c) + "][" + kXyz[a] + "]"; },
                             s.blurred_normal[c][a], true))
          return e;
  }
  if (auto e = pointer("alpha", o.alpha, true)) return e;
  return std::nullopt;
}

std::optional<ParamError> validate(const BasicParams& p) {
  for (int c = 0; c < 3; ++c)
    if (auto e = range([c] { return "specular[" + std::to_string(c) + "]"; }, p.specular[c], 0.0, 100.0)) return e;
  if (auto e = range("shininess", p.shininess, 1.0, 256.0)) return e;
  return std::nullopt;
}

}  // namespace pelt::shading
