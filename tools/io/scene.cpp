#include "tools/io/scene.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "raster/clip.h"
#include "tools/io/animation_block.h"
#include "tools/io/input_error.h"
#include "tools/io/json_fields.h"
#include "tools/io/scene_blocks.h"
#include "tools/io/suggest.h"

namespace pelt::io {
namespace {

using nlohmann::json;

// Line and column (1-based) of a byte offset, for parse errors.
std::pair<size_t, size_t> line_column(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

// A scene file's text is read up to this size.
constexpr size_t kMaxSceneBytes = size_t{64} << 20;

// A file a scene refers to must exist and open for reading, checked at load time so the
// error names the scene field rather than surfacing mid-render.
void check_readable(const JsonFields& js, const std::filesystem::path& p, const std::string& field,
                    const char* what) {
  if (p.native().find('\0') != std::string::npos)
    js.fail(field, std::string(what) + " `" + p.string() + "` holds a NUL character, which no file path can hold");
  if (const std::string reason = unreadable_file_reason(p); !reason.empty())
    js.fail(field, std::string(what) + " `" + p.string() + "` " + reason);
  std::ifstream probe(p, std::ios::binary);
  if (!probe) js.fail(field, std::string(what) + " `" + p.string() + "` cannot be read");
}

std::filesystem::path resolve(const std::filesystem::path& scene_file, const std::string& rel) {
  const std::filesystem::path p(rel);
  return p.is_absolute() ? p : scene_file.parent_path() / p;
}

ImageSettings parse_image(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path, {"width", "height", "background"});
  ImageSettings s;
  if (const json* v = JsonFields::find(j, "width"))
    s.width = static_cast<int>(js.integer(*v, json_child(path, "width"), 1, kMaxImageSide));
  if (const json* v = JsonFields::find(j, "height"))
    s.height = static_cast<int>(js.integer(*v, json_child(path, "height"), 1, kMaxImageSide));
  if (const json* v = JsonFields::find(j, "background")) {
    const std::string field = json_child(path, "background");
    const auto c = js.numbers(*v, field, 3, 4);
    for (size_t k = 0; k < c.size(); ++k) {
      if (c[k] < 0.0) js.fail(json_index(field, k), "must be >= 0, got " + std::to_string(c[k]));
      s.background[static_cast<int>(k)] = static_cast<float>(c[k]);
    }
    if (c.size() == 4 && c[3] > 1.0) js.fail(json_index(field, 3), "alpha must be in [0, 1]");
  }
  return s;
}

Camera parse_camera(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path, {"eye", "target", "up", "fovy_deg", "near", "far"});
  Camera c;
  if (const json* v = JsonFields::find(j, "eye")) c.eye = js.vec3(*v, json_child(path, "eye"));
  if (const json* v = JsonFields::find(j, "target")) c.target = js.vec3(*v, json_child(path, "target"));
  if (const json* v = JsonFields::find(j, "up")) c.up = js.direction(*v, json_child(path, "up"));
  if (const json* v = JsonFields::find(j, "fovy_deg"))
    c.fovy_deg = static_cast<float>(js.number_in(*v, json_child(path, "fovy_deg"), 0.0, 180.0, true, true));
  if (const json* v = JsonFields::find(j, "near")) {
    const double near = js.number_in(*v, json_child(path, "near"), 0.0, 1e30, true);
    c.near = static_cast<float>(near);
    // The rasterizer keeps no vertex nearer the eye than raster::kMinW (its floor on clip w, which
    // keeps 1/w within a float's planes): with a nearer plane, what lies between would vanish
    // without a word.
    if (near < raster::kMinW)
      js.fail(json_child(path, "near"), "must be at least 1e-06, the nearest view depth pelt draws, got " +
                                            v->dump() + " (scale the scene up instead)");
  }
  if (const json* v = JsonFields::find(j, "far"))
    c.far = static_cast<float>(js.number_in(*v, json_child(path, "far"), 0.0, 1e30, true));
  if (!(c.far > c.near))
    js.fail(json_child(path, "far"), "must be greater than near (" + std::to_string(c.near) + "), got " +
                                         std::to_string(c.far));
  const glm::dvec3 forward = glm::dvec3(c.target) - glm::dvec3(c.eye);
  if (!(glm::length(forward) > 1e-9)) js.fail(json_child(path, "target"), "must differ from eye");
  if (!(glm::length(glm::cross(glm::normalize(forward), glm::dvec3(c.up))) > 1e-6))
    js.fail(json_child(path, "up"), "must not be parallel to the view direction (target - eye)");
  return c;
}

Light parse_light(const JsonFields& js, const json& j, const std::string& path) {
  if (!j.is_object()) js.fail(path, "expected an object, got " + json_type_name(j));
  const std::string type_field = json_child(path, "type");
  const std::string type = js.string(js.require(j, path, "type"), type_field);
  Light l;
  if (type == "directional") {
    l.type = LightType::directional;
    js.expect_object(j, path, {"type", "direction", "color", "intensity"});
    l.direction = js.direction(js.require(j, path, "direction"), json_child(path, "direction"));
  } else if (type == "point") {
    l.type = LightType::point;
    js.expect_object(j, path, {"type", "position", "color", "intensity"});
    l.position = js.vec3(js.require(j, path, "position"), json_child(path, "position"));
  } else if (type == "ambient") {
    l.type = LightType::ambient;
    js.expect_object(j, path, {"type", "color", "intensity"});
  } else {
    static constexpr std::string_view kTypes[] = {"directional", "point", "ambient"};
    const std::string hint = did_you_mean(type, kTypes);
    js.fail(type_field, "unknown light type `" + type + "`" +
                            (hint.empty() ? "; expected directional, point or ambient" : hint));
  }
  if (const json* v = JsonFields::find(j, "color")) l.color = js.vec3_in(*v, json_child(path, "color"), 0.0, 1e6);
  if (const json* v = JsonFields::find(j, "intensity"))
    l.intensity = static_cast<float>(js.number_in(*v, json_child(path, "intensity"), 0.0, 1e6));
  return l;
}

Transform parse_transform(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path, {"translate", "rotate_deg", "scale"});
  Transform t;
  if (const json* v = JsonFields::find(j, "translate")) t.translate = js.vec3(*v, json_child(path, "translate"));
  if (const json* v = JsonFields::find(j, "rotate_deg")) t.rotate_deg = js.vec3(*v, json_child(path, "rotate_deg"));
  if (const json* v = JsonFields::find(j, "scale")) {
    const std::string field = json_child(path, "scale");
    if (v->is_number()) {
      const double s = js.number(*v, field);
      if (s == 0.0) js.fail(field, "must be non-zero");
      t.scale = glm::vec3(static_cast<float>(s));
    } else if (v->is_array()) {
      t.scale = js.vec3(*v, field);
      for (int k = 0; k < 3; ++k)
        if (t.scale[k] == 0.0f) js.fail(json_index(field, k), "must be non-zero");
    } else {
      js.fail(field, "expected a number or an array of 3 numbers, got " + json_type_name(*v));
    }
  }
  return t;
}

