#include "tools/render/fur_shader.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "raster/config.h"
#include "shading/fur_vertex_lit.h"
#include "tools/io/alpha_mode.h"
#include "tools/render/texture_sampling.h"
#include "tools/render/varyings.h"

namespace pelt::render {
namespace {

constexpr size_t kLanes = raster::kMaxBatchLanes;

struct alignas(64) Scratch {
  alignas(64) float texel[4][kLanes];
  alignas(64) float map[4][kLanes];  // the colour map's texels (use_color_map)
  alignas(64) float part[4][kLanes];  // one of several colour maps' texels, at its lanes
  uint32_t lane_map[kLanes];           // each lane's colour map (several)
  uint32_t present[kLanes];            // the maps the batch's lanes take, each once
  uint16_t mask[raster::kMaxBatchBlocks];
  alignas(64) float tint[3][raster::kMaxBatchBlocks];  // per block: its layer's tint (shells)
};
thread_local Scratch tls_scratch;

}  // namespace

raster::Texture cut_alpha_texture(const raster::Texture& map, const raster::ParallelFor& parallel) {
  const int w = map.width(), h = map.height();
  std::vector<uint8_t> la(size_t(w) * size_t(h) * 2);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = (size_t(y) * size_t(w) + size_t(x)) * 2;
      la[i] = uint8_t(map.texel(0, x, y) >> 24);
      la[i + 1] = 255;
    }
  raster::Texture out;
  if (const auto e = raster::Texture::from_la8(w, h, la.data(), out, parallel))
    throw std::logic_error("cut_alpha_texture: " + e->message());  // the map's own size was accepted
  return out;
}

void FurShader::set_view(const std::vector<shading::Light>& lights, const glm::vec3& eye) {
  lights_ = lights;
  eye_[0] = eye.x;
  eye_[1] = eye.y;
  eye_[2] = eye.z;
}

template <class MapAt>
void FurShader::sample_face_maps(const raster::FragmentBatch& b, size_t count, const uint32_t* face_map,
                                 const uint32_t* quad_map, uint32_t none, MapAt map_at, float* const out[4]) const {
  Scratch& s = tls_scratch;
  const size_t n = size_t{b.blocks} * raster::kBlockLanes;
  const float* u = b.varying[map_uv_slot_];
  const float* v = b.varying[map_uv_slot_ + 1];
  if (!face_map) {  // one map, every face's
    const FurColorMap& m = map_at(0);
    if (m.texture) {
      sample_placed(*m.texture, m.placement, s_.map_filter, u, v, n, out, s_.double_precision, b.mask);
    } else {
      for (int c = 0; c < 4; ++c) std::fill_n(out[c], n, 1.0f);
    }
    return;
  }
  // Per face: each lane's map from its face (a shell's base face, a fin quad's edge), then each
  // map sampled at its own lanes alone. A block may hold lanes of two maps (triangles of one
  // layer sharing an edge across a material border); each lane's level of detail is still its
  // block's, so a lane samples as it would with its map alone.
  for (uint32_t k = 0; k < b.blocks; ++k) {
    const uint32_t* prim = b.primitive + size_t{k} * raster::kBlockLanes;
    uint32_t* lane = s.lane_map + size_t{k} * raster::kBlockLanes;
    if (s_.fins) {
      for (uint32_t l = 0; l < raster::kBlockLanes; ++l)
        lane[l] = quad_map ? quad_map[(prim[l] + s_.primitive_offset) / 2] : none;
      continue;
    }
    // A block's lanes lie on one layer (shade's runs): one division a block finds its first
    // triangle, and a lane's base face is its triangle less that.
    const uint32_t first = (prim[0] + s_.primitive_offset) / s_.base_faces * s_.base_faces;
    for (uint32_t l = 0; l < raster::kBlockLanes; ++l) {
      const uint32_t face = prim[l] + s_.primitive_offset - first;
      lane[l] = face < s_.base_faces ? face_map[face] : none;  // an uncovered lane's
    }
  }
  for (int c = 0; c < 4; ++c) std::fill_n(out[c], n, 1.0f);  // a face of no map: times 1
  // The maps the batch's lanes take, each once: a mesh of many materials samples only those.
  size_t present = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t m = s.lane_map[i];
    if (m == none || (present > 0 && s.present[present - 1] == m)) continue;
    if (std::find(s.present, s.present + present, m) == s.present + present) s.present[present++] = m;
  }
  float* const part[4] = {s.part[0], s.part[1], s.part[2], s.part[3]};
  for (size_t j = 0; j < present; ++j) {
    const uint32_t m = s.present[j];
    if (m >= count || !map_at(m).texture) continue;
    const FurColorMap& map = map_at(m);
    bool any = false;
    for (uint32_t k = 0; k < b.blocks; ++k) {
      uint32_t bits = 0;
      for (uint32_t l = 0; l < raster::kBlockLanes; ++l) bits |= uint32_t(s.lane_map[k * raster::kBlockLanes + l] == m) << l;
      s.mask[k] = uint16_t(bits & b.mask[k]);
      any |= s.mask[k] != 0;
    }
    if (!any) continue;
    sample_placed(*map.texture, map.placement, s_.map_filter, u, v, n, part, s_.double_precision, s.mask);
    for (int c = 0; c < 4; ++c)
      for (size_t i = 0; i < n; ++i)
        if (s.lane_map[i] == m) out[c][i] = part[c][i];
  }
}

