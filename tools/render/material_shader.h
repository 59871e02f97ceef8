// Opaque materials as rasterizer shaders: turns a FragmentBatch of SurfaceVaryings into
// the shading library's SoA batch and calls its kernel (Lambert, Blinn, unlit, skin).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "raster/pipeline.h"
#include "raster/texture.h"
#include "shading/basic_params.h"
#include "shading/light.h"
#include "shading/skin_params.h"
#include "tools/io/alpha_mode.h"
#include "tools/io/map_placement.h"

namespace pelt::render {

enum class MaterialKind { unlit, lambert, blinn, skin };

// Which term a skin material writes: the full colour, or one layer of the paper's
// multi-layer rendering (the per-layer AOVs).
enum class SkinLayer { all, sebum, epidermis, dermis };

// What a MASK part's test does over its whole colour map (mask_cuts, below).
enum class MaskCuts { nothing, everything, some };

struct MaterialDesc {
  MaterialKind kind = MaterialKind::lambert;
  glm::vec3 color{0.8f};              // albedo of the basic materials
  shading::BasicParams basic;         // blinn
  shading::SkinParams skin;           // skin
  const raster::Texture* color_map = nullptr;  // sampled at the uv varying (v = 0: top row)
  // Tangent-space normal map (linear texels) and the first of the 4 varyings holding the
  // vertex tangent frame (xyz, handedness; raster/mesh.h compute_vertex_tangents).
  const raster::Texture* normal_map = nullptr;
  int tangent_slot = -1;
  // Where the mesh file places each map (wraps, uv transform); the tangent frame is the
  // normal map's own, taken from the uvs its placement transforms.
  io::MapPlacement color_placement, normal_placement;
  raster::Filter filter = raster::Filter::Trilinear;  // of the colour and normal maps
  // A mesh file's material's alpha (glTF alphaMode): under mask or blend the output alpha is
  // multiplied by alpha_factor and by the colour map's alpha (a texture that keeps it), and
  // the draw tests (mask) or blends it (raster::PipelineState). A translucent material's
  // draws blend already: there the shader itself cuts a mask, keeping its own alpha where the
  // map's alpha times the factor reaches alpha_cutoff and writing 0 elsewhere.
  io::AlphaMode alpha_mode = io::AlphaMode::opaque;
  float alpha_cutoff = 0.5f;
  float alpha_factor = 1.0f;
  // What the part's MASK test cuts (mask_cuts of this desc, worked out once its map is loaded;
  // nothing under OPAQUE and BLEND, which have no test): a part cut nowhere is drawn opaque, its
  // alpha neither read nor tested, one cut everywhere is not drawn (the fur's cut-outs read it too).
  MaskCuts mask_cuts = MaskCuts::nothing;
  bool double_precision = false;  // shading and sampling by the double references

  // A skin of Opacity below 1: drawn blended (AlphaOver, no depth write).
  bool translucent() const { return kind == MaterialKind::skin && skin.Opacity < 1.0f; }
};

// What a MASK part's test does over its whole colour map: a map whose alphas all lie on one side of
// the cutoff cuts everything or nothing (exporters mark opaque textures MASK), and then neither its
// surface nor its fur need read it. Every filtered sample lies between the least and the most alpha
// of level 0 (each level's texels are rounded averages of level 0's), less a margin for the
// samples' rounding. Without a map the alpha is the factor alone: everything or nothing. Nothing
// without alphaMode MASK. Reads every texel of level 0: for set-up (MaterialDesc::mask_cuts).
MaskCuts mask_cuts(const MaterialDesc& desc);

class MaterialShader final : public raster::Shader {
 public:
  MaterialShader(const MaterialDesc& desc, std::vector<shading::Light> lights, glm::vec3 eye,
                 SkinLayer layer = SkinLayer::all);
  void shade(const raster::FragmentBatch& batch) const override;
  bool uses_derivatives() const override { return desc_.color_map != nullptr || desc_.normal_map != nullptr; }
  // Lights and eye for the next frames; call between renders, never during one.
  void set_view(const std::vector<shading::Light>& lights, const glm::vec3& eye);

 private:
  MaterialDesc desc_;
  std::vector<shading::Light> lights_;
  float eye_[3];
  SkinLayer layer_;
};

}  // namespace pelt::render
