#include "tools/render/fur_object.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "tools/io/alpha_mode.h"
#include "tools/io/input_error.h"
#include "tools/render/animation.h"
#include "tools/render/varyings.h"

namespace pelt::render {
namespace {

// Rows of the per-vertex lighting SoA: inputs, then the kernel's output for a white and
// for a black texel (their difference is the light that multiplies the strand colour).
enum SoaRow : int { kPosRow = 0, kTangentRow = 3, kNormalRow = 6, kHeightRow = 9, kOnes = 10,
                    kZeros = 14, kLitWhite = 18, kLitBlack = 22, kSoaRows = 26 };

// Fins whose fade is below this are not drawn at all (they would round to nothing in
// 8 bits): most edges are far from a silhouette.
constexpr float kMinFinWeight = 1.0f / 512.0f;

// The tile sort keys a fin's quads in runs of this many (root to tip) by their mean depth, so
// a run's triangles follow each other and pack into shared blocks (DrawCall::sort_group).
// Measured on frame 0 of the shipped fur scenes (box, teapot, teapot2, bunny), against quads
// keyed alone: runs of 3 quads shade 4-10 % fewer lanes a frame for 1-2 % more RMSE against
// the exact sort; runs of 5, 1.5-2 % fewer again for 4-8 % more; a whole 15-quad fin, whose
// root and tip lie at different depths, doubled the box's error. A run must not straddle two
// fins (a straddling run shares no edge and falls back to per-triangle keys), so it divides
// the fin's quad count.
uint32_t fin_quads_per_sort_run(uint32_t quads) {
  for (uint32_t run : {3u, 2u})
    if (quads % run == 0) return run;
  return 1;
}

// The optional blocks, compared with animation.h's field-by-field equality.
bool same(const std::vector<shading::Light>& a, const std::vector<shading::Light>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].type != b[i].type || std::memcmp(a[i].vec, b[i].vec, sizeof(a[i].vec)) != 0 ||
        std::memcmp(a[i].color, b[i].color, sizeof(a[i].color)) != 0)
      return false;
  return true;
}


raster::SamplerState fur_sampler(bool fin, raster::Filter filter) {
  raster::SamplerState s;
  s.filter = filter;
  s.wrap_u = raster::Wrap::Repeat;
  // Fin texture rows run root (t = 0) to tip (t = 1): clamped, as the harness does.
  s.wrap_v = fin ? raster::Wrap::Clamp : raster::Wrap::Repeat;
  return s;
}

// A fur field's error located in the scene: the file, and the field's JSON path under the object.
[[noreturn]] void throw_fur_error(const FurOrigin& origin, const std::string& field, const std::string& reason) {
  const std::string fur_field = "fur." + field;
  throw io::InputError(origin.file, origin.object_path.empty() ? fur_field : origin.object_path + "." + fur_field,
                       reason);
}

void throw_if(const std::optional<raster::TextureError>& e, const FurOrigin& origin) {
  if (e) throw_fur_error(origin, e->field, e->reason);
}

}  // namespace

