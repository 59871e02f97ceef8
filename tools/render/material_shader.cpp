#include "tools/render/material_shader.h"

#include <algorithm>

#include "raster/config.h"
#include "shading/normal_map.h"
#include "shading/skin_kernels.h"
#include "tools/render/texture_sampling.h"
#include "tools/render/varyings.h"

namespace pelt::render {
namespace {

constexpr size_t kLanes = raster::kMaxBatchLanes;

// Per-thread scratch for the arrays a batch needs beyond the rasterizer's: albedo and the
// per-layer outputs. Fixed size: no allocation per batch.
struct alignas(64) Scratch {
  alignas(64) float albedo[3][kLanes];
  alignas(64) float texel[4][kLanes];
  alignas(64) float layers[9][kLanes];
  alignas(64) float normal[3][kLanes];  // the normal-mapped shading normal
  alignas(64) float alpha[kLanes];      // the colour map's alpha, when the material draws it
};
thread_local Scratch tls_scratch;

}  // namespace

MaskCuts mask_cuts(const MaterialDesc& d) {
  if (d.alpha_mode != io::AlphaMode::mask) return MaskCuts::nothing;
  float least = 1.0f, most = 1.0f, margin = 0.0f;
  if (d.color_map) {
    uint32_t lo = 255, hi = 0;
    for (int y = 0; y < d.color_map->height(); ++y)
      for (int x = 0; x < d.color_map->width(); ++x) {
        const uint32_t a = d.color_map->texel(0, x, y) >> 24;
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
    least = float(lo) / 255.0f, most = float(hi) / 255.0f, margin = 1e-3f;
  }
  if (io::mask_keeps(std::max(0.0f, least - margin), d.alpha_factor, d.alpha_cutoff)) return MaskCuts::nothing;
  if (!io::mask_keeps(std::min(1.0f, most + margin), d.alpha_factor, d.alpha_cutoff)) return MaskCuts::everything;
  return MaskCuts::some;
}

MaterialShader::MaterialShader(const MaterialDesc& desc, std::vector<shading::Light> lights,
                               glm::vec3 eye, SkinLayer layer)
    : desc_(desc), lights_(std::move(lights)), eye_{eye.x, eye.y, eye.z}, layer_(layer) {}

void MaterialShader::set_view(const std::vector<shading::Light>& lights, const glm::vec3& eye) {
  lights_ = lights;
  eye_[0] = eye.x;
  eye_[1] = eye.y;
  eye_[2] = eye.z;
}

void MaterialShader::shade(const raster::FragmentBatch& b) const {
  Scratch& s = tls_scratch;
  const size_t n = size_t{b.blocks} * raster::kBlockLanes;
  using V = SurfaceVaryings;
  // Skin takes its colours from SkinParams: its albedo is the colour map alone.
  const glm::vec3 base = desc_.kind == MaterialKind::skin ? glm::vec3(1.0f) : desc_.color;
  const bool draws_alpha = desc_.alpha_mode == io::AlphaMode::blend || desc_.mask_cuts != MaskCuts::nothing;
  if (desc_.color_map) {
    float* const texel[4] = {s.texel[0], s.texel[1], s.texel[2], s.texel[3]};
    sample_placed(*desc_.color_map, desc_.color_placement, desc_.filter, b.varying[V::kUv], b.varying[V::kUv + 1], n,
                  texel, desc_.double_precision);
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < n; ++i) s.albedo[c][i] = base[c] * s.texel[c][i];
    if (draws_alpha) std::copy(s.texel[3], s.texel[3] + n, s.alpha);  // the normal map reuses texel
  } else {
    for (int c = 0; c < 3; ++c) std::fill(s.albedo[c], s.albedo[c] + n, base[c]);
  }

  shading::SurfaceSoA surf{};
  surf.n = n;
  for (int k = 0; k < 3; ++k) {
    surf.pos[k] = b.varying[V::kPos + k];
    surf.normal[k] = b.varying[V::kNormal + k];
    surf.albedo[k] = s.albedo[k];
  }
  if (desc_.normal_map) {
    float* const texel[4] = {s.texel[0], s.texel[1], s.texel[2], s.texel[3]};
    sample_placed(*desc_.normal_map, desc_.normal_placement, desc_.filter, b.varying[V::kUv], b.varying[V::kUv + 1],
                  n, texel, desc_.double_precision);
    const shading::NormalMapSoA frame{n,
                                      {b.varying[V::kNormal], b.varying[V::kNormal + 1], b.varying[V::kNormal + 2]},
                                      {b.varying[desc_.tangent_slot], b.varying[desc_.tangent_slot + 1],
                                       b.varying[desc_.tangent_slot + 2], b.varying[desc_.tangent_slot + 3]},
                                      {s.texel[0], s.texel[1], s.texel[2]}};
    float* const normal[3] = {s.normal[0], s.normal[1], s.normal[2]};
    (desc_.double_precision ? shading::perturb_normals_reference : shading::perturb_normals)(frame, normal);
    for (int k = 0; k < 3; ++k) surf.normal[k] = s.normal[k];
  }
  const bool blurred = desc_.kind == MaterialKind::skin &&
                       desc_.skin.multiple_scattering == shading::MultipleScattering::normal_blur;
  if (blurred)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) surf.blurred_normal[c][k] = b.varying[V::kBlurred + 3 * c + k];

