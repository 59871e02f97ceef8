// The batch hand-off between the rasterizer and the shading kernels: structure of arrays.
#pragma once

#include <cstddef>
#include <optional>

#include "shading/skin_params.h"

namespace pelt::shading {

// n lanes, n a multiple of 16, every pointer 64-byte aligned. Lanes the rasterizer did not cover
// may hold any finite values; their outputs are finite and non-negative, and otherwise unused.
struct SurfaceSoA {
  size_t n;
  const float* pos[3];     // world space
  const float* normal[3];  // world space; need not be unit, may be zero (then the view direction)
  // Linear base colour. Lambert/Blinn/unlit: the material colour x colour map. Skin: the colour
  // map only (white without one); SkinColor and DiffusionColor come from SkinParams. Clamped to
  // [0, 1] by the kernels.
  const float* albedo[3];
  const float* blurred_normal[3][3];  // [channel r,g,b][xyz]; null unless normal_blur
};

// Outputs are linear RGB premultiplied by alpha. The per-layer pointers may be null (not wanted);
// when given, sebum + epidermis + dermis + Opacity * ambient = rgb. Basic materials leave the
// per-layer outputs untouched.
struct ShadeOutSoA {
  float* rgb[3];
  float* alpha;
  float* sebum[3];
  float* epidermis[3];
  float* dermis[3];
};

// Checks n, the alignment and presence of the pointers the call will read and write.
std::optional<ParamError> validate_batch(const SurfaceSoA& s, const ShadeOutSoA& o, bool needs_blurred);

}  // namespace pelt::shading
