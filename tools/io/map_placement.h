// Where a map lies on a mesh's texture coordinates, as mesh files say it: how each axis wraps
// (glTF samplers' wrapS / wrapT, MTL's -clamp) and an affine transform of the uv the map is read
// at (glTF's KHR_texture_transform, MTL's -s and -o).
#pragma once

#include <array>
#include <string>

#include "raster/texture.h"

namespace pelt::io {

struct MapPlacement {
  raster::Wrap wrap_u = raster::Wrap::Repeat;
  raster::Wrap wrap_v = raster::Wrap::Repeat;
  // The map is read at (m[0] u + m[1] v + m[2], m[3] u + m[4] v + m[5]).
  std::array<float, 6> m{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};

  bool transforms() const { return m != MapPlacement{}.m; }
  // The uv the map is read at, for the mesh's (u, v).
  float u_at(float u, float v) const { return m[0] * u + m[1] * v + m[2]; }
  float v_at(float u, float v) const { return m[3] * u + m[4] * v + m[5]; }
  bool operator==(const MapPlacement&) const = default;
};

// What a mesh file may give a placement, for MTL's -s / -o and KHR_texture_transform alike: a
// value above kMostMapValue in size is refused (no uv so far out is meant), and a scale below
// kLeastMapScale, which makes the map one texel wherever it is drawn (a float may round it to 0).
inline constexpr double kMostMapValue = 1e30;
inline constexpr double kLeastMapScale = 1e-30;
// The reason a scale (as `written`) below kLeastMapScale is refused.
inline std::string tiny_scale_reason(const std::string& written) {
  return "a scale of " + written + " shrinks the map to one texel: give one of 1e-30 or more in size";
}

// The same placement for uvs whose v is flipped (v -> 1 - v on both sides: OBJ counts v from
// the bottom of the image, pelt from the top).
inline MapPlacement flipped_v(const MapPlacement& p) {
  MapPlacement f = p;
  const auto& m = p.m;
  // u' = m0 u + m1 (1 - v) + m2;  1 - v' = 1 - (m3 u + m4 (1 - v) + m5)
  f.m = {m[0], -m[1], m[1] + m[2], -m[3], m[4], 1.0f - m[4] - m[5]};
  return f;
}

// For people: "as the uvs say", or the wraps that are not repeat and the transform, e.g.
// "clamp u, mirror v; u' = 2 u + 0.25, v' = 3 v + 0.3" (`u', v'` in the uvs the placement is in).
std::string describe(const MapPlacement& p);

}  // namespace pelt::io
