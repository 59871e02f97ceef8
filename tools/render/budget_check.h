// Resource budgets of a whole render (io::Budget), checked from counts before the
// renderer allocates: the image size, every fur block's shells and texture size, and an
// estimate of the memory the render will hold at its peak. Mesh faces and texture sides
// are checked by the loaders themselves (tools/io), which are the first to know them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "tools/io/budget.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"
#include "tools/io/scene.h"

namespace pelt::render {

// What `pelt render` writes, which sets the image buffers it holds.
enum class ImageOutput {
  still,     // one frame: one float RGBA image
  sequence,  // frames as files: one is written while the next renders, two float RGBA images
  gif,       // a sequence into one GIF: and the GIF encoder's buffers (kGifBytesPerPixel)
};

// What an animated GIF's writing holds beside a sequence's buffers, per pixel of a frame: the
// frame's 8-bit RGBA and RGB copies (7 bytes) and OpenImageIO's GIF encoder. Measured as the
// peak resident set of `pelt render tools/scenes/bunny_wind.json --threads 1` to out.gif against
// out_####.png (`/usr/bin/time -v`, 2026-11-27): +32.2 MB at 1024 x 768 (6 frames), +7.8 MB at
// 512 x 384 (30 frames), 40-41 bytes a pixel whatever the frame count; rounded up.
inline constexpr uint64_t kGifBytesPerPixel = 44;

// Checks what the scene asks for before any mesh is loaded:
//   image.width   width x height against budget.max_pixels, and the image buffers alone
//                 (image_bytes) against budget.max_memory_bytes (`quality.spp` when only
//                 the supersampling buffers make them too large);
//   objects[i].fur.shells (or quality.shells when the scene's quality overrides every
//                 fur block) against budget.max_shells;
//   objects[i].fur.texture_size against budget.max_texture_side.
// width or height <= 0 means the scene's own image size (as RenderSettings does). The
// caller applies the command line's quality flags to scene.quality first; spp is the
// samples per pixel the render will take. Throws io::InputError(scene file, field,
// reason) whose reason gives the requested number, the budget and the flag raising it.
void check_scene_budget(const io::Scene& scene, int width, int height, int spp, const io::Budget& budget,
                        ImageOutput output = ImageOutput::sequence);

// Bytes of the image buffers of a render: the float RGBA colour images `output` needs, the
// 8-bit encoding for the file, and with spp > 1 one sample's image and a double accumulator.
uint64_t image_bytes(int width, int height, int spp, ImageOutput output = ImageOutput::sequence);

// One part of a memory estimate: where it comes from (a scene field path, or `--threads`
// for the per-worker scratch), what it is, and its bytes.
struct MemoryPart {
  std::string field;
  std::string what;
  uint64_t bytes = 0;
  // What kind of thing it is, for the refusal to say when many objects' parts of one kind
  // together outweigh the largest single part ("meshes", "fur geometry", "fur strand textures",
  // "rasterizer set-ups", "image", "scratch", "process", ...), and the object it belongs to
  // (-1: none).
  std::string kind;
  int object = -1;
};

using io::kProcessBaselineBytes;

// The kinds of the parts SceneRenderer does not hold (MemoryEstimate::renderer_total).
inline constexpr std::string_view kSetupsKind = "rasterizer set-ups";
inline constexpr std::string_view kProcessKind = "process";

struct MemoryEstimate {
  // Objects in order (mesh, maps, fur), the image, the scratch: what SceneRenderer holds; then
  // the rasterizer's per-frame set-ups, object by object, and the process itself.
  std::vector<MemoryPart> parts;
  uint64_t total = 0;             // saturating sum of the parts

