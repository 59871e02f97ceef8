#include "tools/render/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "shading/light.h"
#include "shading/normal_blur.h"
#include "tools/render/budget_check.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/json_fields.h"
#include "tools/render/animation.h"
#include "tools/render/length_map.h"
#include "tools/render/varyings.h"

namespace pelt::render {

// The triangles of an object drawn with one set of maps: the whole mesh, or (a mesh file whose
// materials name several) the faces of one set (io::LoadedMesh::maps).
struct SurfacePart {
  std::string material;  // the mesh file's name for the set's first material ("" for the whole mesh)
  MaterialDesc desc;
  std::unique_ptr<MaterialShader> shader;
  // With several parts, each has its own vertices (those on a border between parts are
  // copied), so that each normal map's tangent frame is its own faces', as a GPU importer's
  // primitives per material have them; the triangles keep the whole mesh's numbers in the id
  // AOV. One part draws the object's arrays.
  Mesh mesh;
  std::vector<float> varyings;
  std::vector<uint32_t> triangle_ids;
  io::MapPlacement file_color_placement, file_normal_placement;  // as the mesh file gives them (pelt info)
  // An OBJ's map_d file, whose dissolve the colour map's alpha carries, and whether it came
  // without a map_Kd (the colour map white) (pelt info).
  std::string alpha_map;
  bool alpha_map_alone = false;
};

struct SceneRenderer::Object {
  Mesh mesh;  // world space
  std::vector<float> varyings;  // the whole mesh's; with several parts, theirs replace it
  int varying_count = SurfaceVaryings::kCount;
  MaterialDesc material;  // the scene's material, without maps: each part's desc adds its own
  bool double_sided = false;  // else back faces are culled (the material's "double_sided")
  uint32_t id_base = 0;
  std::vector<SurfacePart> parts;
  std::unique_ptr<FurObject> fur;
  std::vector<std::unique_ptr<raster::Texture>> textures;  // every map the parts draw, each image once
  std::optional<uint64_t> blur_pairs;  // shading::BlurredNormals::pair_estimate, for normal_blur skin
};

namespace {

MaterialKind kind_of(io::MaterialType t) {
  switch (t) {
    case io::MaterialType::unlit: return MaterialKind::unlit;
    case io::MaterialType::lambert: return MaterialKind::lambert;
    case io::MaterialType::blinn: return MaterialKind::blinn;
    case io::MaterialType::skin: return MaterialKind::skin;
  }
  return MaterialKind::lambert;
}

// Light i of the scene, converted, against the shader's own check (shading::validate_lights):
// color and intensity may each be within their ranges while their product is not, and an
// animated intensity may leave it at one frame only. Refused as the scene's input, naming the
// scene's field for the shader's (color: the product; vec: a point light's position).
void check_light(const std::filesystem::path& file, size_t i, const shading::Light& s, int frame) {
  const std::optional<shading::ParamError> e = shading::validate_lights(&s, 1);
  if (!e) return;
  const bool radiance = e->field.find(".color") != std::string::npos;
  float worst = 0.0f;  // the value out of range, for the message
  for (int c = 0; c < 3; ++c) {
    const float v = radiance ? s.color[c] : std::abs(s.vec[c]);
    if (!(v <= worst)) worst = v;
  }
  const std::string at = frame >= 0 ? " at frame " + std::to_string(frame) : "";
  if (radiance)
    throw io::InputError(file.string(), io::json_child(io::json_index("lights", i), "intensity"),
                         "color x intensity must be at most 1e6 in every channel (the shader's range), got " +
                             std::to_string(worst) + at);
  throw io::InputError(file.string(), io::json_child(io::json_index("lights", i), "position"),
                       "each coordinate must be within [-1e30, 1e30] (the shader's range), got " + std::to_string(worst) +
                           at);
}

// Fills `out` in place: called every frame, and a vector that keeps its capacity does not
// allocate after the first. frame < 0: the scene's static lights.
void convert_lights(const std::filesystem::path& file, const std::vector<io::Light>& in, int frame,
                    std::vector<shading::Light>& out) {
  out.clear();
  for (size_t i = 0; i < in.size(); ++i) {
    const io::Light& l = in[i];
    shading::Light s{};
    const glm::vec3 c = l.color * l.intensity;
    s.color[0] = c.r;
    s.color[1] = c.g;
    s.color[2] = c.b;
    switch (l.type) {
      case io::LightType::directional:
        s.type = shading::Light::Type::Directional;
        s.vec[0] = l.direction.x, s.vec[1] = l.direction.y, s.vec[2] = l.direction.z;
        break;
      case io::LightType::point:
        s.type = shading::Light::Type::Point;
        s.vec[0] = l.position.x, s.vec[1] = l.position.y, s.vec[2] = l.position.z;
        break;
      case io::LightType::ambient:
        s.type = shading::Light::Type::Ambient;
        break;
    }
    check_light(file, i, s, frame);
    out.push_back(s);
  }
}

SkinLayer layer_of(Aov aov) {
  switch (aov) {
    case Aov::sebum: return SkinLayer::sebum;
    case Aov::epidermis: return SkinLayer::epidermis;
    case Aov::dermis: return SkinLayer::dermis;
    default: return SkinLayer::all;
  }
}

// Which map load_object_map reads, and how.
struct MapKind {
  const char* field;  // "color_map" or "normal_map": the material's key, and the messages' word
  io::ColorEncoding file_encoding;
  raster::TexelEncoding texels;
};
constexpr MapKind kColorMap{"color_map", io::ColorEncoding::srgb, raster::TexelEncoding::Srgb};
constexpr MapKind kNormalMap{"normal_map", io::ColorEncoding::linear, raster::TexelEncoding::Linear};

// A map of object `index`: the scene material's (`from_scene`, a path), else the one the mesh
// file names (`named`: a file, or pixels decoded from inside the file), else none (`out` left
// empty). Colour maps: glTF baseColorTexture, MTL map_Kd; normal maps: glTF normalTexture,
// MTL norm; either only on a mesh with texture coordinates.
void load_object_map(const io::Scene& scene, size_t index, const MapKind& kind, const std::filesystem::path& from_scene,
                     const io::TextureRef& named, const std::string& material, bool alpha,
                     const io::LoadedMesh& loaded, const Mesh& mesh, const io::Budget& budget,
                     const raster::ParallelFor& parallel, raster::Texture& out, FrameStats& stats,
                     std::vector<std::filesystem::path>& inputs) {
  const io::SceneObject& so = scene.objects[index];
  const std::optional<MapSource> src = map_source(from_scene, named);
  if (!src) return;
  StageTimer t(stats, "textures");
  const std::string object = io::json_index("objects", index);
  // Without uvs every pixel would read texel (0, 0): a flat colour, or one normal, in place of
  // the map the user asked for.
  if (mesh.uvs.size() != mesh.vertex_count())
    throw io::InputError(scene.file.string(),
                         src->named_by_mesh ? object + ".mesh" : object + ".material." + kind.field,
                         std::string("a ") + kind.field + " needs texture coordinates, and mesh `" + so.mesh +
                             "` has none" +
                             (!src->named_by_mesh ? ""
                              : material.empty() ? " (the file names the map)"
                                                 : " (the file's material `" + material + "` names the map)"));
  io::ImageRGBA read;
  if (!src->file && src->named_by_mesh) inputs.insert(inputs.end(), named.files.begin(), named.files.end());
  if (src->file) {
    inputs.push_back(*src->file);
    // A colour map's PNG may say it holds linear values (gAMA 1.0): honoured, but for a map a
    // glTF names, whose specification tells loaders to ignore a PNG's gamma.
    const bool gltf_names = src->named_by_mesh && loaded.format == io::MeshFormat::gltf;
    const io::ColorEncoding encoding = kind.file_encoding == io::ColorEncoding::srgb && !gltf_names
                                           ? io::ColorEncoding::srgb_unless_linear
                                           : kind.file_encoding;
    read = asked_by(map_asked_by(scene, index, kind.field, src->named_by_mesh),
                    [&] { return io::read_image_rgba(*src->file, encoding, budget, alpha ? 4 : 3); });
  }
  const io::ImageRGBA& img = src->file ? read : *src->pixels;
  // Only a mesh file's material whose alpha mode is MASK or BLEND draws a map's alpha (glTF's
  // default OPAQUE mode ignores it; the fur's colour takes the map's colour alone). Drawn as
  // straight alpha otherwise, a texel of alpha 0 took its neighbours' colour, a minified stripe
  // of alpha 8/255 vanished from the average, and a 4th channel that is no alpha was refused.
  if (auto e = raster::Texture::from_linear_float(img.width, img.height, img.rgba.data(), kind.texels, out, parallel,
                                                  alpha ? raster::SourceAlpha::straight : raster::SourceAlpha::ignored)) {
    // The raster's name for its input buffer (rgba[k]) means nothing to the user: the texel and
    // channel are in the reason, and the scene field that asked for the map follows it.
    const std::string field = e->field.rfind("rgba", 0) == 0 ? std::string() : e->field;
    throw io::InputError(src->file ? src->file->string() : so.mesh, field,
                         e->reason + " (" + map_asked_by(scene, index, kind.field, src->named_by_mesh) + ")");
  }
}

std::string triangles(size_t n) { return n == 1 ? "1 triangle" : std::to_string(n) + " triangles"; }

// A map on `without` faces that have no texture coordinates (some of mesh's do), the first of
// them of material `material`: the scene's map or the file's, on the faces of map set `set`.
void refuse_uvless_map(const io::Scene& scene, size_t index, const io::MeshMaps& set, const std::string& material,
                       size_t without) {
  const io::SceneObject& so = scene.objects[index];
  for (const MapKind* kind : {&kColorMap, &kNormalMap}) {
    const bool color = kind == &kColorMap;
    const std::optional<MapSource> src =
        map_source(color ? so.material.color_map : so.material.normal_map, color ? set.color_map : set.normal_map);
    if (!src) continue;
    const std::string object = io::json_index("objects", index);
    const std::string named = material.empty()          ? std::string()
                              : material == io::kNoMaterial ? " (faces of no material"
                                                            : " (faces of material `" + material + "`";
    const std::string whose = named.empty() ? "" : named + (src->named_by_mesh ? ", which names the map)" : ")");
    throw io::InputError(scene.file.string(),
                         src->named_by_mesh ? object + ".mesh" : object + ".material." + kind->field,
                         std::string("a ") + kind->field + " needs texture coordinates, and " + triangles(without) +
                             " of mesh `" + so.mesh + "` that it is drawn on " + (without == 1 ? "has" : "have") +
                             " none" + whose);
  }
}

// Fur on a mesh some of whose faces (`without` triangles) have no texture coordinates: its
// strands are laid by the box mapping, and what would read the uvs is refused.
void refuse_uvless_fur(const io::Scene& scene, size_t index, bool color_map, size_t without) {
  const io::SceneObject& so = scene.objects[index];
  const fur::FurParams& fp = *so.fur;
  const char* field = nullptr;
  const char* what = nullptr;
  if (fp.texture_coordinates == fur::StrandCoordinates::mesh) {
    field = "texture_coordinates";
    what = "\"mesh\" lays the strands on the mesh's texture coordinates";
  } else if (fp.comb && fp.comb->field == fur::CombField::uv) {
    field = "comb.field";
    what = "\"uv\" combs along the mesh's texture coordinates";
  } else if (fp.use_color_map && color_map) {  // without a map FurObject says what is missing
    field = "use_color_map";
    what = "true reads the colour map at the mesh's texture coordinates";
  } else if (!so.fur_length_map.empty()) {
    field = "length_map";
    what = "a length map is read at the mesh's texture coordinates";
  } else {
    return;
  }
  throw io::InputError(scene.file.string(), io::json_index("objects", index) + ".fur." + field,
                       std::string(what) + ", and " + triangles(without) + " of mesh `" + so.mesh + "` " +
                           (without == 1 ? "has" : "have") + " none");
}

// The index of `item` in `list` (an entry `same` as it), appended when there is none.
template <class T, class Same>
uint32_t index_or_add(std::vector<T>& list, const T& item, Same same) {
  const auto it = std::find_if(list.begin(), list.end(), [&](const T& e) { return same(e, item); });
  if (it != list.end()) return uint32_t(it - list.begin());
  list.push_back(item);
  return uint32_t(list.size() - 1);
}

// Per base face, its part's entry of `of_part` (the fur's colour map or cut-out); empty when every
// part has the same one, which then stands for every face.
std::vector<uint32_t> per_face(const std::vector<uint32_t>& of_part, const MeshParts& parts, size_t triangles) {
  if (std::all_of(of_part.begin(), of_part.end(), [&](uint32_t k) { return k == of_part[0]; })) return {};
  std::vector<uint32_t> faces(triangles);
  for (size_t t = 0; t < triangles; ++t) faces[t] = of_part[parts.triangle_part.empty() ? 0 : parts.triangle_part[t]];
  return faces;
}

// Gives each part its triangles (split_mesh) with their own copies of the vertices they use:
// positions, normals, uvs and the `vc` varyings of each.
void copy_parts(const Mesh& m, const std::vector<float>& varyings, int vc, std::vector<PartSplit> split,
                std::vector<SurfacePart>& parts) {
  for (size_t k = 0; k < parts.size(); ++k) {
    SurfacePart& part = parts[k];
    Mesh& pm = part.mesh;
    part.triangle_ids = std::move(split[k].triangles);
    pm.indices = std::move(split[k].indices);
    const std::vector<uint32_t>& vertices = split[k].vertices;
    pm.positions.reserve(vertices.size());
    pm.normals.reserve(vertices.size());
    part.varyings.reserve(vertices.size() * size_t(vc));
    for (const uint32_t v : vertices) {
      pm.positions.push_back(m.positions[v]);
      pm.normals.push_back(m.normals[v]);
      if (!m.uvs.empty()) pm.uvs.push_back(m.uvs[v]);
      part.varyings.insert(part.varyings.end(), varyings.begin() + ptrdiff_t(v) * vc,
                           varyings.begin() + ptrdiff_t(v + 1) * vc);
    }
  }
}

// What an object's arrays hold, for memory_estimate.
size_t mesh_bytes(const Mesh& m, const std::vector<float>& varyings) {
  return m.positions.size() * sizeof(glm::vec3) * 2 + m.uvs.size() * sizeof(glm::vec2) +
         m.indices.size() * sizeof(uint32_t) + varyings.size() * sizeof(float);
}

}  // namespace

io::Scene apply_quality(const io::Scene& scene, const io::Quality& q) {
  io::Scene s = scene;
  for (io::SceneObject& o : s.objects) {
    if (o.fur) {
      if (q.shells && *q.shells != o.fur->shells) {
        // The same fur sliced into more or fewer layers: opacities rescaled to match.
        if (o.fur->authored_shells == 0) o.fur->authored_shells = o.fur->shells;
        o.fur->shells = *q.shells;
      }
      if (q.fins) o.fur->fins = *q.fins;
    }
    if (o.material.type == io::MaterialType::skin) {
      shading::SkinParams& k = o.material.skin;
      if (q.multiple_scattering) k.multiple_scattering = *q.multiple_scattering;
      if (q.single_scattering) k.single_scattering = *q.single_scattering;
      if (q.exact_physics) {
        k.fresnel = shading::Fresnel::exact;
        k.phase = shading::Phase::correct;
      }
    }
  }
  s.quality = q;
  return s;
}

std::vector<glm::vec2> sample_offsets(int spp) {
  int n = 1;
  while (n * n < spp) ++n;
  if (spp < 1 || n * n != spp) throw std::invalid_argument("sample_offsets: spp must be a square");
  std::vector<glm::vec2> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) out.push_back({(float(i) + 0.5f) / float(n) - 0.5f, (float(j) + 0.5f) / float(n) - 0.5f});
  return out;
}

