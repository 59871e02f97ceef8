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

// A colour map the strands take (fur's use_color_map), placed where the base surface reads it.
struct FurColorMap {
  const raster::Texture* texture = nullptr;
  io::MapPlacement placement;  // where the mesh file places the map, as the base surface reads it
};
// FurShaderSetup::face_color_map's entry for a face whose material draws no colour map: its
// strands keep their own colour (times 1).
inline constexpr uint32_t kNoFurColorMap = 0xFFFFFFFFu;

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
  // The object's colour maps (fur's use_color_map), read at the mesh uv (FurMapUv, the slot
  // set_map_uv_slot names): the strand colour is multiplied by its face's, before the tint's clamp
  // to 1. Without face_color_map: color_maps[0], every face's. With it (a mesh whose materials
  // draw several maps, or some none): base face f's is color_maps[face_color_map[f]]
  // (kNoFurColorMap: none), a fin's that of its edge's first face (set_fin_maps).
  const FurColorMap* color_maps = nullptr;
  size_t color_map_count = 0;
  const uint32_t* face_color_map = nullptr;
  raster::Filter map_filter = raster::Filter::Trilinear;
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
  // Fins with face_color_map: each fin quad's map, as face_color_map holds them.
  void set_fin_maps(const uint32_t* quad_map) { quad_map_ = quad_map; }
  // Per-vertex lighting arrives as FurGreyVaryings (else FurVaryings); per frame, as above.
  void set_grey_lighting(bool grey) { grey_ = grey; }
  // The varying slot of the mesh uv (with a colour map): after the frame's lighting layout.
  void set_map_uv_slot(int slot) { map_uv_slot_ = slot; }
  void shade(const raster::FragmentBatch& batch) const override;

 private:
  // The colour maps' texels under the batch's covered lanes into map (1 where a face has none).
  void sample_color_maps(const raster::FragmentBatch& b, float* const map[4]) const;

  FurShaderSetup s_;
  std::vector<shading::Light> lights_;
  float eye_[3] = {0, 0, 0};
  const float* quad_weight_ = nullptr;
  const uint32_t* quad_map_ = nullptr;
  bool grey_ = false;
  int map_uv_slot_ = 0;
};

}  // namespace pelt::render