Material parse_material(const JsonFields& js, const json& j, const std::string& path,
                        const std::filesystem::path& scene_file) {
  if (!j.is_object()) js.fail(path, "expected an object, got " + json_type_name(j));
  const std::string type_field = json_child(path, "type");
  const std::string type = js.string(js.require(j, path, "type"), type_field);
  Material m;
  // Extension point: a material type adds its name here and its own keys below.
  if (type == "unlit") m.type = MaterialType::unlit;
  else if (type == "lambert") m.type = MaterialType::lambert;
  else if (type == "blinn") m.type = MaterialType::blinn;
  else if (type == "skin") m.type = MaterialType::skin;
  else {
    static constexpr std::string_view kTypes[] = {"unlit", "lambert", "blinn", "skin"};
    const std::string hint = did_you_mean(type, kTypes);
    js.fail(type_field, "unknown material type `" + type + "`" +
                            (hint.empty() ? "; expected unlit, lambert, blinn or skin" : hint));
  }
  switch (m.type) {
    case MaterialType::blinn:
      js.expect_object(j, path, {"type", "color", "specular", "shininess", "color_map", "normal_map", "double_sided"});
      break;
    case MaterialType::skin:
      js.expect_object(j, path, {"type", "color_map", "normal_map", "double_sided", "skin"});
      break;
    default:
      js.expect_object(j, path, {"type", "color", "color_map", "normal_map", "double_sided"});
  }
  if (const json* v = JsonFields::find(j, "color")) m.color = js.vec3_in(*v, json_child(path, "color"), 0.0, 1.0);
  if (const json* v = JsonFields::find(j, "specular")) {
    const glm::vec3 s = js.vec3_in(*v, json_child(path, "specular"), 0.0, 100.0);
    for (int k = 0; k < 3; ++k) m.basic.specular[k] = s[k];
  }
  if (const json* v = JsonFields::find(j, "shininess"))
    m.basic.shininess = static_cast<float>(js.number_in(*v, json_child(path, "shininess"), 1.0, 256.0));
  if (const json* v = JsonFields::find(j, "color_map")) {
    const std::string field = json_child(path, "color_map");
    m.color_map = resolve(scene_file, js.string(*v, field));
    check_readable(js, m.color_map, field, "colour map");
  }
  if (const json* v = JsonFields::find(j, "normal_map")) {
    const std::string field = json_child(path, "normal_map");
    m.normal_map = resolve(scene_file, js.string(*v, field));
    check_readable(js, m.normal_map, field, "normal map");
  }
  if (const json* v = JsonFields::find(j, "double_sided"))
    m.double_sided = js.boolean(*v, json_child(path, "double_sided"));
  if (const json* v = JsonFields::find(j, "skin")) m.skin = detail::parse_skin_block(js, *v, json_child(path, "skin"));
  return m;
}