namespace {

// A quality the frame cannot honour is the user's request, reported as bad input.
void check_quality(const io::Scene& scene, const RenderSettings& rs, const io::Quality& q) {
  if (q.spp > 1 && per_pixel_value(rs.aov))
    throw io::InputError(scene.file.string(), "quality.spp",
                         "the depth, id and overdraw AOVs are point-sampled (one value per pixel); use spp 1, got " +
                             std::to_string(q.spp));
}

// The animated lights at every frame where one may break the shader's range, before any frame
// is drawn, so that a scene whose light leaves it at frame 90 is refused before frame 0 is
// written. Between two keys a track runs monotonically from one key's value to the other's
// (linear, smooth or step), and the range bounds color x intensity from above, so the largest
// value of each track over the frames lies at one of its keys or at the first or last frame.
void check_light_tracks(const io::Scene& scene) {
  if (!scene.animation || scene.animation->lights.empty()) return;
  const int frames = scene.animation->frames;
  std::vector<int> at = {0, frames - 1};
  for (const io::LightTracks& t : scene.animation->lights)
    if (t.intensity)
      for (const auto& key : t.intensity->keys)
        if (key.frame < frames) at.push_back(key.frame);
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  FrameInputs in;
  std::vector<shading::Light> lights;
  for (int frame : at) {
    evaluate_frame_inputs(scene, frame, in);
    convert_lights(scene.file, in.lights, frame, lights);
  }
}

}  // namespace

