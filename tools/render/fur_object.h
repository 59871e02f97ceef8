// One furry object: its shared shell/fin vertex array (eq. 1), strand textures, and the
// poses that animate it. Every piece is built or recomputed only when the scene asks for
// it and its inputs changed; the frame's stats say which stages ran.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>

#include "fur/dynamics.h"
#include "fur/fin_spans.h"
#include "fur/fur_geometry.h"
#include "fur/fur_params.h"
#include "fur/strand_textures.h"
#include "fur/surface_order.h"
#include "raster/mesh.h"
#include "raster/pipeline.h"
#include "raster/renderer.h"
#include "raster/texture.h"
#include "tools/io/quality.h"
#include "tools/render/force_schedule.h"
#include "tools/render/frame_stats.h"
#include "shading/fur_lighting.h"
#include "tools/render/fur_shader.h"

namespace pelt::render {

// Order of the translucent fur triangles: the quality knob itself (io::SortQuality, whose
// values say what each order does), not a copy of it to keep in step.
using FurSort = io::SortQuality;

// The rasterizer's order for the fur's: per tile for `tile` and `surface` (the latter with the
// fur's own keys, DrawCall::sort_keys), per pixel for `exact`, none for `none` and `layer`,
// whose order is the draws' own.
raster::SortMode raster_sort_mode(FurSort sort);

// Where strand lighting is evaluated.
enum class FurLighting {
  vertex,  // once per fur vertex, interpolated (default: lighting is smooth over a shell)
  pixel,   // Kajiya-Kay per fragment
};

// How a furry object is drawn, fixed for its lifetime.
struct FurDrawOptions {
  bool match_llvmpipe = false;  // the llvmpipe harness's scene (textures, poses, lighting)
  FurLighting lighting = FurLighting::vertex;
  raster::Filter filter = raster::Filter::Trilinear;  // strand and fin textures
  bool double_precision = false;  // lighting and texture sampling by the double references
  // Per-vertex lighting that is grey everywhere is passed as FurGreyVaryings (the same image
  // from half the varyings); off: always FurVaryings (for tests and measurements).
  bool grey_varyings = true;
  // The `fin_quads: merged` quality: in the tile and exact sorts, a fin's quads span several
  // layers where its chains run straight (fur/fin_spans.h). Off: one quad per pair of layers,
  // as eq. 1 lists them. Never with match_llvmpipe, whose fins are the harness's.
  bool merge_fins = false;
  // The object's colour maps (its material's, or those its mesh names), read by fur whose
  // params ask for it (FurParams::use_color_map); such fur without one is refused. One map and no
  // face_color_map: every face's. Otherwise (faces of materials that draw several maps, or some
  // none): base face f's is color_maps[face_color_map[f]], or none (kNoFurColorMap, the strands
  // untinted); a fin takes its edge's first face's.
  std::vector<FurColorMap> color_maps;
  std::vector<uint32_t> face_color_map;  // one per base face, or empty
  // The cut-outs of the surface under the fur (its mesh file's alphaMode MASK parts): strands are
  // not drawn where it is cut away. One and no face_cut_map: every face's. Otherwise base face f's
  // is cut_maps[face_cut_map[f]], or none (kNoFurCut); a fin takes its edge's first face's. A
  // cut-out without a map (its factor alone) keeps its faces whole or cuts them away whole: the
  // latter draw nothing at all (no shell or fin of theirs reaches the rasterizer).
  std::vector<FurCutMap> cut_maps;
  std::vector<uint32_t> face_cut_map;  // one per base face, or empty
  // One per mesh vertex: the texture coordinates a cut-out's map is read at, for a caller that hands
  // the fur its mesh without uvs (to lay the strands by the box mapping). Empty: the mesh's own.
  std::vector<glm::vec2> map_uvs;
  // One per mesh vertex, in [0, 1] (fur.length_map, read by the caller): the fur's length there
  // as a fraction of params.length (fur::build_fur_geometry). Empty: the full length everywhere.
  std::vector<float> length_scale;
  // Builds the strand textures' layers as its items (the render's threads); none: in order.
  raster::ParallelFor parallel;
  // Off: the fur is never drawn (the depth and id AOVs, a describe-only set-up), so its strand
  // textures are not generated; the object then serves geometry() and counts only.
  bool textures = true;
};

// Where a furry object's fur block sits in its scene, so that a bad field is reported as the
// project reports input errors: "FILE: objects[3].fur.comb.field: REASON".
struct FurOrigin {
  std::string file;         // the scene file (empty for a scene parsed from a string)
  std::string object_path;  // the object's JSON path, "objects[3]"
};

// What may change from frame to frame.
struct FurFrame {
  int frame = 0;
  double time_seconds = 0.0;
  bool still = false;  // the scene has no animation: the wind pose, not a point of the swing
  FurSort sort = FurSort::tile;  // the order append_draws draws in (the fin list's layout follows it)
  glm::vec3 eye{0.0f};
  glm::mat4 clip_from_world{1.0f};  // the camera (projection * view): the draws' and the surface sort's
  std::optional<fur::WindParams> wind;
  std::optional<fur::GravityParams> gravity;
};

class FurObject {
 public:
  // `base` is the object's mesh in world space. options.match_llvmpipe reproduces the
  // llvmpipe harness's scene (textures, poses, animation, lighting) for side-by-side timing.
  // Records "fur_geometry" and "fur_textures" in `setup`. Throws io::InputError with
  // origin.file as its file and "<origin.object_path>.fur.<field>" as its field when the
  // parameters cannot be built.
  FurObject(const Mesh& base, const fur::FurParams& params, const FurDrawOptions& options,
            const FurOrigin& origin, FrameStats& setup);