FurObject::FurObject(const Mesh& base, const fur::FurParams& params, const FurDrawOptions& options,
                     const FurOrigin& origin, FrameStats& setup)
    : params_(params),
      match_llvmpipe_(options.match_llvmpipe),
      lighting_(options.lighting),
      filter_(options.filter),
      double_precision_(options.double_precision),
      grey_allowed_(options.grey_varyings),
      fins_(params.fins != fur::FinMode::off),
      merge_fins_(options.merge_fins && !options.match_llvmpipe && fins_) {
  if (params.use_color_map) {
    if (options.color_maps.empty())
      throw_fur_error(origin, "use_color_map",
                      "true needs a colour map on the object (material.color_map, or a map its mesh names: glTF "
                      "baseColorTexture, MTL map_Kd), and it has none");
    color_maps_ = options.color_maps;
    face_color_map_ = options.face_color_map;
    const bool faces_named = face_color_map_.empty() ? color_maps_.size() == 1
                                                     : face_color_map_.size() == base.triangle_count();
    if (!faces_named ||
        std::any_of(face_color_map_.begin(), face_color_map_.end(),
                    [&](uint32_t m) { return m != kNoFurColorMap && m >= color_maps_.size(); }))
      throw std::invalid_argument("FurObject: face_color_map must give each base face one of the colour maps, or none");
  }
  cut_maps_ = options.cut_maps;
  face_cut_map_ = options.face_cut_map;
  if (!cut_maps_.empty() &&
      (!(face_cut_map_.empty() ? cut_maps_.size() == 1 : face_cut_map_.size() == base.triangle_count()) ||
       std::any_of(face_cut_map_.begin(), face_cut_map_.end(),
                   [&](uint32_t m) { return m != kNoFurCut && m >= cut_maps_.size(); })))
    throw std::invalid_argument("FurObject: face_cut_map must give each base face one of the cut-outs, or none");
  settle_mapless_cuts(base.triangle_count());
  const bool cut_by_map = !cut_maps_.empty();  // every cut-out left reads a map
  mesh_uvs_ = !color_maps_.empty() || cut_by_map;
  const std::vector<glm::vec2>& map_uvs = options.map_uvs.empty() ? base.uvs : options.map_uvs;
  if (cut_by_map && map_uvs.size() != base.positions.size())
    throw std::invalid_argument("FurObject: a cut-out's map needs one texture coordinate per mesh vertex");
  {
    StageTimer t(setup, "fur_geometry");
    if (auto e = fur::build_fur_geometry(base, params, geo_, options.length_scale,
                                         cut_by_map ? std::span<const glm::vec2>(map_uvs) : std::span<const glm::vec2>()))
      throw_fur_error(origin, e->field, e->reason);
    for (size_t f = 0; f < face_gone_.size(); ++f)
      if (face_gone_[f]) fur::collapse_face_shells(geo_, f);  // as a bald face's
  }
  if (options.textures && !all_gone_) {
    StageTimer t(setup, "fur_textures");
    fur::StrandTextures tex;
    if (match_llvmpipe_) {
      tex = fur::match_llvmpipe_textures(fur::ShellForms::LuminanceOnly);
    } else if (auto e = fur::generate_strand_textures(params, tex, fur::ShellForms::LuminanceOnly)) {
      throw_fur_error(origin, e->field, e->reason);
    }
    // Brightness and alpha with a tint per layer: the sampler's La8 path. The harness's shells
    // too: their colour is a layer colour times a brightness, so only L's rounding (at most
    // 0.63/255 of a channel) separates level 0 from its bytes; the levels above differ more
    // anyway (pelt's alpha-weighted mip chain, not glGenerateMipmap's plain average).
    const fur::ShellLuminance& lum = tex.shell_luminance;
    throw_if(raster::TextureArray::from_la8_layers(lum.size, lum.size, lum.layers, lum.la.data(), shell_tex_,
                                                   options.parallel),
             origin);
    shell_tint_ = lum.tint;
    // The fin likewise, with a tint linear in the fin's height v (fur::FinLuminance); none
    // without fins.
    if (fins_) {
      const fur::FinLuminance& fin_lum = tex.fin_luminance;
      throw_if(raster::Texture::from_la8(fin_lum.size, fin_lum.size, fin_lum.la.data(), fin_tex_, options.parallel),
               origin);
      fin_tint_root_ = fin_lum.tint_root;
      fin_tint_slope_ = fin_lum.tint_slope;
    }
  }
  // Nothing of a mesh cut away whole is ever drawn: update() makes nothing for it, so it keeps
  // no poses, tangents, light or varyings either (some 200 bytes a fur vertex).
  if (all_gone_) return;
  const size_t v = geo_.positions.size();
  pose_ = geo_.positions;
  gravity_pose_ = geo_.positions;
  tangents_.resize(v);
  wind_forces_.resize(geo_.base_vertex_count);
  const int vc = (lighting_ == FurLighting::pixel ? FurPixelVaryings::kCount : FurVaryings::kCount) +
                 (mesh_uvs_ ? FurMapUv::kCount : 0);
  shell_varyings_.resize(v * vc);
  if (fins_) {
    fin_varyings_.resize(v * vc);
    fin_weight_.assign(geo_.edges.size(), 1.0f);
  }
  if (lighting_ == FurLighting::vertex) {
    light_soa_.stride = (v + 15) / 16 * 16;
    light_soa_.storage.assign(light_soa_.stride * kSoaRows + 16, 0.0f);
    auto addr = reinterpret_cast<uintptr_t>(light_soa_.storage.data());
    light_soa_.base = light_soa_.storage.data() + ((64 - addr % 64) % 64) / sizeof(float);
    for (int c = 0; c < 4; ++c) std::fill_n(light_soa_.row(kOnes + c), light_soa_.stride, 1.0f);
  }
  // The static parts of the per-pixel varyings: uvs never change. (Per-vertex lighting
  // writes its uvs with the light, in the frame's layout.)
  if (lighting_ == FurLighting::pixel)
    for (size_t i = 0; i < v; ++i) {
      const int uv = FurPixelVaryings::kUv;
      shell_varyings_[i * vc + uv] = geo_.shell_uvs[i].x;
      shell_varyings_[i * vc + uv + 1] = geo_.shell_uvs[i].y;
      if (!fins_) continue;
      fin_varyings_[i * vc + uv] = geo_.fin_uvs[i].x;
      fin_varyings_[i * vc + uv + 1] = geo_.fin_uvs[i].y;
    }
  if (lighting_ == FurLighting::pixel && mesh_uvs_) write_mesh_uvs(vc);
}

