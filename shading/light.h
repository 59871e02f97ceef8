// A light as the shading kernels see it: plain data, one per scene light.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "shading/skin_params.h"

namespace pelt::shading {

struct Light {
  enum class Type : uint32_t { Directional, Point, Ambient } type;
  // Directional: direction TO the light (normalised by the kernels; must not be zero).
  // Point: world position. Point lights do not decay with distance (Maya's default "No Decay",
  // the paper's renderer); a point light exactly at the shaded point shines along its normal.
  // Ambient: ignored.
  float vec[3];
  float color[3];  // colour x intensity, linear, each in [0, 1e6]
};

// The light's vector as the SIMD kernels read it, prepared once per call: a directional
// light's direction made unit in double (so every kernel and target agrees on it to the last
// bit), a point light's position as given.
inline void kernel_light_vector(const Light& l, float out[3]) {
  const double len = l.type == Light::Type::Directional
                         ? std::sqrt(double(l.vec[0]) * l.vec[0] + double(l.vec[1]) * l.vec[1] +
                                     double(l.vec[2]) * l.vec[2])
                         : 1.0;
  for (int c = 0; c < 3; ++c) out[c] = float(l.vec[c] / len);
}

// First bad field ("lights[2].color[0]") with its reason, or nullopt.
std::optional<ParamError> validate_lights(const Light* lights, size_t count);

}  // namespace pelt::shading