SceneRenderer::SceneRenderer(const io::Scene& scene, const RenderSettings& settings)
    : SceneRenderer(scene, std::nullopt, settings) {}

SceneRenderer::SceneRenderer(const io::Scene& scene, std::vector<io::SceneMesh> meshes,
                             const RenderSettings& settings)
    : SceneRenderer(scene, std::optional(std::move(meshes)), settings) {}

SceneRenderer::SceneRenderer(const io::Scene& scene, std::optional<std::vector<io::SceneMesh>> meshes,
                             const RenderSettings& settings)
    : quality_(settings.quality.value_or(scene.quality)),
      scene_(apply_quality(scene, quality_)),
      settings_(settings),
      width_(settings.width > 0 ? settings.width : scene.image.width),
      height_(settings.height > 0 ? settings.height : scene.image.height),
      renderer_(settings.threads) {
  setup_stats_.frame = -1;
  check_quality(scene_, settings_, quality_);
  if (meshes && meshes->size() != scene.objects.size())
    throw std::invalid_argument("SceneRenderer: one mesh per scene object expected");
  // Budgets: what the scene file asks for before any mesh is read, the loaders check faces
  // and texture sizes as they read headers, and the memory estimate is checked from the
  // loaded counts before anything else is allocated.
  check_scene_budget(scene_, width_, height_, quality_.spp, settings_.budget, settings_.output);
  if (!meshes) {
    StageTimer t(setup_stats_, "meshes");
    meshes = io::load_scene_meshes(scene_, settings_.budget);
  }
  budget_estimate_ =
      check_memory_budget(scene_, *meshes, width_, height_, settings_.threads, quality_.spp, settings_.budget,
                          aov_shows_fur(settings_.aov), settings_.output,
                          quality_.sort == io::SortQuality::exact);  // describe-only too: it estimates the render
  build(std::move(*meshes));
}