SceneObject parse_object(const JsonFields& js, const json& j, const std::string& path,
                         const std::filesystem::path& scene_file) {
  js.expect_object(j, path, {"name", "mesh", "transform", "material", "fur"});
  SceneObject o;
  o.name = path;
  if (const json* v = JsonFields::find(j, "name")) o.name = js.string(*v, json_child(path, "name"));
  const std::string mesh_field = json_child(path, "mesh");
  o.mesh = js.string(js.require(j, path, "mesh"), mesh_field);
  if (o.mesh.empty()) js.fail(mesh_field, "must name a built-in (e.g. `box:8`) or a mesh file");
  if (looks_like_builtin_spec(o.mesh)) {
    o.builtin = parse_builtin_spec(o.mesh, js.file(), mesh_field);
  } else {
    o.mesh_path = resolve(scene_file, o.mesh);
    check_readable(js, o.mesh_path, mesh_field, "mesh file");
  }
  if (const json* v = JsonFields::find(j, "transform")) o.transform = parse_transform(js, *v, json_child(path, "transform"));
  o.material = parse_material(js, js.require(j, path, "material"), json_child(path, "material"), scene_file);
  // Extension point: per-object effect blocks (fur today) are parsed by their owners' rules.
  if (const json* v = JsonFields::find(j, "fur")) {
    const std::string fur_path = json_child(path, "fur");
    o.fur = detail::parse_fur_block(js, *v, fur_path);
    // A file, so read here with the scene's other paths; fur/ knows no files.
    if (const json* m = JsonFields::find(*v, "length_map")) {
      const std::string field = json_child(fur_path, "length_map");
      o.fur_length_map = resolve(scene_file, js.string(*m, field));
      check_readable(js, o.fur_length_map, field, "length map");
    }
  }
  return o;
}

}  // namespace

glm::mat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::mat4 Camera::projection(float aspect) const {
  return glm::perspective(glm::radians(fovy_deg), aspect, near, far);
}

glm::mat4 Transform::matrix() const {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
  m = glm::rotate(m, glm::radians(rotate_deg.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotate_deg.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotate_deg.x), glm::vec3(1, 0, 0));
  return glm::scale(m, scale);
}

