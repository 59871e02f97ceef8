// Fur shells and fins as a rasterizer shader: samples the strand textures (the layer of
// each block's triangle, or the fin texture), fades fins by their view weight, and lights
// the strands: with the per-vertex light the rasterizer interpolated (default), or with
// Kajiya-Kay per fragment.
#pragma once

#include <stdexcept>
#include <vector>

#include <glm/vec3.hpp>

#include "raster/pipeline.h"
#include "raster/texture.h"
#include "shading/fur_lighting.h"
#include "shading/light.h"
#include "tools/io/map_placement.h"

namespace pelt::render {

struct FurShaderSetup {
  bool fins = false;                         // fin draw (else shells)
  const raster::TextureArray* shells = nullptr;
  // Per layer (required for shells): the shells are luminance-alpha (fur::ShellLuminance,
  // raster::TexelFormat::La8), colour = min(1, tint * L).
  const glm::vec3* shell_tint = nullptr;
  // Fins: luminance-alpha (fur::FinLuminance, raster::TexelFormat::La8), colour = min(1,
  // (fin_tint_root + fin_tint_slope v) * L) at the fin's height v.
  const raster::Texture* fin = nullptr;
  glm::vec3 fin_tint_root{0.0f}, fin_tint_slope{0.0f};
  raster::SamplerState sampler;
  uint32_t base_faces = 0;                   // shells: triangles per layer
  uint32_t primitive_offset = 0;             // first triangle of this draw in the object's list
  // The object's colour map (fur's use_color_map), read at the mesh uv (FurMapUv, the slot
  // set_map_uv_slot names): the strand colour is multiplied by it, before the tint's clamp to 1.
  const raster::Texture* color_map = nullptr;
  raster::Filter map_filter = raster::Filter::Trilinear;
  io::MapPlacement map_placement;  // where the mesh file places the map, as the base surface reads it
  bool per_pixel_lighting = false;           // FurPixelVaryings and Kajiya-Kay per fragment
  bool double_precision = false;             // texture sampling and lighting by the double references
  bool match_llvmpipe = false;               // per-pixel: the harness's fixed light term
  glm::vec3 llvmpipe_light{0.0f, 1.0f, 0.0f};
  shading::FurLightParams light_params;
};

class FurShader final : public raster::Shader {
 public:
  // Throws std::invalid_argument for a shell draw without shell_tint.
  explicit FurShader(const FurShaderSetup& setup) : s_(setup) {
    if (!s_.fins && !s_.shell_tint) throw std::invalid_argument("FurShader: a shell draw needs shell_tint");
  }
  // Per-frame inputs; call between renders, never during one. Fins: `quad_weight` gives each
  // fin quad of the draw (triangles 2q and 2q + 1, counted from primitive_offset) its fade
  // (null: 1).
  void set_view(const std::vector<shading::Light>& lights, const glm::vec3& eye);
  void set_fins(const float* quad_weight) { quad_weight_ = quad_weight; }
  // Per-vertex lighting arrives as FurGreyVaryings (else FurVaryings); per frame, as above.
  void set_grey_lighting(bool grey) { grey_ = grey; }
  // The varying slot of the mesh uv (with a colour map): after the frame's lighting layout.
  void set_map_uv_slot(int slot) { map_uv_slot_ = slot; }
  void shade(const raster::FragmentBatch& batch) const override;

 private:
  FurShaderSetup s_;
  std::vector<shading::Light> lights_;
  float eye_[3] = {0, 0, 0};
  const float* quad_weight_ = nullptr;
  bool grey_ = false;
  int map_uv_slot_ = 0;
};

}  // namespace pelt::render