void SceneRenderer::build(std::vector<io::SceneMesh> meshes) {
  convert_lights(scene_.file, scene_.lights, -1, lights_);
  check_light_tracks(scene_);
  // Window depth is about 1 - near / distance in a float: beyond about 2^24 x near it is 1, the far
  // plane's, for every surface, which is then drawn at that depth where nothing in front hides
  // it (raster::kClearDepth). Said, not refused: a generous far plane with the scene well inside
  // 2^24 x near draws right.
  const double depth_reach = double(scene_.camera.near) * double(1 << 24);
  if (double(scene_.camera.far) > depth_reach) {
    char reach[32];
    std::snprintf(reach, sizeof reach, "%.3g", depth_reach);
    warnings_.push_back(scene_.file.string() + " (camera.near): surfaces farther than about " + reach +
                        " scene units (2^24 x near) all take the far plane's depth, so nearer ones cannot hide "
                        "farther ones there; raise near or lower far below it");
  }
  offsets_ = sample_offsets(quality_.spp);
  const io::Scene& scene = scene_;
  const RenderSettings& settings = settings_;
  // Set-up work that splits into independent items (blurred normals, texture rows and strand
  // layers) runs on the render's threads; each gives the same result on any count.
  const raster::ParallelFor parallel = [this](size_t count, const std::function<void(size_t)>& fn) {
    renderer_.parallel_for(count, [&fn](size_t k, int) { fn(k); });
  };
  uint32_t id_base = 0;
  input_files_.push_back(scene.file);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const io::SceneObject& so = scene.objects[i];
    if (!so.mesh_path.empty()) input_files_.push_back(so.mesh_path);
    const std::string mesh_field = io::json_child(io::json_index("objects", i), "mesh");
    for (const std::string& w : meshes[i].loaded.warnings) warnings_.push_back(so.mesh + " (" + mesh_field + "): " + w);
    auto obj = std::make_unique<Object>();
    obj->mesh = std::move(meshes[i].loaded.mesh);
    io::bake_transform(obj->mesh, meshes[i].model);
    const Mesh& m = obj->mesh;
    obj->material.kind = kind_of(so.material.type);
    obj->material.color = so.material.color;
    obj->material.basic = so.material.basic;
    obj->material.skin = so.material.skin;
    obj->material.filter = quality_.filter;
    obj->material.double_precision = quality_.precision == io::Precision::double_precision;
    obj->double_sided = so.material.double_sided;
    obj->id_base = id_base;
    id_base += static_cast<uint32_t>(m.triangle_count());

    // Internally v = 0 is the top row of an image (glTF); OBJ files count v from the bottom, and
    // place their maps (MTL -s, -o) in their own uvs.
    const io::LoadedMesh& loaded = meshes[i].loaded;  // its mesh moved out above; its maps kept
    const bool v_up = loaded.format == io::MeshFormat::obj;
    if (v_up)
      for (glm::vec2& uv : obj->mesh.uvs) uv.y = 1.0f - uv.y;
    const auto ours = [v_up](const io::MapPlacement& p) { return v_up ? io::flipped_v(p) : p; };
    // Each image is read once, however many parts draw it: the scene's map (every part's),
    // or a file's or embedded image the mesh names.
    std::map<MapImage, const raster::Texture*> read;
    const auto load_map = [&](const MapKind& kind, const std::filesystem::path& from_scene, const io::TextureRef& named,
                              const std::string& material, bool alpha,
                              io::MapPlacement& file_placement) -> const raster::Texture* {
      const std::optional<MapSource> src = map_source(from_scene, named);
      if (!src) return nullptr;
      file_placement = src->named_by_mesh ? named.placement : io::MapPlacement{};
      const MapImage key = map_image(kind.field, *src, alpha);
      if (const auto it = read.find(key); it != read.end()) return it->second;
      auto tex = std::make_unique<raster::Texture>();
      load_object_map(scene, i, kind, from_scene, named, material, alpha, loaded, obj->mesh, settings.budget, parallel,
                      *tex, setup_stats_, input_files_);
      obj->textures.push_back(std::move(tex));
      return read[key] = obj->textures.back().get();
    };
    const MeshParts parts = mesh_parts(so, loaded);
    // Faces the file gave no texture coordinates (LoadedMesh::uv_missing), per part: a map drawn
    // on them would read uv (0, 0), one texel, so it is refused.
    std::vector<size_t> uvless(parts.count(), 0);
    std::vector<const std::string*> uvless_material(parts.count(), nullptr);  // of the part's first such face
    for (size_t t = 0; t < m.triangle_count() && !loaded.uv_missing.empty(); ++t) {
      if (!io::lacks_uv(m, loaded.uv_missing, t)) continue;
      const size_t p = parts.triangle_part.empty() ? 0 : parts.triangle_part[t];
      if (uvless[p]++ == 0) uvless_material[p] = &loaded.set(loaded.maps_of(t)).material;
    }
    bool any_map = false, any_normal_map = false, any_color_map = false;
    for (const uint32_t k : parts.first_set) {
      const io::MeshMaps& set = loaded.set(k);
      if (const size_t p = obj->parts.size(); uvless[p] > 0) refuse_uvless_map(scene, i, set, *uvless_material[p], uvless[p]);
      SurfacePart& part = obj->parts.emplace_back();
      part.material = parts.count() > 1 ? set.material : std::string();
      part.desc = obj->material;
      part.desc.color_map = load_map(kColorMap, so.material.color_map, set.color_map, set.material, keeps_alpha(set),
                                     part.file_color_placement);
      part.desc.color_placement = ours(part.file_color_placement);
      if (const std::filesystem::path* dissolve = set.color_map.dissolve_file();
          dissolve && part.desc.color_map && map_source(so.material.color_map, set.color_map)->named_by_mesh) {
        part.alpha_map = dissolve->filename().string();
        part.alpha_map_alone = set.color_map.dissolved_color_file() == nullptr;
      }
      part.desc.normal_map =
          load_map(kNormalMap, so.material.normal_map, set.normal_map, set.material, false, part.file_normal_placement);
      part.desc.normal_placement = ours(part.file_normal_placement);
      part.desc.alpha_mode = set.alpha_mode;
      part.desc.alpha_cutoff = set.alpha_cutoff;
      part.desc.alpha_factor = set.alpha_factor;
      part.desc.mask_cuts = mask_cuts(part.desc);
      any_map |= part.desc.color_map || part.desc.normal_map;
      any_normal_map |= part.desc.normal_map != nullptr;
      any_color_map |= part.desc.color_map != nullptr;
    }
    shading::BlurredNormals blurred;
    const bool blur = obj->material.kind == MaterialKind::skin &&
                      obj->material.skin.multiple_scattering == shading::MultipleScattering::normal_blur;
    if (blur) {
      StageTimer t(setup_stats_, "normal_blur");
      const shading::NormalBlurInput in{&m.positions[0].x, &m.normals[0].x, m.vertex_count(),
                                        m.indices.data(), m.indices.size()};
      // A search per vertex (0.5 s on the head scan on one core): spread over the render's threads.
      const shading::NormalBlurBudget blur_budget{settings.budget.max_blur_pairs, io::kMaxBlurPairsFlag,
                                                  settings.describe_only};
      if (auto e = shading::blur_normals(in, obj->material.skin.normal_blur_radius, blurred, parallel, blur_budget))
        throw io::InputError(scene.file.string(), "objects[" + std::to_string(i) + "].material.skin." + e->field,
                             e->reason);
      obj->blur_pairs = blurred.pair_estimate;
      obj->varying_count = SurfaceVaryings::kCountBlurred;
    } else if (!any_map) {
      obj->varying_count = SurfaceVaryings::kCountWithoutUv;
    }
    const int tangent_slot = any_normal_map ? obj->varying_count : -1;
    if (any_normal_map) obj->varying_count += 4;
    const int vc = obj->varying_count;
    obj->varyings.assign(m.vertex_count() * vc, 0.0f);
    for (size_t v = 0; v < m.vertex_count(); ++v) {
      float* dst = obj->varyings.data() + v * vc;
      dst[SurfaceVaryings::kPos + 0] = m.positions[v].x;
      dst[SurfaceVaryings::kPos + 1] = m.positions[v].y;
      dst[SurfaceVaryings::kPos + 2] = m.positions[v].z;
      dst[SurfaceVaryings::kNormal + 0] = m.normals[v].x;
      dst[SurfaceVaryings::kNormal + 1] = m.normals[v].y;
      dst[SurfaceVaryings::kNormal + 2] = m.normals[v].z;
      if (!m.uvs.empty() && vc > SurfaceVaryings::kUv) {
        dst[SurfaceVaryings::kUv + 0] = m.uvs[v].x;
        dst[SurfaceVaryings::kUv + 1] = m.uvs[v].y;
      }
      if (blur && !settings.describe_only)
        for (int c = 0; c < 3; ++c)
          for (int k = 0; k < 3; ++k) dst[SurfaceVaryings::kBlurred + 3 * c + k] = blurred.channel[c][3 * v + k];
    }
    const bool split = parts.count() > 1;
    if (split) {
      copy_parts(m, obj->varyings, vc, split_mesh(m, parts), obj->parts);
      obj->varyings = {};  // each part has its own
    }
    for (SurfacePart& part : obj->parts) {
      const Mesh& pm = split ? part.mesh : m;
      float* const varyings = split ? part.varyings.data() : obj->varyings.data();
      if (part.desc.normal_map) {
        const io::MapPlacement& np = part.desc.normal_placement;
        // The frame of the normal map's own uvs: a rotation or a negative scale turns it.
        std::vector<glm::vec2> placed;
        if (np.transforms()) {
          placed.reserve(pm.uvs.size());
          for (const glm::vec2& uv : pm.uvs) placed.emplace_back(np.u_at(uv.x, uv.y), np.v_at(uv.x, uv.y));
        }
        const std::vector<glm::vec4> tangents = compute_vertex_tangents(pm, np.transforms() ? placed : pm.uvs);
        part.desc.tangent_slot = tangent_slot;
        for (size_t v = 0; v < pm.vertex_count(); ++v)
          for (int k = 0; k < 4; ++k) varyings[v * vc + size_t(tangent_slot) + k] = tangents[v][k];
      }
      part.shader = std::make_unique<MaterialShader>(part.desc, lights_, scene.camera.eye, layer_of(settings.aov));
    }
    if (so.fur) {
      // The fur of a mesh some of whose faces have no uvs is built as on a mesh without any (the
      // box mapping, or the projection, lays its strands), once nothing it is asked for reads them:
      // the uvs are set aside while it is built.
      const size_t uvless_faces = std::accumulate(uvless.begin(), uvless.end(), size_t{0});
      if (uvless_faces > 0) refuse_uvless_fur(scene, i, any_color_map, uvless_faces);
      std::vector<glm::vec2> set_aside;
      if (uvless_faces > 0) set_aside.swap(obj->mesh.uvs);
      FurDrawOptions fo;
      fo.match_llvmpipe = settings.match_llvmpipe;
      fo.lighting = settings.fur_lighting;
      fo.filter = quality_.filter;
      fo.double_precision = quality_.precision == io::Precision::double_precision;
      fo.grey_varyings = settings.fur_grey_varyings;
      fo.merge_fins = quality_.fin_quads == io::FinQuads::merged;
      fo.parallel = parallel;
      fo.textures = !settings.describe_only && aov_shows_fur(settings.aov);
      // The fur reads each part's colour image without its alpha (one part may read it with, for
      // a cut-out, another without: the fur takes the colour alone), one map per image and
      // placement; with several, or faces of no map beside mapped ones, per base face its map.
      if (so.fur->use_color_map && any_color_map) {
        std::vector<uint32_t> map_of_part(parts.count(), kNoFurColorMap);
        for (size_t p = 0; p < parts.count(); ++p) {
          const SurfacePart& part = obj->parts[p];
          if (!part.desc.color_map) continue;
          const io::MeshMaps& set = loaded.set(parts.first_set[p]);
          io::MapPlacement unused;
          const FurColorMap map{load_map(kColorMap, so.material.color_map, set.color_map, set.material, false, unused),
                                part.desc.color_placement};
          map_of_part[p] = index_or_add(fo.color_maps, map, [](const FurColorMap& a, const FurColorMap& b) {
            return a.texture == b.texture && a.placement == b.placement;
          });
        }
        fo.face_color_map = per_face(map_of_part, parts, m.triangle_count());
      }
      // The fur is cut where its surface is (alphaMode MASK): each such part's map with its alpha,
      // as the surface reads it, one cut-out per distinct test; per base face when not every part
      // is cut alike.
      std::vector<uint32_t> cut_of_part(parts.count(), kNoFurCut);
      std::map<const raster::Texture*, const raster::Texture*> cut_alpha;  // each map's alpha copied once
      for (size_t p = 0; p < parts.count(); ++p) {
        const MaterialDesc& d = obj->parts[p].desc;
        // A part cut nowhere (no MASK, or one whose map's alphas all pass) has no cut-out, and where
        // the fur is not drawn there is nothing to cut. One that cuts everywhere reads no map (a
        // furry mesh's tiles took 1.5x the time sampling a map that cut nothing).
        if (d.mask_cuts == MaskCuts::nothing || !fo.textures) continue;
        FurCutMap cut{{nullptr, d.color_placement}, d.alpha_factor, d.alpha_cutoff};
        if (d.mask_cuts == MaskCuts::everything) {
          // The cutoff is above 0 here, which a factor of 0 never reaches: FurObject then draws
          // nothing of these faces.
          cut.factor = 0.0f;
        } else {  // some: a map's alphas on both sides of the cutoff
          const raster::Texture*& copy = cut_alpha[d.color_map];
          if (!copy) {
            StageTimer t(setup_stats_, "textures");
            obj->textures.push_back(std::make_unique<raster::Texture>(cut_alpha_texture(*d.color_map, parallel)));
            copy = obj->textures.back().get();
          }
          cut.map.texture = copy;
        }
        cut_of_part[p] = index_or_add(fo.cut_maps, cut, [](const FurCutMap& a, const FurCutMap& b) {
          return a.map.texture == b.map.texture && (!a.map.texture || a.map.placement == b.map.placement) &&
                 a.factor == b.factor && a.cutoff == b.cutoff;
        });
      }
      fo.face_cut_map = per_face(cut_of_part, parts, m.triangle_count());
      // Set aside for the strands' layout, the uvs are still where a cut-out's map is read.
      if (!fo.cut_maps.empty() && uvless_faces > 0) fo.map_uvs = set_aside;
      if (!so.fur_length_map.empty()) {
        StageTimer t(setup_stats_, "textures");
        input_files_.push_back(so.fur_length_map);
        fo.length_scale = read_length_map(so.fur_length_map, obj->mesh, so.mesh, scene.file.string(),
                                          io::json_child(io::json_child(io::json_index("objects", i), "fur"),
                                                         "length_map"),
                                          settings.budget);
      }
      obj->fur = std::make_unique<FurObject>(obj->mesh, *so.fur, fo,
                                             FurOrigin{scene.file.string(), io::json_index("objects", i)}, setup_stats_);
      if (uvless_faces > 0) obj->mesh.uvs.swap(set_aside);  // a throw above ends the set-up: nothing to restore
      if (obj->fur->geometry().uvs_cover_no_area)
        warnings_.push_back(so.mesh + " (" + io::json_index("objects", i) +
                            ".fur): the mesh's texture coordinates cover no area, so the strands are laid by the box mapping "
                            "(texture_coordinates \"box\" says so and silences this)");
    }
    objects_.push_back(std::move(obj));
  }
}