  // Brings poses, tangents, lighting, varyings and fins up to date for `f` seen under
  // `lights`; records the "gravity", "wind", "fur_pose", "fur_lighting", "fins" and
  // "fur_sort" stages that ran. Which poses are made again is ForceSchedule's decision: gravity
  // that bends nothing and wind of strength 0 are none, frames that differ only in time are
  // not re-simulated, and a frame at rest in the swing pushes no wind.
  void update(const FurFrame& f, const std::vector<shading::Light>& lights, FrameStats& stats);

  // Appends the shell and fin draws (after the opaque base) as of the last update(): its
  // camera, lights and eye, in its sort order.
  void append_draws(std::vector<raster::DrawCall>& draws) const;

  const fur::FurGeometry& geometry() const { return geo_; }
  // With FurDrawOptions::face_color_map, each fin quad's colour map (its edge's first face's), in
  // the order of the fin draws' quads as of the last update(); otherwise empty.
  const std::vector<uint32_t>& fin_quad_maps() const { return fin_quad_map_; }
  // Likewise each fin quad's cut-out with FurDrawOptions::face_cut_map.
  const std::vector<uint32_t>& fin_quad_cuts() const { return fin_quad_cut_; }
  // Floats per vertex of the fur draws' varyings as of the last update().
  int varying_count() const;
  uint64_t triangles() const;
  // Bytes held by this object's arrays and textures (for `pelt info`).
  size_t memory_bytes() const;

 private:
  void rebuild_pose(float t);
  void light_vertices(const std::vector<shading::Light>& lights, const glm::vec3& eye);
  // The draws' shaders for the frame's sort (built when the sort changes) and their per-frame
  // inputs: lights, eye, fin weights.
  void prepare_shaders(const std::vector<shading::Light>& lights, const glm::vec3& eye);
  // The lighting layout's own floats per vertex, before the mesh uv that a colour map or a
  // cut-out's map adds.
  int lighting_varying_count() const;
  void rebuild_varyings();
  // The mesh uvs into both varying arrays' records of `stride` floats, as their last two.
  void write_mesh_uvs(int stride);
  void rebuild_fin_list();
  // Sets face_gone_ and all_gone_ from the cut-outs without a map, and leaves in cut_maps_ and
  // face_cut_map_ only those that read one.
  void settle_mapless_cuts(size_t faces);
  bool edge_gone(uint32_t e) const { return !face_gone_.empty() && face_gone_[geo_.edges[e].face0]; }
  // How far a merged fin may stray from the per-layer one (fur/fin_spans.h), scene units.
  float fin_tolerance() const { return fur::kFinSpanTolerance * geo_.layer_distance; }