  shading::ShadeOutSoA out{};
  for (int c = 0; c < 3; ++c) out.rgb[c] = b.out[c];
  out.alpha = b.out[3];
  const float* const* picked = nullptr;
  float* layer_ptr[3][3];
  if (desc_.kind == MaterialKind::skin && layer_ != SkinLayer::all) {
    for (int l = 0; l < 3; ++l)
      for (int c = 0; c < 3; ++c) layer_ptr[l][c] = s.layers[3 * l + c];
    for (int c = 0; c < 3; ++c) {
      out.sebum[c] = layer_ptr[0][c];
      out.epidermis[c] = layer_ptr[1][c];
      out.dermis[c] = layer_ptr[2][c];
    }
    picked = layer_ptr[layer_ == SkinLayer::sebum ? 0 : layer_ == SkinLayer::epidermis ? 1 : 2];
  }

  const shading::Light* lights = lights_.data();
  const size_t lc = lights_.size();
  const bool dbl = desc_.double_precision;
  switch (desc_.kind) {
    case MaterialKind::unlit:
      (dbl ? shading::shade_unlit_reference : shading::shade_unlit)(lights, lc, eye_, surf, out);
      break;
    case MaterialKind::lambert:
      (dbl ? shading::shade_lambert_reference : shading::shade_lambert)(lights, lc, eye_, surf, out);
      break;
    case MaterialKind::blinn:
      (dbl ? shading::shade_blinn_reference : shading::shade_blinn)(desc_.basic, lights, lc, eye_, surf, out);
      break;
    case MaterialKind::skin:
      (dbl ? shading::shade_skin_reference : shading::shade_skin)(desc_.skin, lights, lc, eye_, surf, out);
      break;
  }
  if (picked)
    for (int c = 0; c < 3; ++c) std::copy(picked[c], picked[c] + n, b.out[c]);
  if (draws_alpha) {
    const float f = desc_.alpha_factor, cut = desc_.alpha_cutoff;
    // Without a colour map the alpha is the factor alone.
    const float* const map = desc_.color_map ? s.alpha : nullptr;
    if (desc_.alpha_mode == io::AlphaMode::mask && desc_.translucent())
      for (size_t i = 0; i < n; ++i) b.out[3][i] = io::mask_keeps(map ? map[i] : 1.0f, f, cut) ? b.out[3][i] : 0.0f;
    else
      for (size_t i = 0; i < n; ++i) b.out[3][i] *= f * (map ? map[i] : 1.0f);
  }
  // The skin shader returns colour premultiplied by Opacity (RenderMan's Ci = Oi * ...), the
  // rasterizer blends a straight source colour (AlphaOver multiplies it by alpha): undo the
  // premultiplication once, or a translucent skin layer would count its opacity twice. Opacity 0 gives alpha 0, which blends to nothing.
  const float op = desc_.skin.Opacity;
  if (desc_.kind == MaterialKind::skin && op > 0.0f && op < 1.0f) {
    const float inv = 1.0f / op;
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < n; ++i) b.out[c][i] *= inv;
  }
}

}  // namespace pelt::render
