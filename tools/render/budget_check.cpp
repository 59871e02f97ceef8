#include "tools/render/budget_check.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fur/fur_geometry.h"
#include "raster/renderer.h"
#include "raster/setup.h"
#include "raster/vertex_kernels.h"
#include "raster/texture.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/varyings.h"

namespace pelt::render {
namespace {

static_assert(io::kTextureSideLimit == raster::kMaxTextureSide, "the texture side budget's limit is the rasterizer's");

using io::sat_add;
using io::sat_mul;

// FurObject's arrays, by what they are sized on (tools/render/fur_object.*, fur/fur_geometry.h).
// Per base vertex: unit normal, growth direction, dynamics force.
constexpr uint64_t kFurBytesPerBaseVertex = 3 * sizeof(glm::vec3);
// Per fur vertex: rest position, shell uv, layer, the gravity, wind and current poses,
// tangent, the 26-row lighting SoA of vertex lighting, shell varyings of the larger (pixel
// lighting) layout, and the pose in clip space (the surface sort's keys; counted whatever the
// sort, as the scene's own quality may be overridden). With fins, also the fin uv and varyings.
constexpr uint64_t kFurVaryingBytes = std::max(FurVaryings::kCount, FurPixelVaryings::kCount) * sizeof(float);
constexpr uint64_t kFurBytesPerVertex = sizeof(glm::vec3) + sizeof(glm::vec2) + sizeof(uint16_t) +
                                        4 * sizeof(glm::vec3) + 26 * sizeof(float) + sizeof(glm::vec4) +
                                        kFurVaryingBytes;
constexpr uint64_t kFurBytesPerFinVertex = sizeof(glm::vec2) + kFurVaryingBytes;
// Per base face: its unit normal. Per shell triangle: the surface sort's key. Per shell or
// fin triangle: three indices. Per edge: the
// FurEdge, its fin weight, and the fin list entries of its (shells - 1) quads, counted
// per fin triangle (one uint32 per quad, two triangles a quad).
constexpr uint64_t kFurBytesPerBaseFace = sizeof(glm::vec3);
constexpr uint64_t kFurBytesPerTriangle = 3 * sizeof(uint32_t);
constexpr uint64_t kFurBytesPerShellTriangle = sizeof(float);
constexpr uint64_t kFurBytesPerEdge = sizeof(fur::FurEdge) + sizeof(float);
constexpr uint64_t kFurBytesPerFinTriangle = sizeof(uint32_t) / 2;

std::string object_field(size_t i) { return "objects[" + std::to_string(i) + "]"; }

int effective_side(int requested, int scene_side) { return requested > 0 ? requested : scene_side; }

// The shell count the renderer will use for object i, and the field that set it.
int effective_shells(const io::Scene& scene, size_t i, std::string& field) {
  if (scene.quality.shells) {
    field = "quality.shells";
    return *scene.quality.shells;
  }
  field = object_field(i) + ".fur.shells";
  return scene.objects[i].fur->shells;
}

// Mipmapped 8-bit RGBA: the levels add a third to level 0 (rounded up).
uint64_t mipmapped_rgba8(uint64_t texels) { return sat_mul(sat_mul(texels, 4), 4) / 3 + 4; }

// What the rasterizer allocates for a frame's draws: per vertex of each draw its clip position
// and front-end vertex, per triangle a set-up triangle (as if none were culled: a growing
// vector's capacity is up to twice its size anyway) and about one tile's bin entry and its
// sort scratch. A meshes' 2 M triangles measured 251 MiB of peak resident set above the
// estimate before this part (a helper's measurement, 2026-11-27); this counts 279 MiB.
uint64_t raster_bytes(uint64_t draw_vertices, uint64_t triangles) {
  constexpr uint64_t kPerVertex = sizeof(glm::vec4) + sizeof(raster::FrontVertex);
  constexpr uint64_t kPerTriangle = sizeof(raster::TriSetup) + sizeof(uint32_t) + sizeof(uint64_t);
  return sat_add(sat_mul(draw_vertices, kPerVertex), sat_mul(triangles, kPerTriangle));
}

MemoryPart mesh_part(const io::SceneObject& so, const Mesh& m, size_t i) {
  const uint64_t v = m.positions.size(), f = m.indices.size() / 3;
  const bool blur = so.material.type == io::MaterialType::skin &&
                    so.material.skin.multiple_scattering == shading::MultipleScattering::normal_blur;
  const uint64_t varyings = blur ? SurfaceVaryings::kCountBlurred : SurfaceVaryings::kCount;
  uint64_t per_vertex = 2 * sizeof(glm::vec3) + (m.uvs.empty() ? 0 : sizeof(glm::vec2)) + varyings * sizeof(float);
  if (blur) per_vertex += 9 * sizeof(float);  // the three blurred normals, held while varyings are filled
  MemoryPart p;
  p.kind = "meshes";
  p.object = int(i);
  p.field = object_field(i) + ".mesh";
  p.what = "mesh, " + std::to_string(v) + " vertices and " + std::to_string(f) + " triangles with varyings";
  p.bytes = sat_add(sat_mul(v, per_vertex), sat_mul(f, 3 * sizeof(uint32_t)));
  return p;
}

// A mesh drawn in parts (mesh_parts): each part's copies of the vertices it uses (a vertex on a
// border between parts in each), with their varyings and tangent frames, and each triangle's
// number in the whole mesh (the renderer's split_parts); and the copies' count.
struct SplitPart {
  MemoryPart part;
  uint64_t vertices = 0;
};
SplitPart split_part(const io::SceneObject& so, const Mesh& m, const MeshParts& parts, size_t i) {
  uint64_t copies = 0;
  for (const PartSplit& part : split_mesh(m, parts)) copies += part.vertices.size();
  const bool blur = so.material.type == io::MaterialType::skin &&
                    so.material.skin.multiple_scattering == shading::MultipleScattering::normal_blur;
  const uint64_t varyings = (blur ? SurfaceVaryings::kCountBlurred : SurfaceVaryings::kCount) + 4;
  const uint64_t per_vertex = 2 * sizeof(glm::vec3) + sizeof(glm::vec2) + varyings * sizeof(float);
  SplitPart out;
  out.vertices = copies;
  MemoryPart& p = out.part;
  p.kind = "meshes";
  p.object = int(i);
  p.field = object_field(i) + ".mesh";
  p.what = "mesh drawn in " + std::to_string(parts.count()) + " parts by material, " + std::to_string(copies) +
           " vertex copies";
  p.bytes = sat_add(sat_mul(copies, per_vertex), sat_mul(uint64_t(m.indices.size() / 3), 4 * sizeof(uint32_t)));
  return out;
}

// A mip chain's working set while it is built: level 0 packed, 4 bytes a texel, and level 1
// in double, 32 bytes a texel of a quarter as many (raster/texture.cpp).
constexpr uint64_t kBuildBytes = 4 + 32 / 4;

// A texture read from an image file: float RGBA as read, the file's own pixels while they
// are converted, the mip chain's working set, and the mipmapped 8-bit texture the shader
// samples.
uint64_t image_texture_bytes(uint64_t texels, uint64_t file_bytes_per_texel) {
  return sat_add(sat_mul(texels, 4 * sizeof(float) + file_bytes_per_texel + kBuildBytes), mipmapped_rgba8(texels));
}

// Object i's colour or normal map (`key`), sized from its header as the renderer will load
// it (map_source), plus `extra` bytes that come with it; empty field when it has none.
// `fur_cut`: the fur is cut out by the map's alpha, copied into an La8 texture of the map's size
// (cut_alpha_texture), which comes with it.
MemoryPart map_part(const io::Scene& scene, size_t i, const char* key, const std::string& noun,
                    const std::filesystem::path& from_scene, const io::TextureRef& named, uint64_t extra,
                    const std::string& what_extra, bool fur_cut = false) {
  MemoryPart p;
  const std::optional<MapSource> src = map_source(from_scene, named);
  if (!src) return p;
  int width, height;
  uint64_t file_bytes_per_texel = 0;  // embedded: no file pixels
  if (src->file) {
    const io::ImageHeader h = asked_by(map_asked_by(scene, i, key, src->named_by_mesh),
                                       [&] { return io::read_image_header(*src->file); });
    width = h.width;
    height = h.height;
    file_bytes_per_texel = uint64_t(std::min(h.channels, 4)) * uint64_t(h.bytes_per_channel);
    p.what = noun + " " + src->file->filename().string();
  } else {
    width = src->pixels->width;
    height = src->pixels->height;
    // Pixels a loader read from files (an OBJ's map_Kd and map_d as one image) are named by them.
    const std::filesystem::path *dissolve = named.dissolve_file(), *color = named.dissolved_color_file();
    p.what = !dissolve ? "embedded " + noun
             : !color  ? noun + " from map_d " + dissolve->filename().string()
                       : noun + " " + color->filename().string() + " with its map_d " + dissolve->filename().string();
  }
  p.what += ", " + std::to_string(width) + " x " + std::to_string(height) + " texels" + what_extra;
  p.field = object_field(i) + (src->named_by_mesh ? ".mesh" : ".material." + std::string(key));
  const uint64_t texels = uint64_t(width) * uint64_t(height);
  p.bytes = sat_add(image_texture_bytes(texels, file_bytes_per_texel), extra);
  if (fur_cut) {  // the copy's level 0 as bytes, and its mip chain at 2 bytes a texel
    p.bytes = sat_add(p.bytes, sat_add(sat_mul(texels, 2), mipmapped_rgba8(texels) / 2));
    p.what += ", and its alpha for the fur's cut-out";
  }
  p.kind = noun + "s";
  p.object = int(i);
  return p;
}

// `cut_by_map`: the drawn fur is cut out by a part's colour map's alpha (alphaMode MASK), which it
// reads at the mesh uvs as a colour map.
void add_fur_parts(const io::Scene& scene, const io::SceneMesh& sm, size_t i, int threads, bool drawn,
                   bool cut_by_map, std::vector<MemoryPart>& parts, std::vector<MemoryPart>& frame_parts) {
  const fur::FurParams& fp = *scene.objects[i].fur;
  std::string shells_field;
  const int shells = effective_shells(scene, i, shells_field);
  const Mesh& m = sm.loaded.mesh;
  const uint64_t faces = m.indices.size() / 3;
  const uint64_t edges = (3 * faces + 1) / 2;
  // The fur is built on the mesh in the scene's space, where the box mapping's planes (and so its
  // vertex copies) depend on the object's rotation. The copies depend on positions, normals and
  // triangles only: the uvs are not copied (an estimate made before the render allocates).
  Mesh world;
  world.positions = m.positions;
  world.normals = m.normals;
  world.indices = m.indices;
  io::bake_transform(world, sm.model);
  const fur::FurCounts c = fur::fur_counts(fur::fur_base_vertex_count(world, fp), faces, edges, shells, fp.fins);
  const bool fins = fp.fins != fur::FinMode::off;

  MemoryPart geo;
  geo.kind = "fur geometry";
  geo.object = int(i);
  geo.field = shells_field;
  geo.what = "fur geometry, " + std::to_string(shells) + " shells: " + std::to_string(c.shell_vertices) +
             " vertices, " + std::to_string(c.shell_faces + c.fin_faces) + " shell and fin triangles";
  uint64_t g = sat_mul(c.base_vertices, kFurBytesPerBaseVertex);
  g = sat_add(g, sat_mul(c.shell_vertices, kFurBytesPerVertex));
  if (fins) g = sat_add(g, sat_mul(c.shell_vertices, kFurBytesPerFinVertex));
  // A colour map's or a cut-out's mesh uv: two more varyings per fur vertex in the shell and fin
  // arrays, and the mesh uvs per base vertex; a length map's scale per base vertex.
  if (fp.use_color_map || cut_by_map) {
    g = sat_add(g, sat_mul(c.shell_vertices, (fins ? 2 : 1) * FurMapUv::kCount * sizeof(float)));
    g = sat_add(g, sat_mul(c.base_vertices, sizeof(glm::vec2)));
  }
  // Each such map's list per base face and per fin quad, when the mesh's parts differ in it.
  const uint64_t face_lists = uint64_t(fp.use_color_map) + uint64_t(cut_by_map);
  g = sat_add(g, sat_mul(face_lists, sat_mul(sat_add(c.base_faces, c.fin_faces / 2), sizeof(uint32_t))));
  if (!scene.objects[i].fur_length_map.empty()) g = sat_add(g, sat_mul(c.base_vertices, sizeof(float)));
  g = sat_add(g, sat_mul(c.base_faces, kFurBytesPerBaseFace));
  g = sat_add(g, sat_mul(sat_add(c.shell_faces, c.fin_faces), kFurBytesPerTriangle));
  g = sat_add(g, sat_mul(c.shell_faces, kFurBytesPerShellTriangle));
  g = sat_add(g, sat_mul(c.edges, fins ? kFurBytesPerEdge : sizeof(fur::FurEdge)));
  g = sat_add(g, sat_mul(c.fin_faces, kFurBytesPerFinTriangle));
  geo.bytes = g;
  parts.push_back(std::move(geo));

  // Strand textures: each shell layer generated unmipped as luminance and alpha (2 bytes a
  // texel), the fin (with fins) as RGBA8 and as luminance and alpha (6), each then copied into a mipmapped texture of 4 bytes a texel
  // (raster/texture.h); the layers are built on up to `threads` threads at once, each holding
  // a mip chain's working set (image_texture_bytes' kBuildBytes).
  const uint64_t layer_texels = uint64_t(fp.texture_size) * uint64_t(fp.texture_size);
  const uint64_t shell_layers = uint64_t(std::max(shells, 0)), layers = shell_layers + (fins ? 1 : 0);
  MemoryPart tex;
  tex.kind = "fur strand textures";
  tex.object = int(i);
  tex.field = object_field(i) + ".fur.texture_size";
  tex.what = "fur strand textures, " + std::to_string(layers) + " layers of " + std::to_string(fp.texture_size) +
             "^2 texels with mips";
  const uint64_t builds = std::min<uint64_t>(layers, uint64_t(std::max(threads, 1)));
  tex.bytes = sat_add(sat_add(sat_mul(layers, mipmapped_rgba8(layer_texels)),
                              sat_mul(layer_texels, sat_add(sat_mul(shell_layers, 2), fins ? 6 : 0))),
                      sat_mul(builds, sat_mul(layer_texels, kBuildBytes)));
  if (drawn) parts.push_back(std::move(tex));

  // The rasterizer's set-up of the shells' and the fins' draws (both over the fur's vertices).
  // Silhouette fins draw only the edges near the silhouette: a quarter of the fin triangles is
  // counted (7.6 % were drawn in a furry sphere's frame, more at grazing views).
  const uint64_t fin_drawn = fp.fins == fur::FinMode::all ? c.fin_faces : fins ? c.fin_faces / 4 : 0;
  // Each draw sets up every fur vertex: shells and fins, or in the layer sort one draw per
  // layer and per pair of layers.
  const uint64_t layer_draws = uint64_t(std::max(shells, 1));
  const uint64_t draws = scene.quality.sort == io::SortQuality::layer ? (fins ? 2 * layer_draws - 1 : layer_draws)
                                                                       : (fins ? 2 : 1);
  MemoryPart raster;
  raster.kind = kSetupsKind;
  raster.object = int(i);
  raster.field = shells_field;
  raster.what = "rasterizer's set-up of the fur's " + std::to_string(c.shell_faces + fin_drawn) +
                " triangles in " + std::to_string(draws) + " draws a frame";
  raster.bytes = raster_bytes(sat_mul(draws, c.shell_vertices), c.shell_faces + fin_drawn);
  if (drawn) frame_parts.push_back(std::move(raster));
}

// A budget below pelt's own footprint refuses every render: said so, naming --max-memory, not
// blamed on the image, a mesh or the scene's largest part. `estimate_said`: what the refusal
// says of the render's estimate first, when there is one.
void refuse_below_process(const io::Budget& budget, const std::string& estimate_said) {
  if (budget.max_memory_bytes >= kProcessBaselineBytes) return;
  throw io::InputError("", io::kMaxMemoryFlag,
                       estimate_said + "pelt itself (code, shared libraries, start-up heap) takes about " +
                           describe_bytes(kProcessBaselineBytes) + " before any scene: a budget of " +
                           describe_bytes(budget.max_memory_bytes) + " is too small for any render");
}

[[noreturn]] void refuse(const io::Scene& scene, const std::string& field, const std::string& reason) {
  throw io::InputError(scene.file.string(), field, reason);
}

}  // namespace

std::optional<MapSource> map_source(const std::filesystem::path& from_scene, const io::TextureRef& named) {
  if (!from_scene.empty()) return MapSource{&from_scene, nullptr, false};
  if (!named.path.empty()) return MapSource{&named.path, nullptr, true};
  if (named.pixels) return MapSource{nullptr, named.pixels.get(), true};
  return std::nullopt;
}

MapImage map_image(const char* kind, const MapSource& src, bool alpha) {
  return {kind, alpha, src.file ? src.file->string() : std::string(), static_cast<const void*>(src.pixels)};
}

MeshParts mesh_parts(const io::SceneObject& so, const io::LoadedMesh& loaded) {
  // A map as a part draws it: its image and where it lies (none: an empty image).
  const auto drawn = [](const char* kind, const std::filesystem::path& from_scene, const io::TextureRef& named) {
    const std::optional<MapSource> src = map_source(from_scene, named);
    if (!src) return std::make_pair(MapImage{}, io::MapPlacement{});
    return std::make_pair(map_image(kind, *src), src->named_by_mesh ? named.placement : io::MapPlacement{});
  };
  using Key = std::tuple<std::pair<MapImage, io::MapPlacement>, std::pair<MapImage, io::MapPlacement>, io::AlphaMode,
                         float, float>;
  std::vector<Key> keys;
  MeshParts parts;
  for (size_t k = 0; k < std::max<size_t>(1, loaded.maps.size()); ++k) {
    const io::MeshMaps& set = loaded.set(k);
    const Key key{drawn("color_map", so.material.color_map, set.color_map),
                  drawn("normal_map", so.material.normal_map, set.normal_map), set.alpha_mode, set.alpha_cutoff,
                  set.alpha_factor};
    const auto same = std::find(keys.begin(), keys.end(), key);
    parts.part_of_set.push_back(uint32_t(same - keys.begin()));
    if (same == keys.end()) {
      keys.push_back(key);
      parts.first_set.push_back(uint32_t(k));
    }
  }
  if (parts.count() > 1) {
    parts.triangle_part.reserve(loaded.triangle_maps.size());
    for (const uint32_t set : loaded.triangle_maps) parts.triangle_part.push_back(parts.part_of_set[set]);
  }
  return parts;
}

std::vector<PartSplit> split_mesh(const Mesh& m, const MeshParts& parts) {
  std::vector<PartSplit> out(parts.count());
  for (size_t t = 0; t < parts.triangle_part.size(); ++t) out[parts.triangle_part[t]].triangles.push_back(uint32_t(t));
  std::vector<uint32_t> local(m.positions.size(), UINT32_MAX);  // the part's number of each mesh vertex
  for (PartSplit& part : out) {
    part.indices.reserve(3 * part.triangles.size());
    for (const uint32_t t : part.triangles)
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = m.indices[3 * size_t(t) + size_t(c)];
        if (local[v] == UINT32_MAX) {
          local[v] = static_cast<uint32_t>(part.vertices.size());
          part.vertices.push_back(v);
        }
        part.indices.push_back(local[v]);
      }
    for (const uint32_t v : part.vertices) local[v] = UINT32_MAX;
  }
  return out;
}