Scene parse_scene(const std::string& text, const std::filesystem::path& file) {
  const JsonFields js(file.string());
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    // nlohmann prefixes "[json.exception.parse_error.101] parse error at line L, column C: ".
    if (const size_t colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
    js.fail("", "malformed JSON at line " + std::to_string(line) + ", column " + std::to_string(col) +
                    ": " + what);
  } catch (const json::exception& e) {
    // Numbers beyond double range (1e999) are not parse errors to nlohmann but range errors.
    std::string what = e.what();
    if (const size_t bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    js.fail("", "malformed JSON: " + what + " (numbers must be finite)");
  }
  if (const std::optional<std::string> repeated = find_repeated_key(text))
    js.fail(*repeated, "given twice in the same object; keep one (a JSON reader takes the later without a word)");
  js.expect_object(root, "", {"pelt", "image", "camera", "lights", "objects", "animation", "quality"});
  const json& version = js.require(root, "", "pelt");
  if (!version.is_number())
    js.fail("pelt", "expected the format version number 1, got " + json_type_name(version));
  // As a double: 1.0 is version 1, and a huge or negative number is named as written.
  if (version.get<double>() != double(kSceneVersion)) {
    std::ostringstream v;
    v << version;
    js.fail("pelt", "unsupported format version " + v.str() + " (this build reads version " +
                        std::to_string(kSceneVersion) + ")");
  }

  Scene s;
  s.file = file;
  if (const json* v = JsonFields::find(root, "image")) s.image = parse_image(js, *v, "image");
  if (const json* v = JsonFields::find(root, "camera")) s.camera = parse_camera(js, *v, "camera");
  if (const json* v = JsonFields::find(root, "lights")) {
    if (!v->is_array()) js.fail("lights", "expected an array, got " + json_type_name(*v));
    for (size_t i = 0; i < v->size(); ++i) s.lights.push_back(parse_light(js, (*v)[i], json_index("lights", i)));
  }
  const json& objects = js.require(root, "", "objects");
  if (!objects.is_array()) js.fail("objects", "expected an array, got " + json_type_name(objects));
  if (objects.empty()) js.fail("objects", "needs at least one object");
  for (size_t i = 0; i < objects.size(); ++i)
    s.objects.push_back(parse_object(js, objects[i], json_index("objects", i), file));
  if (const json* v = JsonFields::find(root, "animation"))
    s.animation = detail::parse_animation_block(js, *v, "animation", s);
  if (const json* v = JsonFields::find(root, "quality")) s.quality = detail::parse_quality_block(js, *v, "quality");
  return s;
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw InputError(file.string(), "", "scene file not found");
  if (std::filesystem::is_directory(file, ec)) throw InputError(file.string(), "", "is a folder, not a scene file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "", "cannot open the scene file for reading");
  // Read in pieces up to a bound: a scene may come through a pipe (`pelt render <(make_scene)`),
  // but a device such as /dev/zero would otherwise be read until memory runs out.
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, size_t(in.gcount()));
    if (text.size() > kMaxSceneBytes)
      throw InputError(file.string(), "",
                       "is larger than " + std::to_string(kMaxSceneBytes >> 20) +
                           " MiB; a scene names its meshes and images rather than holding them");
  }
  if (in.bad()) throw InputError(file.string(), "", "error while reading the scene file");
  return parse_scene(text, file);
}

std::vector<SceneMesh> load_scene_meshes(const Scene& scene) { return load_scene_meshes(scene, Budget{}); }

std::vector<SceneMesh> load_scene_meshes(const Scene& scene, const Budget& budget) {
  std::vector<SceneMesh> out;
  out.reserve(scene.objects.size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const std::string field = json_child(json_index("objects", i), "mesh");
    SceneMesh sm;
    sm.model = o.transform.matrix();
    if (o.builtin) {
      sm.loaded.mesh = make_builtin_mesh(*o.builtin, budget, scene.file.string(), field);
    } else {
      try {
        sm.loaded = load_mesh_file(o.mesh_path, budget);
      } catch (const InputError& e) {
        throw InputError(e.file, e.field, e.reason + " (in " + field + " of " + scene.file.string() + ")");
      }
    }
    out.push_back(std::move(sm));
  }
  return out;
}

void bake_transform(Mesh& mesh, const glm::mat4& model) {
  const glm::dmat4 m(model);
  const glm::dmat3 nm = glm::inverseTranspose(glm::dmat3(m));
  for (auto& p : mesh.positions) p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
  for (auto& n : mesh.normals) {
    const glm::dvec3 t = nm * glm::dvec3(n);
    const double len = glm::length(t);
    n = len > 0.0 ? glm::vec3(t / len) : n;
  }
  if (glm::determinant(glm::dmat3(m)) < 0.0)
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) std::swap(mesh.indices[k + 1], mesh.indices[k + 2]);
}

}  // namespace pelt::io