void FurObject::settle_mapless_cuts(size_t faces) {
  // A cut-out without a map tests the factor alone (MaterialShader), the same at every fragment:
  // it keeps all of its faces or none. Faces it keeps need no test; faces it cuts away grow no
  // fur at all, so nothing of theirs is drawn, where their shells and fins used to be
  // rasterized, shaded and zeroed fragment by fragment. The cut-outs that read a map stay, renumbered.
  if (cut_maps_.empty()) return;
  std::vector<uint32_t> renumber(cut_maps_.size(), kNoFurCut);
  std::vector<FurCutMap> kept;
  for (size_t m = 0; m < cut_maps_.size(); ++m)
    if (cut_maps_[m].map.texture) {
      renumber[m] = static_cast<uint32_t>(kept.size());
      kept.push_back(cut_maps_[m]);
    }
  auto cuts_away = [&](uint32_t m) {
    if (m == kNoFurCut) return false;  // checked first: cut_maps_[kNoFurCut] lies far past the end
    const FurCutMap& c = cut_maps_[m];
    return !c.map.texture && !io::mask_keeps(1.0f, c.factor, c.cutoff);
  };
  face_gone_.assign(faces, 0);
  size_t gone = 0;
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t m = face_cut_map_.empty() ? 0u : face_cut_map_[f];
    face_gone_[f] = cuts_away(m);
    gone += face_gone_[f];
    if (!face_cut_map_.empty() && m != kNoFurCut) face_cut_map_[f] = renumber[m];
  }
  all_gone_ = faces > 0 && gone == faces;
  if (gone == 0) face_gone_.clear();
  cut_maps_ = std::move(kept);
  if (cut_maps_.empty()) face_cut_map_.clear();
}

void FurObject::write_mesh_uvs(int stride) {
  const int at = stride - FurMapUv::kCount;
  const size_t n = geo_.base_vertex_count;
  for (size_t i = 0; i < pose_.size(); ++i) {
    const glm::vec2 uv = geo_.mesh_uvs[i % n];
    for (std::vector<float>* dst : {&shell_varyings_, fins_ ? &fin_varyings_ : nullptr}) {
      if (!dst) continue;
      (*dst)[i * stride + at] = uv.x;
      (*dst)[i * stride + at + 1] = uv.y;
    }
  }
}

uint64_t FurObject::triangles() const {
  return geo_.shell_indices.size() / 3 + geo_.fin_indices.size() / 3;
}

size_t FurObject::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t n = bytes(geo_.positions) + bytes(geo_.shell_uvs) + bytes(geo_.fin_uvs) + bytes(geo_.layer) +
             bytes(geo_.shell_indices) + bytes(geo_.fin_indices) + bytes(geo_.edges) +
             bytes(gravity_pose_) + bytes(wind_pose_) + bytes(pose_) + bytes(tangents_) +
             bytes(shell_varyings_) + bytes(fin_varyings_) + bytes(fin_list_) + bytes(light_soa_.storage) +
             bytes(pose_clip_) + bytes(shell_keys_) + bytes(geo_.mesh_uvs) + bytes(geo_.length_scale) +
             bytes(face_color_map_) + bytes(fin_quad_map_) + bytes(cut_maps_) + bytes(face_cut_map_) +
             bytes(fin_quad_cut_) + bytes(face_gone_);
  for (const raster::Texture& t : shell_tex_.layers) n += t.bytes();
  return n + fin_tex_.bytes();
}