std::string map_asked_by(const io::Scene& scene, size_t i, const char* map, bool named_by_mesh) {
  const std::string object = object_field(i);
  if (named_by_mesh)
    return std::string("the ") + map + " that " + scene.objects[i].mesh + " names, in " + object + ".mesh of " +
           scene.file.string();
  return "in " + object + ".material." + map + " of " + scene.file.string();
}

uint64_t image_bytes(int width, int height, int spp, ImageOutput output) {
  const uint64_t px = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
  // The float RGBA images (a sequence writes one while the next renders), the 8-bit RGBA written
  // to the file.
  uint64_t per_pixel = (output == ImageOutput::still ? 1 : 2) * 4 * sizeof(float) + 4;
  if (output == ImageOutput::gif) per_pixel += kGifBytesPerPixel;
  if (spp > 1) per_pixel += 4 * sizeof(float) + 4 * sizeof(double);  // one sample's image, the sum
  return sat_mul(px, per_pixel);
}

void check_scene_budget(const io::Scene& scene, int width, int height, int spp, const io::Budget& budget,
                        ImageOutput output) {
  const int w = effective_side(width, scene.image.width), h = effective_side(height, scene.image.height);
  const uint64_t px = uint64_t(std::max(w, 0)) * uint64_t(std::max(h, 0));
  if (px > budget.max_pixels)
    refuse(scene, "image.width",
           "the image is " + std::to_string(w) + " x " + std::to_string(h) + " = " + std::to_string(px) +
               " pixels, " + io::over_budget(std::to_string(budget.max_pixels) + " pixels", io::kMaxPixelsFlag));
  // Before any mesh loads (the OBJ reader's own check counts the process too, and would name the
  // mesh for a budget no render fits in).
  refuse_below_process(budget, "");
  const uint64_t image = image_bytes(w, h, spp, output);
  if (image > budget.max_memory_bytes) {
    const bool spp_made_it = spp > 1 && image_bytes(w, h, 1, output) <= budget.max_memory_bytes;
    refuse(scene, spp_made_it ? "quality.spp" : "image.width",
           "the " + std::to_string(w) + " x " + std::to_string(h) + " image" +
               (spp > 1 ? " at " + std::to_string(spp) + " samples per pixel" : std::string()) +
               (output == ImageOutput::gif ? " written as a GIF" : "") + " needs " + describe_bytes(image) +
               " of buffers, " +
               io::over_budget(describe_bytes(budget.max_memory_bytes), io::kMaxMemoryFlag));
  }
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].fur) continue;
    std::string field;
    const int shells = effective_shells(scene, i, field);
    if (shells > budget.max_shells)
      refuse(scene, field,
             std::to_string(shells) + " fur shells, " +
                 io::over_budget(std::to_string(budget.max_shells), io::kMaxShellsFlag));
    const int side = scene.objects[i].fur->texture_size;
    if (side > budget.max_texture_side)
      refuse(scene, object_field(i) + ".fur.texture_size",
             "fur strand textures of " + std::to_string(side) + " x " + std::to_string(side) + " texels, a side " +
                 io::over_budget(std::to_string(budget.max_texture_side), io::kMaxTextureSideFlag));
  }
}

