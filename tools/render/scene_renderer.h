// Builds a frame pipeline from a scene and renders its frames: only the stages the scene
// calls for are built (fur for furry objects, wind only with wind, blurred normals only
// for normal_blur skin), and per-frame work is redone only when its inputs change.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "raster/renderer.h"
#include "tools/io/budget.h"
#include "tools/io/quality.h"
#include "tools/io/map_placement.h"
#include "tools/io/scene.h"
#include "tools/render/animation.h"
#include "tools/render/budget_check.h"
#include "tools/render/frame_stats.h"
#include "tools/render/fur_object.h"
#include "tools/render/material_shader.h"

namespace pelt::render {

enum class Aov { color, depth, id, overdraw, sebum, epidermis, dermis };

// The AOVs of one value per pixel rather than a colour: point-sampled (no supersampling), never
// written to a GIF; one channel in EXR (float) and TIFF (depth float, id and overdraw 32-bit
// unsigned), and overdraw also as a PNG heat map (overdraw_heatmap.h).
inline bool per_pixel_value(Aov a) { return a == Aov::depth || a == Aov::id || a == Aov::overdraw; }
// Whether fur can change the AOV: the depth and id images are the opaque surfaces' alone, and
// fur (translucent, no depth write) changes neither, so there its poses, lighting and draws
// are skipped (its geometry is still built, so a bad fur block is reported whatever the AOV).
inline bool aov_shows_fur(Aov a) { return a != Aov::depth && a != Aov::id; }
// The skin shader's layers (MaterialShader): a skin material draws one of them alone.
inline bool skin_layer(Aov a) { return a == Aov::sebum || a == Aov::epidermis || a == Aov::dermis; }

struct RenderSettings {
  int width = 0, height = 0;  // 0: the scene's image size
  int threads = 1;
  // The quality knobs (tools/io/quality.h); unset: the scene's own `quality` block.
  std::optional<io::Quality> quality;
  io::Budget budget;
  Aov aov = Aov::color;
  bool match_llvmpipe = false;      // fur as the llvmpipe harness draws it (bench fps)
  FurLighting fur_lighting = FurLighting::vertex;
  bool fur_grey_varyings = true;    // FurDrawOptions::grey_varyings (off: tests, measurements)
  // The colour AOV as RGBA8 UNORM bytes (FrameImage::color8, raster::unorm8 of each channel)
  // instead of floats: a frame that only has to reach memory, as bench fps draws it.
  bool color8 = false;
  // `pelt info`: the scene is built to be described, not drawn. The set-up that can take
  // minutes is estimated instead of run (the normal blur's searches: its pairs are counted on
  // 64 sampled vertices and checked against the budget); render() refuses to draw.
  bool describe_only = false;
  // What the frames are written as, for the image buffers the memory estimate counts (a
  // sequence's two by default: `pelt render` says when it writes a still or a GIF).
  ImageOutput output = ImageOutput::sequence;
};

// The scene as a quality setting draws it: `shells` and `fins` replace every fur block's,
// `multiple_scattering` and `single_scattering` every skin material's, and the reference's
// exact physics sets exact Fresnel and the correct phase function. The other knobs act at
// render time.
io::Scene apply_quality(const io::Scene& scene, const io::Quality& q);

// Sub-pixel offsets of `spp` = n x n stratified samples (stratum centres), in pixels from the
// pixel centre, each coordinate in (-0.5, 0.5). Row-major, the order they are accumulated in.
std::vector<glm::vec2> sample_offsets(int spp);

// The planes of one rendered frame, row 0 at the top. Only the AOV asked for is filled.
struct FrameImage {
  int width = 0, height = 0;
  std::vector<float> color;     // RGBA linear, colour premultiplied by alpha (with RenderSettings::color8 only
                                // when supersampled)
  std::vector<uint8_t> color8;  // RenderSettings::color8: RGBA8 UNORM of the linear (premultiplied) colour
  std::vector<float> depth;     // window depth, 1 = background
  std::vector<uint32_t> id;     // scene triangle index + 1, 0 = background
  std::vector<uint32_t> overdraw;  // translucent fragments that passed the depth test (raster::RenderTarget)
};

class SceneRenderer {
 public:
  // Loads meshes and builds everything the scene needs once. Throws io::InputError for
  // bad input. The set-up stages' times are reported in the first frame's stats.
  SceneRenderer(const io::Scene& scene, const RenderSettings& settings);
  // The same with meshes already loaded (one per scene object, in order): for benchmarks
  // and tools that generate geometry. Their load time is not reported.
  SceneRenderer(const io::Scene& scene, std::vector<io::SceneMesh> meshes,
                const RenderSettings& settings);
  ~SceneRenderer();