void FurObject::rebuild_pose(float t) {
  const uint32_t n = geo_.base_vertex_count, s = geo_.layers;
  // At t = 0 the frame shows the gravity pose alone; the wind pose may be stale or unmade.
  if (t == 0.0f) {
    pose_ = gravity_pose_;
  } else {
    fur::lerp_poses(gravity_pose_, wind_pose_, t, pose_);
  }
  fur::strand_tangents(pose_, geo_.growth, n, s, tangents_, 0, n);
}

void FurObject::light_vertices(const std::vector<shading::Light>& lights, const glm::vec3& eye) {
  Soa& a = light_soa_;
  const uint32_t n = geo_.base_vertex_count;
  const float inv_top = geo_.layers > 1 ? 1.0f / float(geo_.layers - 1) : 0.0f;
  for (size_t i = 0; i < pose_.size(); ++i) {
    const glm::vec3& nrm = geo_.base_normals[i % n];
    for (int k = 0; k < 3; ++k) {
      a.row(kPosRow + k)[i] = pose_[i][k];
      a.row(kTangentRow + k)[i] = tangents_[i][k];
      a.row(kNormalRow + k)[i] = nrm[k];
    }
    a.row(kHeightRow)[i] = float(geo_.layer[i]) * inv_top;
  }
  shading::FurSurfaceSoA surf{};
  surf.n = a.stride;
  for (int k = 0; k < 3; ++k) {
    surf.pos[k] = a.row(kPosRow + k);
    surf.tangent[k] = a.row(kTangentRow + k);
    surf.normal[k] = a.row(kNormalRow + k);
  }
  surf.height = a.row(kHeightRow);
  for (int pass = 0; pass < 2; ++pass) {
    for (int c = 0; c < 4; ++c) surf.texel[c] = a.row((pass == 0 ? kOnes : kZeros) + c);
    shading::FurOutSoA out{};
    for (int c = 0; c < 4; ++c) out.rgba[c] = a.row((pass == 0 ? kLitWhite : kLitBlack) + c);
    if (match_llvmpipe_) {
      const glm::vec3 l = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
      const float dir[3] = {l.x, l.y, l.z};
      (double_precision_ ? shading::shade_fur_match_llvmpipe_reference : shading::shade_fur_match_llvmpipe)(
          dir, surf, out);
    } else {
      const float e[3] = {eye.x, eye.y, eye.z};
      (double_precision_ ? shading::shade_fur_reference : shading::shade_fur)(light_params_, lights.data(),
                                                                              lights.size(), e, surf, out);
    }
  }
}

int FurObject::lighting_varying_count() const {
  return lighting_ == FurLighting::pixel ? FurPixelVaryings::kCount
         : grey_                         ? FurGreyVaryings::kCount
                                         : FurVaryings::kCount;
}

int FurObject::varying_count() const {
  return lighting_varying_count() + (mesh_uvs_ ? FurMapUv::kCount : 0);
}