  // The first of the largest parts the scene makes (never the process's own footprint); parts
  // must hold one.
  const MemoryPart& largest() const;
  // The parts SceneRenderer itself holds (SceneRenderer::memory_estimate's share): all but the
  // rasterizer's per-frame set-ups and the process's own footprint.
  uint64_t renderer_total() const;
};

// Estimates, from counts only, the bytes a render of `scene` with these loaded meshes
// (one per object, in order, as io::load_scene_meshes returns them) holds at its peak:
//   per object: positions, normals, uvs, indices and varyings (17 floats a vertex for
//   normal_blur skin, 8 otherwise, plus the blurred normals); the colour map (the
//   material's, else the mesh file's) sized from its header: float RGBA as read, the
//   file's pixels, and the mipmapped 8-bit texture; fur: fur::fur_counts for the
//   effective shell count with edges = ceil(3F/2) (exact for a closed mesh, where every
//   edge has two faces) and the per-vertex, per-face and per-edge arrays of FurObject
//   (both lighting modes' varyings: the larger), and the strand textures,
//   shells x texture_size^2 x 4 x 4/3 (mips) plus the unmipped layers they are made
//   from, and the fin texture likewise;
//   the image buffers (image_bytes) and each worker's tile scratch as
//   SceneRenderer::memory_estimate counts it;
// then, after those parts (which SceneRenderer holds): the rasterizer's set-up of each draw
// every frame (a clip position and a front-end vertex per vertex and draw, a set-up triangle
// and its bin entries per triangle, as if none were culled) and the process's own footprint
// (kProcessBaselineBytes). The fur's vertices are set up once per draw: two (shells and fins)
// or, in the layer sort, one per layer and per pair of layers. Without `fur_drawn` (the depth
// and id AOVs, which draw no fur) neither the strand textures nor the fur's set-ups count.
// Colour-map headers are read from disk (io::read_image_header). width or height <= 0
// means the scene's image size; threads < 1 counts as one worker.
// `exact_sort` (quality sort exact): each worker's fragment lists at their cap
// (raster::Renderer::exact_sort_bytes).
MemoryEstimate estimate_memory(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                               int height, int threads, int spp, bool fur_drawn = true,
                               ImageOutput output = ImageOutput::sequence, bool exact_sort = false);

// Refuses an estimate above budget.max_memory_bytes: io::InputError(scene file, the
// largest part's field, reason with the estimate, the budget, --max-memory and the
// largest part). Called after the meshes are loaded and before fur, textures, varyings
// or the image are allocated. The first form takes spp from scene.quality. Returns the
// estimate's total, which `pelt info` reports.
uint64_t check_memory_budget(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                             int height, int threads, const io::Budget& budget);
uint64_t check_memory_budget(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                             int height, int threads, int spp, const io::Budget& budget, bool fur_drawn = true,
                             ImageOutput output = ImageOutput::sequence, bool exact_sort = false);

using io::describe_bytes;

// Where an object's colour or normal map comes from: the scene material's file
// (`from_scene`), else the file or the pixels decoded from inside it that the mesh file
// names; nullopt when neither names one. The memory estimate and the renderer both take an
// object's maps from here. The pointers point into the arguments.
struct MapSource {
  const std::filesystem::path* file = nullptr;  // null: `pixels`
  const io::ImageRGBA* pixels = nullptr;
  bool named_by_mesh = false;
};
std::optional<MapSource> map_source(const std::filesystem::path& from_scene, const io::TextureRef& named);

// The image a map reads (`kind`: "color_map" or "normal_map", whose encodings differ, and
// whether a colour map keeps its alpha): its file, or its pixels decoded from inside the mesh
// file. The renderer reads each image once, and the estimate counts it once, by this key.
using MapImage = std::tuple<std::string, bool, std::string, const void*>;
MapImage map_image(const char* kind, const MapSource& src, bool alpha = false);
// Whether a map set's colour map is read with its alpha (the material draws it).
inline bool keeps_alpha(const io::MeshMaps& set) { return set.alpha_mode != io::AlphaMode::opaque; }

// The parts an object is drawn in: one per distinct pair of maps (image and placement) and
// alpha (mode, cutoff, factor) once the scene's own maps replace the mesh file's, so that faces
// drawing alike are one part (one draw, one tangent frame over them all). The renderer draws
// them, the estimate counts them.
struct MeshParts {
  std::vector<uint32_t> part_of_set;  // per map set of the file (io::LoadedMesh::maps), its part
  std::vector<uint32_t> first_set;    // per part, the first set drawn in it (its name, its maps)
  std::vector<uint32_t> triangle_part;  // per triangle, its part; empty when there is one part
  size_t count() const { return first_set.size(); }
};
MeshParts mesh_parts(const io::SceneObject& so, const io::LoadedMesh& loaded);

// One part of a split mesh (parts.count() > 1): its triangles (their numbers in the whole
// mesh, in order), the mesh vertices they use (in order of first use: a vertex on a border
// between parts is in each part), and their corners numbered in that list. The renderer copies
// a part's arrays from it; the estimate counts the copies.
struct PartSplit {
  std::vector<uint32_t> triangles, vertices, indices;
};
std::vector<PartSplit> split_mesh(const Mesh& m, const MeshParts& parts);

// Who asks for object i's colour or normal map (`map`: "color_map" or "normal_map"), for the
// message of an image that cannot be read, whose own name may be all a user would see:
// "in objects[0].material.color_map of s.json", or with named_by_mesh "the color_map that
// m.obj names, in objects[0].mesh of s.json".
std::string map_asked_by(const io::Scene& scene, size_t i, const char* map, bool named_by_mesh);

// fn()'s result; an io::InputError it throws gets " (asked_by)" after its reason.
template <class Fn>
auto asked_by(const std::string& who, Fn&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (const io::InputError& e) {
    throw io::InputError(e.file, e.field, e.reason + " (" + who + ")");
  }
}

}  // namespace pelt::render