uint64_t MemoryEstimate::renderer_total() const {
  uint64_t sum = 0;
  for (const MemoryPart& p : parts)
    if (p.kind != kSetupsKind && p.kind != kProcessKind) sum = sat_add(sum, p.bytes);
  return sum;
}

const MemoryPart& MemoryEstimate::largest() const {
  // The process's own footprint is no part of the scene a user could change: never named.
  return *std::max_element(parts.begin(), parts.end(), [](const MemoryPart& a, const MemoryPart& b) {
    return (a.kind == kProcessKind ? 0 : a.bytes) < (b.kind == kProcessKind ? 0 : b.bytes);
  });
}

MemoryEstimate estimate_memory(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                               int height, int threads, int spp, bool fur_drawn, ImageOutput output, bool exact_sort) {
  if (meshes.size() != scene.objects.size())
    throw std::invalid_argument("estimate_memory: one mesh per scene object expected");
  MemoryEstimate e;
  std::vector<MemoryPart> frame_parts;  // after the renderer's own, in object order
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const io::SceneObject& so = scene.objects[i];
    const Mesh& m = meshes[i].loaded.mesh;
    e.parts.push_back(mesh_part(so, m, i));
    // Its draw a frame, and what an object costs however small: its shader, its draw, the
    // small vectors of each (about 13 KB an object measured over 10,648 spheres), and as much
    // for each further part (13-14 KB a part measured over 10,000 parts).
    constexpr uint64_t kObjectBytes = 16 << 10;
    const io::LoadedMesh& loaded = meshes[i].loaded;
    const MeshParts parts = mesh_parts(so, loaded);
    // Each image once, however many parts draw it (the renderer's load_map).
    std::set<MapImage> counted;
    // The images whose alpha cuts the fur out (a MASK part's colour map, the fur drawn): each comes
    // with its La8 copy, whichever part reads it first.
    std::set<MapImage> cut_images;
    for (const uint32_t k : parts.first_set)
      if (const io::MeshMaps& set = loaded.set(k); so.fur && fur_drawn && set.alpha_mode == io::AlphaMode::mask)
        if (const std::optional<MapSource> src = map_source(so.material.color_map, set.color_map))
          cut_images.insert(map_image("color_map", *src, true));
    bool tangents_counted = false;
    for (const uint32_t k : parts.first_set) {
      const io::MeshMaps& set = loaded.set(k);
      const auto once = [&](const char* key, const std::filesystem::path& from_scene, const io::TextureRef& named,
                            bool alpha) {
        const std::optional<MapSource> src = map_source(from_scene, named);
        return src && counted.insert(map_image(key, *src, alpha)).second;
      };
      const std::optional<MapSource> color = map_source(so.material.color_map, set.color_map);
      const bool fur_cut = color && keeps_alpha(set) && cut_images.count(map_image("color_map", *color, true)) > 0;
      if (once("color_map", so.material.color_map, set.color_map, keeps_alpha(set)))
        e.parts.push_back(
            map_part(scene, i, "color_map", "colour map", so.material.color_map, set.color_map, 0, "", fur_cut));
      // A normal map brings the four tangent-frame varyings per vertex, and the frames.
      if (once("normal_map", so.material.normal_map, set.normal_map, false)) {
        const uint64_t tangents = tangents_counted ? 0 : sat_mul(uint64_t(m.positions.size()), 2 * 4 * sizeof(float));
        e.parts.push_back(map_part(scene, i, "normal_map", "normal map", so.material.normal_map, set.normal_map,
                                   tangents, tangents_counted ? "" : ", and the tangent frames"));
        tangents_counted = true;
      }
    }
    // The fur's colour maps (each part's) are read without their alpha, also where a part reads
    // its map with.
    if (so.fur && so.fur->use_color_map)
      for (const uint32_t k : parts.first_set) {
        const io::MeshMaps& set = loaded.set(k);
        if (const std::optional<MapSource> src = map_source(so.material.color_map, set.color_map);
            src && counted.insert(map_image("color_map", *src, false)).second)
          e.parts.push_back(map_part(scene, i, "color_map", "colour map", so.material.color_map, set.color_map, 0, ""));
      }
    // The parts' draws set up their own vertex copies, every one at once.
    uint64_t draw_vertices = m.positions.size();
    if (parts.count() > 1) {
      SplitPart split = split_part(so, m, parts, i);
      draw_vertices = split.vertices;
      e.parts.push_back(std::move(split.part));
    }
    frame_parts.push_back({object_field(i) + ".mesh",
                           "rasterizer's set-up of its " + std::to_string(m.triangle_count()) + " triangles a frame" +
                               (parts.count() > 1 ? " in " + std::to_string(parts.count()) + " draws" : ""),
                           sat_add(raster_bytes(draw_vertices, m.triangle_count()),
                                   sat_mul(kObjectBytes, uint64_t(parts.count()))),
                           std::string(kSetupsKind), int(i)});
    if (so.fur) add_fur_parts(scene, meshes[i], i, threads, fur_drawn, !cut_images.empty(), e.parts, frame_parts);
    if (!so.fur_length_map.empty()) {  // read as floats and sampled once, then freed
      const std::string field = object_field(i) + ".fur.length_map";
      const io::ImageHeader h = asked_by("in " + field + " of " + scene.file.string(),
                                         [&] { return io::read_image_header(so.fur_length_map); });
      const uint64_t texels = uint64_t(h.width) * uint64_t(h.height);
      e.parts.push_back({field,
                         "length map " + so.fur_length_map.filename().string() + ", " + std::to_string(h.width) +
                             " x " + std::to_string(h.height) + " texels",
                         sat_mul(texels, 4 * sizeof(float) + uint64_t(std::min(h.channels, 4)) * h.bytes_per_channel),
                         "length maps", int(i)});
    }
  }
  const int w = effective_side(width, scene.image.width), h = effective_side(height, scene.image.height);
  e.parts.push_back({"image.width",
                     "image buffers, " + std::to_string(w) + " x " + std::to_string(h) +
                         (spp > 1 ? " at " + std::to_string(spp) + " samples per pixel" : std::string()) +
                         (output == ImageOutput::gif ? ", and the GIF encoder's" : ""),
                     image_bytes(w, h, spp, output), "image"});
  const uint64_t workers = uint64_t(std::max(threads, 1));
  e.parts.push_back({"--threads", "tile scratch of " + std::to_string(workers) + " worker(s)",
                     sat_mul(workers, uint64_t(raster::Renderer::worker_scratch_bytes())), "scratch"});
  if (exact_sort)
    e.parts.push_back({"--sort", "the exact sort's fragments, " + std::to_string(raster::kExactFragmentCap) +
                                     " at most a tile, in each of " + std::to_string(workers) + " worker(s)",
                       sat_mul(workers, uint64_t(raster::Renderer::exact_sort_bytes(raster::kExactFragmentCap))),
                       "scratch"});
  for (MemoryPart& p : frame_parts) e.parts.push_back(std::move(p));
  e.parts.push_back({"", "pelt process itself (code, shared libraries, start-up heap)", kProcessBaselineBytes,
                     std::string(kProcessKind)});
  for (const MemoryPart& p : e.parts) e.total = sat_add(e.total, p.bytes);
  return e;
}