SceneRenderer::~SceneRenderer() = default;

int SceneRenderer::frame_count() const { return scene_.animation ? scene_.animation->frames : 1; }

uint64_t SceneRenderer::base_triangles() const {
  uint64_t n = 0;
  for (const auto& o : objects_) n += o->mesh.triangle_count();
  return n;
}

uint64_t SceneRenderer::fur_triangles() const {
  uint64_t n = 0;
  for (const auto& o : objects_)
    if (o->fur) n += o->fur->triangles();
  return n;
}

size_t SceneRenderer::memory_estimate() const {
  size_t n = 0;
  for (const auto& o : objects_) {
    n += mesh_bytes(o->mesh, o->varyings);
    for (const auto& t : o->textures) n += t->bytes();
    for (const SurfacePart& p : o->parts) n += mesh_bytes(p.mesh, p.varyings) + p.triangle_ids.size() * sizeof(uint32_t);
    if (o->fur) n += o->fur->memory_bytes();
  }
  const size_t pixels = size_t(width_) * height_;
  n += pixels * 4 * sizeof(float);  // the colour image
  const size_t exact =
      quality_.sort == io::SortQuality::exact ? raster::Renderer::exact_sort_bytes(raster::kExactFragmentCap) : 0;
  return n + size_t(std::max(1, settings_.threads)) * (raster::Renderer::worker_scratch_bytes() + exact);
}