void FurObject::rebuild_varyings() {
  const size_t count = pose_.size();
  if (lighting_ == FurLighting::vertex) {
    Soa& a = light_soa_;
    auto diffuse = [&](int c, size_t i) { return a.row(kLitWhite + c)[i] - a.row(kLitBlack + c)[i]; };
    auto specular = [&](int c, size_t i) { return a.row(kLitBlack + c)[i]; };
    grey_ = grey_allowed_;
    for (size_t i = 0; i < count && grey_; ++i)
      grey_ = diffuse(0, i) == diffuse(1, i) && diffuse(0, i) == diffuse(2, i) && specular(0, i) == specular(1, i) &&
              specular(0, i) == specular(2, i);
    // Either layout packs the vertices' records from the array's start, so the (static) uvs
    // are rewritten only when the layout changes: the first frame, or a light turning grey
    // or coloured.
    const int stride = varying_count();
    const int channels = grey_ ? 1 : 3;
    const int spec = grey_ ? FurGreyVaryings::kSpecular : FurVaryings::kSpecular;
    static_assert(FurGreyVaryings::kUv == FurVaryings::kUv && FurGreyVaryings::kDiffuse == FurVaryings::kDiffuse);
    const bool write_uvs = stride != uv_stride_;
    uv_stride_ = stride;
    if (write_uvs && mesh_uvs_) write_mesh_uvs(stride);
    for (size_t i = 0; i < count; ++i) {
      float* sv = shell_varyings_.data() + i * stride;
      if (write_uvs) {
        sv[FurVaryings::kUv] = geo_.shell_uvs[i].x;
        sv[FurVaryings::kUv + 1] = geo_.shell_uvs[i].y;
      }
      for (int c = 0; c < channels; ++c) {
        sv[FurVaryings::kDiffuse + c] = diffuse(c, i);
        sv[spec + c] = specular(c, i);
      }
      if (!fins_) continue;
      float* fv = fin_varyings_.data() + i * stride;
      if (write_uvs) {
        fv[FurVaryings::kUv] = geo_.fin_uvs[i].x;
        fv[FurVaryings::kUv + 1] = geo_.fin_uvs[i].y;
      }
      for (int c = 0; c < channels; ++c) {
        fv[FurVaryings::kDiffuse + c] = diffuse(c, i);
        fv[spec + c] = specular(c, i);
      }
    }
    return;
  }
  using P = FurPixelVaryings;
  const uint32_t n = geo_.base_vertex_count;
  const float inv_top = geo_.layers > 1 ? 1.0f / float(geo_.layers - 1) : 0.0f;
  for (size_t i = 0; i < count; ++i) {
    const glm::vec3& p = pose_[i];
    const glm::vec3& t = tangents_[i];
    const glm::vec3& nrm = geo_.base_normals[i % n];
    const float h = float(geo_.layer[i]) * inv_top;
    const size_t at = i * size_t(varying_count());
    for (float* dst : {shell_varyings_.data() + at, fins_ ? fin_varyings_.data() + at : nullptr}) {
      if (!dst) continue;
      dst[P::kPos] = p.x, dst[P::kPos + 1] = p.y, dst[P::kPos + 2] = p.z;
      dst[P::kTangent] = t.x, dst[P::kTangent + 1] = t.y, dst[P::kTangent + 2] = t.z;
      dst[P::kHeight] = h;
      dst[P::kNormal] = nrm.x, dst[P::kNormal + 1] = nrm.y, dst[P::kNormal + 2] = nrm.z;
    }
  }
}

void FurObject::rebuild_fin_list() {
  const uint32_t edges = static_cast<uint32_t>(geo_.edges.size());
  fin_list_.clear();
  fin_quad_weight_.clear();
  fin_quad_map_.clear();
  fin_quad_cut_.clear();
  const bool maps = !face_color_map_.empty(), cuts = !face_cut_map_.empty();
  auto add_map = [&](uint32_t e) {
    if (maps) fin_quad_map_.push_back(face_color_map_[geo_.edges[e].face0]);
    if (cuts) fin_quad_cut_.push_back(face_cut_map_[geo_.edges[e].face0]);
  };
  auto quad = [&](uint32_t s, uint32_t e) -> const uint32_t* {
    return geo_.fin_indices.data() + (size_t{s} * edges + e) * 6;
  };
  if (fin_strips_) {
    // Each fin root to tip: one quad per pair of layers, or merged (fur/fin_spans.h) from the
    // chains' breaks, which update() works out whenever the pose moves, before any draw. Room
    // for every quad unmerged, so that a pose that merges less never allocates mid-run.
    const uint32_t n = geo_.base_vertex_count, layers = geo_.layers;
    fin_list_.reserve(size_t{edges} * (layers - 1) * 6);
    fin_quad_weight_.reserve(size_t{edges} * (layers - 1));
    if (maps) fin_quad_map_.reserve(size_t{edges} * (layers - 1));
    if (cuts) fin_quad_cut_.reserve(size_t{edges} * (layers - 1));
    fin_ends_.resize(layers);
    uint32_t* ends = fin_ends_.data();
    uint32_t count = layers - 1;
    for (uint32_t s = 0; s < count; ++s) ends[s] = s + 1;
    for (uint32_t e = 0; e < edges; ++e) {
      if (fin_weight_[e] < kMinFinWeight || edge_gone(e)) continue;
      const fur::FurEdge& edge = geo_.edges[e];
      if (merge_fins_)
        count = fur::fin_quad_ends(pose_, n, layers, edge.a, edge.b, fin_breaks_, fin_tolerance(), ends);
      for (uint32_t k = 0, s0 = 0; k < count; s0 = ends[k++]) {
        uint32_t q[6];
        fur::fin_quad_indices(edge, n, s0, ends[k], q);
        fin_list_.insert(fin_list_.end(), q, q + 6);
        fin_quad_weight_.push_back(fin_weight_[e]);
        add_map(e);
      }
    }
    return;
  }
  fin_segment_.assign(geo_.layers, 0);
  for (uint32_t s = 0; s + 1 < geo_.layers; ++s) {
    fin_segment_[s] = static_cast<uint32_t>(fin_quad_weight_.size());
    for (uint32_t e = 0; e < edges; ++e) {
      if (fin_weight_[e] < kMinFinWeight || edge_gone(e)) continue;
      fin_list_.insert(fin_list_.end(), quad(s, e), quad(s, e) + 6);
      fin_quad_weight_.push_back(fin_weight_[e]);
      add_map(e);
    }
  }
  fin_segment_[geo_.layers - 1] = static_cast<uint32_t>(fin_quad_weight_.size());
}