void FurShader::apply_cuts(const raster::FragmentBatch& b, float* alpha) const {
  Scratch& s = tls_scratch;
  const size_t n = size_t{b.blocks} * raster::kBlockLanes;
  float* const cut[4] = {s.map[0], s.map[1], s.map[2], s.map[3]};
  sample_face_maps(b, s_.cut_map_count, s_.face_cut_map, quad_cut_, kNoFurCut,
                   [&](uint32_t m) -> const FurColorMap& { return s_.cut_maps[m].map; }, cut);
  // The surface's own test (MaterialShader): kept where the map's alpha (the luminance of
  // cut_alpha_texture) times the factor reaches the cutoff. A lane of no cut-out, or of one
  // without a map, reads 1.
  const float* a = cut[0];
  if (!s_.face_cut_map) {
    const float f = s_.cut_maps[0].factor, cutoff = s_.cut_maps[0].cutoff;
    for (size_t i = 0; i < n; ++i) alpha[i] = io::mask_keeps(a[i], f, cutoff) ? alpha[i] : 0.0f;
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    const uint32_t m = s.lane_map[i];
    if (m == kNoFurCut) continue;
    alpha[i] = io::mask_keeps(a[i], s_.cut_maps[m].factor, s_.cut_maps[m].cutoff) ? alpha[i] : 0.0f;
  }
}

