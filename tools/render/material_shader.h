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

namespace pelt::render {

enum class MaterialKind { unlit, lambert, blinn, skin };

// Which term a skin material writes: the full colour, or one layer of the paper's
// multi-layer rendering (the per-layer AOVs).
enum class SkinLayer { all, sebum, epidermis, dermis };

struct MaterialDesc {
  MaterialKind kind = MaterialKind::lambert;
  glm::vec3 color{0.8f};              // albedo of the basic materials
  shading::BasicParams basic;         // blinn
  shading::SkinParams skin;           // skin
  const raster::Texture* color_map = nullptr;  // sampled at the uv varying (v = 0: top row)
  raster::Filter filter = raster::Filter::Trilinear;  // of the colour map
  bool double_precision = false;  // shading and sampling by the double references
};

class MaterialShader final : public raster::Shader {
 public:
  MaterialShader(const MaterialDesc& desc, std::vector<shading::Light> lights, glm::vec3 eye,
                 SkinLayer layer = SkinLayer::all);
  void shade(const raster::FragmentBatch& batch) const override;
  bool uses_derivatives() const override { return desc_.color_map != nullptr; }
  // Lights and eye for the next frames; call between renders, never during one.
  void set_view(const std::vector<shading::Light>& lights, const glm::vec3& eye);

 private:
  MaterialDesc desc_;
  std::vector<shading::Light> lights_;
  float eye_[3];
  SkinLayer layer_;
};

}  // namespace pelt::render
