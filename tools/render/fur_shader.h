// Fur shells and fins as a rasterizer shader: samples the strand textures (the layer of
// each block's triangle, or the fin texture), fades fins by their view weight, and lights
// the strands: with the per-vertex light the rasterizer interpolated (default), or with
// Kajiya-Kay per fragment.
#pragma once

#include <stdexcept>
#include <vector>

#include <glm/vec3.hpp>

#include "raster/parallel.h"
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

// A cut-out in the surface under the fur (a mesh file's alphaMode MASK part): strands rooted where
// the surface is cut away are not drawn. The alpha is the map's at the fragment's mesh uv (the
// strand's root: a shell vertex carries its base vertex's uv) times `factor`, tested as
// MaterialShader tests the surface's: kept where it reaches `cutoff`.
struct FurCutMap {
  // The map's alpha as luminance (cut_alpha_texture), placed as the surface reads the map; no
  // texture: the alpha is the factor alone.
  FurColorMap map;
  float factor = 1.0f;
  float cutoff = 0.5f;
};
// FurShaderSetup::face_cut_map's entry for a face that is not cut.
inline constexpr uint32_t kNoFurCut = 0xFFFFFFFFu;

// A map's alpha as an La8 texture (L = the alpha of `map`'s level 0, A = 1; its levels then
// average L plainly, as the map's own levels average its alpha): the cut-outs sample the strands'
// La8 path instead of the map's sRGB RGBA8 one, which decodes three colour channels for nothing.
raster::Texture cut_alpha_texture(const raster::Texture& map, const raster::ParallelFor& parallel = {});

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
  // The cut-outs under the fur, read at the mesh uv as the colour maps are: without face_cut_map
  // cut_maps[0] cuts every face; with it base face f is cut by cut_maps[face_cut_map[f]] (kNoFurCut:
  // none), a fin by its edge's first face's (set_fin_cuts).
  const FurCutMap* cut_maps = nullptr;
  size_t cut_map_count = 0;
  const uint32_t* face_cut_map = nullptr;
  raster::Filter map_filter = raster::Filter::Trilinear;  // of the colour maps and cut-outs
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
  // Fins with face_cut_map: each fin quad's cut-out, as face_cut_map holds them.
  void set_fin_cuts(const uint32_t* quad_cut) { quad_cut_ = quad_cut; }
  // Per-vertex lighting arrives as FurGreyVaryings (else FurVaryings); per frame, as above.
  void set_grey_lighting(bool grey) { grey_ = grey; }
  // The varying slot of the mesh uv (with a colour map or a cut-out): after the frame's lighting layout.
  void set_map_uv_slot(int slot) { map_uv_slot_ = slot; }
  void shade(const raster::FragmentBatch& batch) const override;

 private:
  // The texels of the per-face maps `map_at(m)` (m < count) under the batch's covered lanes into
  // out, 1 where a face has none (face_map's `none`) or its map no texture: one map for every face
  // without face_map, else face f's is face_map[f] and a fin quad's quad_map's. Leaves each lane's
  // map in the scratch's lane_map when face_map is given.
  template <class MapAt>
  void sample_face_maps(const raster::FragmentBatch& b, size_t count, const uint32_t* face_map,
                        const uint32_t* quad_map, uint32_t none, MapAt map_at, float* const out[4]) const;
  // Zeroes `alpha` where the batch's lanes lie over a cut-out (FurCutMap).
  void apply_cuts(const raster::FragmentBatch& b, float* alpha) const;

  FurShaderSetup s_;
  std::vector<shading::Light> lights_;
  float eye_[3] = {0, 0, 0};
  const float* quad_weight_ = nullptr;
  const uint32_t* quad_map_ = nullptr;
  const uint32_t* quad_cut_ = nullptr;
  bool grey_ = false;
  int map_uv_slot_ = 0;
};

}  // namespace pelt::render