void FurShader::shade(const raster::FragmentBatch& b) const {
  Scratch& s = tls_scratch;
  const size_t n = size_t{b.blocks} * raster::kBlockLanes;
  const int uv_slot = s_.per_pixel_lighting ? FurPixelVaryings::kUv : FurVaryings::kUv;
  const float* u = b.varying[uv_slot];
  const float* v = b.varying[uv_slot + 1];
  // With per-vertex lighting the alpha is sampled straight into the output, and the three
  // colour channels of the luminance shells and fin (La8: all equal) into texel[0] alone.
  const bool vertex_lit = !s_.per_pixel_lighting;
  const bool one_channel = vertex_lit && s_.color_map_count == 0;
  float* const alpha = vertex_lit ? b.out[3] : s.texel[3];
  float* const texel_out[4] = {s.texel[0], one_channel ? s.texel[0] : s.texel[1],
                               one_channel ? s.texel[0] : s.texel[2], alpha};

  // Texture: the fin texture for the whole batch, or per run of blocks on one shell layer;
  // only the covered lanes (the others read 0, and the colour below stays finite there).
  // A block holds lanes of one triangle or of triangles sharing edges (pipeline.h), and a
  // shell triangle shares vertices only with triangles of its own layer (eq. 1: layer s
  // owns vertices s N .. s N + N - 1), so lane 0's layer is the block's.
  if (s_.fins) {
    sample_texture(*s_.fin, s_.sampler, u, v, n, texel_out, s_.double_precision, b.mask);
  } else {
    const uint32_t layers = static_cast<uint32_t>(s_.shells->layers.size());
    auto layer_of = [&](uint32_t block) {
      return std::min(layers - 1, (b.primitive[block * raster::kBlockLanes] + s_.primitive_offset) / s_.base_faces);
    };
    uint32_t i = 0;
    while (i < b.blocks) {
      const uint32_t layer = layer_of(i);
      // The run goes on while its blocks' triangles lie in the layer's range [first, end): a
      // compare a block, where layer_of's division was a fifth of this function's time.
      const uint32_t first = layer * s_.base_faces;
      const bool last = layer + 1 == layers;  // layer_of puts every triangle above it in the last layer
      const uint32_t end = last ? 0 : first + s_.base_faces;
      uint32_t j = i + 1;
      for (; j < b.blocks; ++j) {
        const uint32_t p = b.primitive[j * raster::kBlockLanes] + s_.primitive_offset;
        if (p < first || (!last && p >= end)) break;
      }
      const size_t off = size_t{i} * raster::kBlockLanes;
      float* const run_out[4] = {texel_out[0] + off, texel_out[1] + off, texel_out[2] + off, texel_out[3] + off};
      const size_t run = size_t{j - i} * raster::kBlockLanes;
      sample_texture(s_.shells->layers[layer], s_.sampler, u + off, v + off, run, run_out, s_.double_precision,
                     b.mask + i);
      for (uint32_t k = i; k < j; ++k)
        for (int c = 0; c < 3; ++c) s.tint[c][k] = s_.shell_tint[layer][c];
      i = j;
    }
  }
  if (s_.color_map_count > 0) {
    // Every channel of the strand texel (La8: all equal) times the map's colour under it.
    float* const map_out[4] = {s.map[0], s.map[1], s.map[2], s.map[3]};
    sample_face_maps(b, s_.color_map_count, s_.face_color_map, quad_map_, kNoFurColorMap,
                     [&](uint32_t m) -> const FurColorMap& { return s_.color_maps[m]; }, map_out);
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < n; ++i) texel_out[c][i] *= s.map[c][i];
  }
  if (s_.fins && quad_weight_) {
    // Per lane: a block may hold the quads of several fins. (Looked up through the quad's edge,
    // two dependent loads a lane, this was about 1.5 % of a teapot:5 frame.)
    for (size_t i = 0; i < n; ++i) alpha[i] *= quad_weight_[(b.primitive[i] + s_.primitive_offset) / 2];
  }
  if (s_.cut_map_count > 0) apply_cuts(b, alpha);

  // Colour = min(1, tint * texel): per block the layer's tint for the luminance shells, per lane
  // a tint from the fin's height v (root to tip) for the luminance fin.
  if (vertex_lit) {
    // colour = min(1, tint * texel) * diffuse + specular per channel; a luminance shell's three
    // texel channels are one array, as are a grey light's three values (FurGreyVaryings).
    shading::FurVertexLitSoA lit;
    lit.blocks = b.blocks;
    if (s_.fins) {  // the fin's colour runs from root to tip: a tint per lane from its height v
      lit.height = v;
      for (int c = 0; c < 3; ++c) {
        lit.tint_root[c] = s_.fin_tint_root[c];
        lit.tint_slope[c] = s_.fin_tint_slope[c];
      }
    }
    for (int c = 0; c < 3; ++c) {
      lit.texel[c] = texel_out[c];
      lit.tint[c] = s.tint[c];
      lit.diffuse[c] = b.varying[grey_ ? FurGreyVaryings::kDiffuse : FurVaryings::kDiffuse + c];
      lit.specular[c] = b.varying[grey_ ? FurGreyVaryings::kSpecular : FurVaryings::kSpecular + c];
      lit.out[c] = b.out[c];
    }
    shading::shade_fur_vertex_lit(lit);
    return;
  }
  if (!s_.fins)
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < n; ++i) s.texel[c][i] = std::min(1.0f, s.texel[c][i] * s.tint[c][i / raster::kBlockLanes]);
  else
    for (int c = 0; c < 3; ++c)  // the vertex-lit kernel's per-lane tint
      for (size_t i = 0; i < n; ++i)
        s.texel[c][i] =
            std::min(1.0f, s.texel[c][i] * shading::height_tint(s_.fin_tint_root[c], s_.fin_tint_slope[c], v[i]));
  using P = FurPixelVaryings;
  shading::FurSurfaceSoA surf{};
  surf.n = n;
  for (int k = 0; k < 3; ++k) {
    surf.pos[k] = b.varying[P::kPos + k];
    surf.tangent[k] = b.varying[P::kTangent + k];
    surf.normal[k] = b.varying[P::kNormal + k];
  }
  surf.height = b.varying[P::kHeight];
  for (int c = 0; c < 4; ++c) surf.texel[c] = s.texel[c];
  shading::FurOutSoA out{};
  for (int c = 0; c < 4; ++c) out.rgba[c] = b.out[c];
  if (s_.match_llvmpipe) {
    const float l[3] = {s_.llvmpipe_light.x, s_.llvmpipe_light.y, s_.llvmpipe_light.z};
    (s_.double_precision ? shading::shade_fur_match_llvmpipe_reference : shading::shade_fur_match_llvmpipe)(
        l, surf, out);
  } else {
    (s_.double_precision ? shading::shade_fur_reference : shading::shade_fur)(s_.light_params, lights_.data(),
                                                                              lights_.size(), eye_, surf, out);
  }
}

}  // namespace pelt::render