void FurObject::update(const FurFrame& f, const std::vector<shading::Light>& lights,
                       FrameStats& stats) {
  const uint32_t n = geo_.base_vertex_count, s = geo_.layers;
  sort_ = f.sort;
  clip_from_world_ = f.clip_from_world;
  if (all_gone_) return;  // nothing is drawn: no pose, light or fin list to make
  // The sorts the rasterizer orders (per tile or per pixel) take each fin root to tip as a
  // strip; the others draw layer by layer.
  const bool strips = raster_sort_mode(f.sort) != raster::SortMode::None;
  if (strips != fin_strips_ && fins_) {
    fin_strips_ = strips;
    fin_list_dirty_ = true;
  }
  float t = 0.0f;
  if (match_llvmpipe_) {
    if (!llvmpipe_poses_made_) {
      // The harness's two precomputed arrays (its P0 and P1) stand for both poses.
      StageTimer st(stats, "gravity");
      wind_pose_.resize(pose_.size());
      fur::llvmpipe_poses(geo_, gravity_pose_, wind_pose_);
      llvmpipe_poses_made_ = true;
      poses_dirty_ = true;
    }
    t = fur::llvmpipe_animation_t(f.frame);
  } else {
    const ForceStep step = forces_.next(f.gravity, f.wind, f.time_seconds, f.still);
    if (step.gravity) {
      if (step.gravity_bends) {
        StageTimer st(stats, "gravity");
        // The authored count keeps the bend of the scene's fur when a quality setting
        // re-slices it (fur/dynamics.h).
        fur::apply_gravity(geo_.positions, geo_.base_normals, n, s, uint32_t(params_.authored_shells),
                           *f.gravity, fur::GravityLaw::lever, gravity_pose_, 0, n);
      } else {
        gravity_pose_ = geo_.positions;
      }
      poses_dirty_ = true;
    }
    if (step.wind) {
      StageTimer st(stats, "wind");
      fur::update_wind_field(geo_, *f.wind, wind_field_);
      wind_field_.forces(step.wind_time, wind_forces_, 0, n);
      wind_pose_.resize(pose_.size());
      fur::apply_wind(gravity_pose_, geo_.growth, geo_.base_normals, wind_forces_, n, s, wind_pose_, 0, n);
      poses_dirty_ = true;
    }
    t = step.t;
  }
  bool varyings_dirty = false;
  if (poses_dirty_ || !pose_t_ || *pose_t_ != t) {
    StageTimer st(stats, "fur_pose");
    rebuild_pose(t);
    keyed_clip_.reset();
    pose_t_ = t;
    poses_dirty_ = false;
    lighting_dirty_ = true;
    varyings_dirty = true;
    if (merge_fins_) {  // where the chains run straight has moved: the merged fin list with it
      const uint32_t words = fur::fin_break_words(geo_.layers);
      fin_breaks_.resize(size_t{n} * words);
      fur::fin_chain_breaks(pose_, n, geo_.layers, fin_tolerance(), fur::kMaxFinSpan, 0, n, fin_breaks_);
      fin_list_dirty_ = true;
    }
  }
  if (lighting_ == FurLighting::vertex &&
      (lighting_dirty_ || !lit_eye_ || *lit_eye_ != f.eye || !lit_lights_ || !same(*lit_lights_, lights))) {
    StageTimer st(stats, "fur_lighting");
    light_vertices(lights, f.eye);
    lit_eye_ = f.eye;
    lit_lights_ = lights;
    lighting_dirty_ = false;
    varyings_dirty = true;
  }
  if (varyings_dirty) {
    StageTimer st(stats, "fur_pose");
    rebuild_varyings();
  }
  // Silhouette weights depend on the eye alone (and the rest mesh's faces); the list of drawn
  // fins on the weights and, for merged fins, on the pose. Each is remade only when its own
  // inputs moved: a pose that moves under a still camera rebuilds the list, not the weights.
  const bool weights_stale = params_.fins == fur::FinMode::silhouette && (!fins_eye_ || *fins_eye_ != f.eye);
  if (fins_ && (weights_stale || fin_list_dirty_)) {
    StageTimer st(stats, "fins");
    if (weights_stale) {
      for (size_t e = 0; e < geo_.edges.size(); ++e) {
        const fur::FurEdge& edge = geo_.edges[e];
        const glm::vec3 mid = 0.5f * (geo_.positions[edge.a] + geo_.positions[edge.b]);
        const glm::vec3 view = glm::normalize(f.eye - mid);
        std::optional<glm::vec3> nb;
        if (edge.face1 != fur::kNoFace) nb = geo_.face_normals[edge.face1];
        fin_weight_[e] = fur::fin_weight(geo_.face_normals[edge.face0], nb, view, params_.fins);
      }
      fins_eye_ = f.eye;
    }
    rebuild_fin_list();
    fin_list_dirty_ = false;
  }
  // A subpixel jitter of the projection (supersampling) moves no key: depths are w, and the
  // lean on screen is a difference of positions.
  if (f.sort == FurSort::surface && (!keyed_clip_ || *keyed_clip_ != f.clip_from_world)) {
    StageTimer st(stats, "fur_sort");
    if (!surface_order_) surface_order_.emplace(geo_);
    pose_clip_.resize(pose_.size());
    for (size_t i = 0; i < pose_.size(); ++i) pose_clip_[i] = f.clip_from_world * glm::vec4(pose_[i], 1.0f);
    surface_order_->compute(pose_clip_, shell_keys_);
    keyed_clip_ = f.clip_from_world;
  }
  prepare_shaders(lights, f.eye);
}

