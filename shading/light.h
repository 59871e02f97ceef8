// A light as the shading kernels see it: plain data, one per scene light.
#pragma once

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

// First bad field ("lights[2].color[0]") with its reason, or nullopt.
std::optional<ParamError> validate_lights(const Light* lights, size_t count);

}  // namespace pelt::shading