uint64_t check_memory_budget(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                             int height, int threads, int spp, const io::Budget& budget, bool fur_drawn,
                             ImageOutput output, bool exact_sort) {
  const MemoryEstimate e = estimate_memory(scene, meshes, width, height, threads, spp, fur_drawn, output, exact_sort);
  if (e.total <= budget.max_memory_bytes) return e.total;
  const MemoryPart& big = e.largest();
  // As check_scene_budget: image buffers that one sample per pixel would fit in the budget are
  // refused for their samples, so a flag or a sweep that set them is named, not the image size.
  // Only the image part depends on spp: the total at one sample swaps that part alone.
  const bool spp_made_it =
      big.field == "image.width" && spp > 1 &&
      e.total - big.bytes + image_bytes(effective_side(width, scene.image.width),
                                        effective_side(height, scene.image.height), 1, output) <= budget.max_memory_bytes;
  // Many objects' parts of one kind can outweigh the largest single part (216 furry spheres):
  // said, with how many parts, so the user looks at the scene's objects, not the image.
  // Named when that kind over all its objects is at least twice the largest part (the largest
  // part and one more object of its kind are no news).
  std::map<std::string, std::pair<uint64_t, std::set<int>>> by_kind;  // bytes, objects
  for (const MemoryPart& p : e.parts) {
    if (p.object < 0) continue;
    auto& [bytes, objects] = by_kind[p.kind];
    bytes = sat_add(bytes, p.bytes);
    objects.insert(p.object);
  }
  std::string together;
  uint64_t most = sat_mul(big.bytes, 2) - 1;
  for (const auto& [kind, sum] : by_kind)
    if (sum.second.size() > 1 && sum.first > most) {
      most = sum.first;
      together = "; together, the " + kind + " of " + std::to_string(sum.second.size()) + " objects take " +
                 describe_bytes(sum.first);
    }
  refuse_below_process(budget, "this render needs an estimated " + describe_bytes(e.total) + ", of which ");
  refuse(scene, spp_made_it ? "quality.spp" : big.field,
         "this render needs an estimated " + describe_bytes(e.total) + ", " +
             io::over_budget(describe_bytes(budget.max_memory_bytes), io::kMaxMemoryFlag) +
             "; the largest part is the " + big.what + ": " + describe_bytes(big.bytes) + together);
}

uint64_t check_memory_budget(const io::Scene& scene, const std::vector<io::SceneMesh>& meshes, int width,
                             int height, int threads, const io::Budget& budget) {
  return check_memory_budget(scene, meshes, width, height, threads, scene.quality.spp, budget, true,
                             ImageOutput::sequence, scene.quality.sort == io::SortQuality::exact);
}

}  // namespace pelt::render