const fur::FurCounts* SceneRenderer::fur_counts(size_t object) const {
  const fur::FurGeometry* g = fur_geometry(object);
  return g ? &g->counts : nullptr;
}

const fur::FurGeometry* SceneRenderer::fur_geometry(size_t object) const {
  return objects_[object]->fur ? &objects_[object]->fur->geometry() : nullptr;
}

std::vector<SceneRenderer::MapsDrawn> SceneRenderer::maps_drawn(size_t object) const {
  std::vector<MapsDrawn> out;
  for (const SurfacePart& p : objects_[object]->parts) {
    MapsDrawn& m = out.emplace_back();
    m.material = p.material;
    m.triangles = objects_[object]->parts.size() == 1 ? objects_[object]->mesh.triangle_count() : p.triangle_ids.size();
    m.color = p.desc.color_map != nullptr;
    m.normal = p.desc.normal_map != nullptr;
    m.color_placement = p.file_color_placement;
    m.normal_placement = p.file_normal_placement;
    m.alpha_mode = p.desc.alpha_mode;
    m.alpha_cutoff = p.desc.alpha_cutoff;
    m.alpha_factor = p.desc.alpha_factor;
    m.cut_away = p.desc.mask_cuts == MaskCuts::everything;
    m.alpha_map = p.alpha_map;
    m.alpha_map_alone = p.alpha_map_alone;
  }
  return out;
}