raster::SortMode raster_sort_mode(FurSort sort) {
  switch (sort) {
    case FurSort::tile:
    case FurSort::surface: return raster::SortMode::Tile;  // surface: with the fur's own keys
    case FurSort::exact: return raster::SortMode::Exact;
    case FurSort::none:
    case FurSort::layer: break;
  }
  return raster::SortMode::None;
}

void FurObject::prepare_shaders(const std::vector<shading::Light>& lights, const glm::vec3& eye) {
  const FurSort sort = sort_;
  const uint32_t faces = static_cast<uint32_t>(geo_.counts.base_faces);
  // One shader per draw (the layer order splits shells and fins into per-layer draws);
  // built once per sort mode, only their per-frame inputs change.
  const size_t want = sort == FurSort::layer ? 2 * geo_.layers - 1 : 2;
  if (shaders_.size() != want) {
    shaders_.clear();
    for (size_t k = 0; k < want; ++k) {
      FurShaderSetup su;
      const bool fin = sort == FurSort::layer ? (k % 2 == 1) : (k == 1);
      su.fins = fin;
      su.shells = &shell_tex_;
      su.shell_tint = shell_tint_.data();
      su.fin = &fin_tex_;
      su.fin_tint_root = fin_tint_root_;
      su.fin_tint_slope = fin_tint_slope_;
      su.sampler = fur_sampler(fin, filter_);
      su.double_precision = double_precision_;
      su.base_faces = faces;
      su.primitive_offset = (sort == FurSort::layer && !fin) ? uint32_t(k / 2) * faces : 0;
      su.per_pixel_lighting = lighting_ == FurLighting::pixel;
      su.match_llvmpipe = match_llvmpipe_;
      su.llvmpipe_light = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
      su.color_maps = color_maps_.data();  // placed as the base surface reads them (MaterialShader)
      su.color_map_count = color_maps_.size();
      su.face_color_map = face_color_map_.empty() ? nullptr : face_color_map_.data();
      su.cut_maps = cut_maps_.data();  // placed as the base surface reads them too
      su.cut_map_count = cut_maps_.size();
      su.face_cut_map = face_cut_map_.empty() ? nullptr : face_cut_map_.data();
      su.map_filter = filter_;
      shaders_.push_back(std::make_unique<FurShader>(su));
    }
  }
  // Silhouette fins fade by their edge's weight, looked up per quad; the others are drawn whole.
  // In the layer order each layer's fin shader maps its primitives into the whole fin list.
  const float* weight = params_.fins == fur::FinMode::silhouette ? fin_quad_weight_.data() : nullptr;
  for (size_t k = 0; k < shaders_.size(); ++k) {
    FurShader& sh = *shaders_[k];
    sh.set_view(lights, eye);
    sh.set_fins(weight && sort == FurSort::layer && k % 2 == 1 ? weight + fin_segment_[k / 2] : weight);
    const uint32_t* quad_map = fin_quad_map_.empty() ? nullptr : fin_quad_map_.data();
    sh.set_fin_maps(quad_map && sort == FurSort::layer && k % 2 == 1 ? quad_map + fin_segment_[k / 2] : quad_map);
    const uint32_t* quad_cut = fin_quad_cut_.empty() ? nullptr : fin_quad_cut_.data();
    sh.set_fin_cuts(quad_cut && sort == FurSort::layer && k % 2 == 1 ? quad_cut + fin_segment_[k / 2] : quad_cut);
    sh.set_grey_lighting(grey_);
    sh.set_map_uv_slot(lighting_varying_count());
  }
}