  // Renders frame `frame` (0-based) of the scene's animation. Deterministic: the same
  // frame gives the same image whatever was rendered before and on any thread count.
  // `camera` overrides the scene's camera for this frame (benchmarks orbit it).
  void render(int frame, FrameImage& out, FrameStats& stats, const io::Camera* camera = nullptr);

  int width() const { return width_; }
  const io::Quality& quality() const { return quality_; }
  int height() const { return height_; }
  int frame_count() const;
  uint64_t base_triangles() const;
  uint64_t fur_triangles() const;
  // Fur vertex and face counts of object i (nullptr when it has no fur).
  const fur::FurCounts* fur_counts(size_t object) const;
  // The fur's geometry of object i, as built (nullptr when it has no fur).
  const fur::FurGeometry* fur_geometry(size_t object) const;
  // The (source, neighbour) vertex pairs object i's normal blur was estimated to settle, the
  // figure --max-blur-pairs was checked against (shading::BlurredNormals::pair_estimate): what
  // `pelt info` reports. nullopt when the object has no normal blur.
  std::optional<uint64_t> blur_pair_estimate(size_t object) const;
  // The maps object i draws, each with where it lies (io::MapPlacement) in its mesh file's own
  // uvs (OBJ: v from the bottom), for `pelt info`: one entry for the whole mesh, or one per map
  // set its file's materials give (io::LoadedMesh::maps). A map the scene names lies as the uvs say.
  struct MapsDrawn {
    std::string material;  // the set's first material, as the mesh file names it ("" for the whole mesh)
    size_t triangles = 0;
    bool color = false, normal = false;
    io::MapPlacement color_placement, normal_placement;
    io::AlphaMode alpha_mode = io::AlphaMode::opaque;  // the mesh file's material's, with its cutoff and factor
    float alpha_cutoff = 0.5f, alpha_factor = 1.0f;
    // A MASK whose test fails on every texel (or on the factor alone): neither the part nor the
    // fur over it is drawn or computed.
    bool cut_away = false;
    // An OBJ's map_d (its file name), whose dissolve the colour map's alpha carries (io/dissolve_map.h);
    // alone: the material has no map_Kd, so the colour map is white with map_d's dissolve as alpha.
    std::string alpha_map;
    bool alpha_map_alone = false;
  };
  std::vector<MapsDrawn> maps_drawn(size_t object) const;
  // Floats per fur vertex that the last frame's fur draws of object i interpolate (0 without
  // fur): 4 for grey per-vertex light, 8 for coloured, 12 lit per pixel.
  int fur_varying_count(size_t object) const;
  // Estimated bytes for rendering a frame: meshes, varyings, fur arrays and textures,
  // colour maps, the output image and the rasterizer's per-worker tile scratch.
  size_t memory_estimate() const;
  // The estimate of a render's peak that --max-memory was checked against (budget_check.h:
  // both images of `pelt render`, the spp buffers, every worker's scratch): what `pelt info`
  // reports, so that its figure and the budget's refusal agree.
  uint64_t budget_estimate() const { return budget_estimate_; }
  // Every file this renderer read: the scene, its mesh files, and the colour and normal maps
  // (the scene's or those the meshes name). `pelt render` refuses to write over any of them.
  const std::vector<std::filesystem::path>& input_files() const { return input_files_; }
  // What the mesh loaders accepted but changed or ignored (normals computed, uvs dropped,
  // a loader's own warning), one line each naming the object's mesh field and file: for
  // the commands to show the user.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  struct Object;
  io::Quality quality_;
  io::Scene scene_;  // with the quality's overrides applied
  RenderSettings settings_;
  int width_, height_;
  raster::Renderer renderer_;
  std::vector<shading::Light> lights_;
  FrameInputs inputs_;  // this frame's, kept so evaluating them reuses its vectors
  std::vector<std::unique_ptr<Object>> objects_;
  std::vector<raster::DrawCall> draws_;  // reused every frame
  std::vector<glm::vec2> offsets_;       // sub-pixel sample offsets, one per pass
  uint64_t budget_estimate_ = 0;
  std::vector<std::filesystem::path> input_files_;
  std::vector<float> sample_color_;      // one sample's image when spp > 1
  std::vector<double> accum_;            // the sum of the samples' images
  // Both public constructors: meshes given, or (nullopt) loaded here after the scene budget.
  SceneRenderer(const io::Scene& scene, std::optional<std::vector<io::SceneMesh>> meshes,
                const RenderSettings& settings);
  void build(std::vector<io::SceneMesh> meshes);
  FrameStats setup_stats_;  // stages run by the constructor, reported once
  std::vector<std::string> warnings_;
  bool setup_reported_ = false;
};

}  // namespace pelt::render