  fur::FurParams params_;
  bool match_llvmpipe_;
  FurLighting lighting_;
  raster::Filter filter_;
  bool double_precision_;
  bool grey_allowed_;
  bool fins_;  // params_.fins is not off: the fin texture, varyings and list exist
  bool grey_ = false;  // this frame's varyings are FurGreyVaryings
  std::vector<FurColorMap> color_maps_;  // read at the mesh uvs (FurMapUv) when any
  std::vector<uint32_t> face_color_map_;  // FurDrawOptions::face_color_map
  std::vector<uint32_t> fin_quad_map_;    // with face_color_map_: each fin quad's (its edge's face0's)
  std::vector<FurCutMap> cut_maps_;       // FurDrawOptions::cut_maps
  std::vector<uint32_t> face_cut_map_;    // FurDrawOptions::face_cut_map
  std::vector<uint32_t> fin_quad_cut_;    // with face_cut_map_: each fin quad's (its edge's face0's)
  // Per base face, 1 where a cut-out without a map cuts it away whole (its shells are single
  // points, its edges' fins are not listed; a fin takes its edge's first face's cut); empty when
  // none is. all_gone_: every face is, and the object draws nothing, makes nothing per frame and
  // holds no per-frame arrays (poses, varyings, light).
  std::vector<uint8_t> face_gone_;
  bool all_gone_ = false;
  bool mesh_uvs_ = false;  // a colour map or a cut-out's map is read at the mesh uvs (FurMapUv)
  int uv_stride_ = 0;  // the record stride the uvs in the varying arrays were written for (0: none yet)
  shading::FurLightParams light_params_;
  fur::FurGeometry geo_;
  raster::TextureArray shell_tex_;
  std::vector<glm::vec3> shell_tint_;  // per layer: colour = min(1, tint * L) of the La8 shells
  raster::Texture fin_tex_;            // La8: colour = min(1, (fin_tint_root_ + fin_tint_slope_ v) * L)
  glm::vec3 fin_tint_root_{0.0f}, fin_tint_slope_{0.0f};

  std::vector<glm::vec3> gravity_pose_, wind_pose_, pose_, tangents_, wind_forces_;
  fur::WindField wind_field_;
  std::vector<float> shell_varyings_, fin_varyings_;
  std::vector<float> fin_weight_;           // per edge
  // Fins drawn this frame: all of them, or (silhouette) those with a visible weight; the weight
  // of each quad's edge (per quad, so that the shader looks it up with one load a lane). In
  // layer-then-edge order (FurSort none and layer), with where each layer's
  // segment starts, or (fin_strips_: tile and exact) each fin's quads root to tip, a strip
  // whose triangles share edges one after the other, so that the tiles pack them into
  // shared blocks.
  std::vector<uint32_t> fin_list_, fin_segment_;
  std::vector<float> fin_quad_weight_;
  bool fin_strips_ = false;
  bool merge_fins_;
  std::vector<uint64_t> fin_breaks_;  // merge_fins_: per base vertex, fur::fin_chain_breaks of pose_
  std::vector<uint32_t> fin_ends_;    // one fin's fur::fin_quad_ends
  // FurSort::surface: the shells' keys from the pose in clip space, made by update() when the
  // pose or the camera moves (nullopt: not made for the current pose).
  std::optional<fur::SurfaceOrder> surface_order_;
  std::vector<glm::vec4> pose_clip_;
  std::vector<float> shell_keys_;
  std::optional<glm::mat4> keyed_clip_;

  // Per-vertex lighting: SoA inputs and outputs padded to whole 16-lane batches.
  struct Soa {
    std::vector<float> storage;  // over-allocated so rows can start on 64-byte boundaries
    float* base = nullptr;
    size_t stride = 0;  // floats per row, a multiple of 16
    float* row(int k) { return base + size_t(k) * stride; }
  } light_soa_;
  std::optional<std::vector<shading::Light>> lit_lights_;
  std::optional<glm::vec3> lit_eye_;
  bool lighting_dirty_ = true;

  // Which poses a frame makes (the inputs the current ones were made from).
  ForceSchedule forces_;
  bool llvmpipe_poses_made_ = false;  // match_llvmpipe: the harness's two arrays, made once
  std::optional<float> pose_t_;
  std::optional<glm::vec3> fins_eye_;
  bool fin_list_dirty_ = true;
  bool poses_dirty_ = true;
  FurSort sort_ = FurSort::tile;  // the last update()'s
  glm::mat4 clip_from_world_{1.0f};  // the last update()'s

  std::vector<std::unique_ptr<FurShader>> shaders_;
};

}  // namespace pelt::render