void FurObject::append_draws(std::vector<raster::DrawCall>& draws) const {
  const FurSort sort = sort_;
  const uint32_t faces = static_cast<uint32_t>(geo_.counts.base_faces);
  if (all_gone_) return;
  const bool fins = fins_ && !fin_quad_weight_.empty();
  auto draw = [&](bool fin, uint32_t first_tri, uint32_t count, const FurShader* sh) {
    if (count == 0) return;
    raster::DrawCall d;
    d.positions = pose_.data();
    // Fins keep their mean-depth keys: keyed after the shells at their root layer instead, the
    // shipped scenes' silhouette fins measured further from the exact sort (README).
    if (sort == FurSort::surface && !fin && shell_keys_.size() == geo_.shell_indices.size() / 3)
      d.sort_keys = shell_keys_.data() + first_tri;
    d.vertex_count = static_cast<uint32_t>(pose_.size());
    d.indices = (fin ? fin_list_.data() : geo_.shell_indices.data()) + 3 * size_t{first_tri};
    d.triangle_count = count;
    d.varyings = fin ? fin_varyings_.data() : shell_varyings_.data();
    d.varying_count = static_cast<uint32_t>(varying_count());
    d.clip_from_object = clip_from_world_;
    d.shader = sh;
    d.state.blend = raster::BlendMode::AlphaOver;
    d.state.depth_func = raster::DepthFunc::LessEqual;  // shell 0 lies exactly on the base
    d.state.depth_write = false;
    d.state.cull = fin ? raster::CullMode::None : raster::CullMode::Back;
    // A merged quad is keyed alone: it already spans up to fur::kMaxFinSpan layers.
    if (fin && fin_strips_) d.sort_group = merge_fins_ ? 2 : 2 * fin_quads_per_sort_run(geo_.layers - 1);
    draws.push_back(d);
  };
  if (sort == FurSort::layer) {
    for (uint32_t s = 0; s < geo_.layers; ++s) {
      draw(false, s * faces, faces, shaders_[2 * s].get());
      if (fins && s + 1 < geo_.layers)
        draw(true, 2 * fin_segment_[s], 2 * (fin_segment_[s + 1] - fin_segment_[s]), shaders_[2 * s + 1].get());
    }
  } else {
    draw(false, 0, static_cast<uint32_t>(geo_.shell_indices.size() / 3), shaders_[0].get());
    if (fins) draw(true, 0, static_cast<uint32_t>(fin_list_.size() / 3), shaders_[1].get());
  }
}

}  // namespace pelt::render