std::optional<uint64_t> SceneRenderer::blur_pair_estimate(size_t object) const {
  return objects_[object]->blur_pairs;
}

int SceneRenderer::fur_varying_count(size_t object) const {
  return objects_[object]->fur ? objects_[object]->fur->varying_count() : 0;
}

void SceneRenderer::render(int frame, FrameImage& out, FrameStats& stats, const io::Camera* camera_override) {
  if (settings_.describe_only) throw std::logic_error("SceneRenderer: a describe_only renderer draws no frame");
  stats = FrameStats{};
  stats.frame = frame;
  if (!setup_reported_) {
    for (size_t i = 0; i < kStageCount; ++i) stats.stages[i] = setup_stats_.stages[i];
    setup_reported_ = true;
  }

  // Everything that may vary per frame, from the scene's keyframes; static values come
  // back identical, so the fur stages below recompute only what changed.
  evaluate_frame_inputs(scene_, frame, inputs_);
  const FrameInputs& inputs = inputs_;
  const io::Camera& camera = camera_override ? *camera_override : inputs.camera;
  convert_lights(scene_.file, inputs.lights, frame, lights_);
  const float aspect = float(width_) / float(height_);
  const glm::mat4 clip_from_world = camera.projection(aspect) * camera.view();
  const FurSort fur_sort = quality_.sort;
  const bool fur_shows = aov_shows_fur(settings_.aov);
  for (size_t i = 0; i < objects_.size(); ++i) {
    if (!objects_[i]->fur || !fur_shows) continue;
    FurFrame f;
    f.frame = frame;
    f.time_seconds = inputs.time_seconds;
    f.still = !scene_.animation;
    f.sort = fur_sort;
    f.eye = camera.eye;
    f.clip_from_world = clip_from_world;
    f.wind = inputs.fur[i].wind;
    f.gravity = inputs.fur[i].gravity;
    objects_[i]->fur->update(f, lights_, stats);
  }
  std::vector<raster::DrawCall>& draws = draws_;
  draws.clear();
  for (const auto& o : objects_)
    for (const SurfacePart& p : o->parts) {
      // A MASK part whose test fails on every texel of its map leaves no fragment: not drawn
      // (its fur is cut away whole too, see the fur's cut-outs), where it was set up and shaded
      // for every pixel it covers only to be discarded.
      if (p.desc.mask_cuts == MaskCuts::everything) continue;
      p.shader->set_view(lights_, camera.eye);
      const bool whole = o->parts.size() == 1;  // the object's own arrays
      const Mesh& m = whole ? o->mesh : p.mesh;
      raster::DrawCall d;
      d.positions = m.positions.data();
      d.vertex_count = static_cast<uint32_t>(m.vertex_count());
      d.indices = m.indices.data();
      d.triangle_count = static_cast<uint32_t>(m.triangle_count());
      d.varyings = whole ? o->varyings.data() : p.varyings.data();
      d.varying_count = static_cast<uint32_t>(o->varying_count);
      d.clip_from_object = clip_from_world;
      d.shader = p.shader.get();
      d.id_base = o->id_base;
      d.triangle_ids = whole ? nullptr : p.triangle_ids.data();
      // Single-sided (the default) culls back faces: they cannot be seen on a closed mesh,
      // and skipping them halves the set-up and depth work of a dense scan.
      d.state.cull = o->double_sided ? raster::CullMode::None : raster::CullMode::Back;
      // A translucent skin blends every part (a cut-out one cut by its shader).
      if (p.desc.translucent() || p.desc.alpha_mode == io::AlphaMode::blend) {
        d.state.blend = raster::BlendMode::AlphaOver;
        d.state.depth_write = false;
      } else if (p.desc.mask_cuts != MaskCuts::nothing) {
        // (One that cuts nothing is drawn opaque: an alpha-tested draw is shaded twice.)
        d.state.alpha_test = true;
        d.state.alpha_cutoff = p.desc.alpha_cutoff;
      }
      draws.push_back(d);
    }
  // Translucent fur after every opaque draw (the rasterizer shades opaque work first
  // anyway; this keeps the translucent submission order object by object).
  for (const auto& o : objects_)
    if (o->fur && fur_shows) o->fur->append_draws(draws);

  out.width = width_;
  out.height = height_;
  const size_t px = size_t(width_) * height_;
  raster::RenderTarget target{width_, height_};
  switch (settings_.aov) {
    case Aov::depth:
      out.depth.resize(px);
      target.depth = out.depth.data();
      break;
    case Aov::id:
      out.id.resize(px);
      target.id = out.id.data();
      break;
    case Aov::overdraw:
      out.overdraw.resize(px);
      target.overdraw = out.overdraw.data();
      break;
    default:
      if (settings_.color8) {
        out.color8.resize(px * 4);
        target.color8 = out.color8.data();
      }
      // Supersampling averages float passes (below), and converts the average once.
      if (!settings_.color8 || offsets_.size() > 1) {
        out.color.resize(px * 4);
        target.color = out.color.data();
      }
      break;
  }
  raster::RenderOptions opt;
  // The scene gives the background straight; the planes hold premultiplied colour, so a
  // background of alpha 0 adds nothing to a translucent pixel's colour.
  const glm::vec4 bg = scene_.image.background;
  opt.background = glm::vec4(glm::vec3(bg) * bg.a, bg.a);
  opt.sort = raster_sort_mode(fur_sort);
  // Supersampling: one full pass per stratified sample, the projection shifted by the
  // sample's sub-pixel offset, the passes' colours summed in double in a fixed order (so
  // the result is the same on any thread count) and divided once. Each pass composites its
  // own translucent fragments, so the average is the box-filtered, correctly sorted image.
  const std::vector<glm::vec2>& offsets = offsets_;
  if (offsets.size() > 1) {
    sample_color_.resize(px * 4);
    accum_.assign(px * 4, 0.0);
    target.color = sample_color_.data();
    target.color8 = nullptr;
  }
  stats.samples = static_cast<int>(offsets.size());
  for (const glm::vec2& o : offsets) {
    if (offsets.size() > 1) {
      // Image rows grow downward, clip-space y upward.
      const glm::mat4 jitter = glm::translate(
          glm::mat4(1.0f), glm::vec3(2.0f * o.x / float(width_), -2.0f * o.y / float(height_), 0.0f));
      const glm::mat4 m = jitter * clip_from_world;
      for (raster::DrawCall& d : draws) d.clip_from_object = m;
    }
    raster::RasterStats rs;
    renderer_.render(draws, opt, target, &rs);
    stats.raster += rs;
    if (offsets.size() > 1)
      for (size_t i = 0; i < px * 4; ++i) accum_[i] += sample_color_[i];
  }
  if (offsets.size() > 1) {
    const double inv = 1.0 / double(offsets.size());
    for (size_t i = 0; i < px * 4; ++i) out.color[i] = static_cast<float>(accum_[i] * inv);
    if (settings_.color8)  // supersampling is for the colour AOVs only (quality.spp's check)
      for (size_t i = 0; i < px * 4; ++i) out.color8[i] = raster::unorm8(out.color[i]);
  }
  stats.stage("raster_front") = {true, stats.raster.ms_front};
  stats.stage("raster_tiles") = {true, stats.raster.ms_tiles};
}

}  // namespace pelt::render
