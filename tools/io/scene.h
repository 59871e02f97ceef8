// Scene files, version 1: what to render (image, camera, lights, objects, animation),
// parsed from JSON and validated field by field.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fur/fur_params.h"
#include "shading/basic_params.h"
#include "shading/skin_params.h"
#include "tools/io/animation_tracks.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/mesh_loader.h"
#include "tools/io/quality.h"

namespace pelt::io {

inline constexpr int kSceneVersion = 1;
inline constexpr int kMaxImageSide = 16384;

struct ImageSettings {
  int width = 1024;                              // "width": 1..16384
  int height = 768;                              // "height": 1..16384
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};  // "background": [r,g,b] or [r,g,b,a], linear
};

// Right-handed, looking down -z in view space (OpenGL conventions).
struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};     // "eye"
  glm::vec3 target{0.0f, 0.0f, 0.0f};  // "target": must differ from eye
  glm::vec3 up{0.0f, 1.0f, 0.0f};      // "up": non-zero, not parallel to target - eye
  float fovy_deg = 45.0f;              // "fovy_deg": vertical field of view, 0 < x < 180
  float near = 0.1f;                   // "near": > 0
  float far = 100.0f;                  // "far": > near

  glm::mat4 view() const;                    // glm::lookAt(eye, target, up)
  glm::mat4 projection(float aspect) const;  // glm::perspective; clip z in [-w, w]
  bool operator==(const Camera&) const = default;
};

enum class LightType { directional, point, ambient };

struct Light {
  LightType type = LightType::directional;  // "type": "directional" | "point" | "ambient"
  // "direction" (directional, required): the direction FROM the surface TOWARD the light
  // (the L of the shading code), normalised on load.
  glm::vec3 direction{0.0f, 1.0f, 0.0f};
  glm::vec3 position{0.0f};           // "position" (point, required)
  glm::vec3 color{1.0f, 1.0f, 1.0f};  // "color": linear, each >= 0
  float intensity = 1.0f;             // "intensity": >= 0; radiance = color x intensity
  bool operator==(const Light&) const = default;
};

// The material kinds; `skin` reads its parameters from the material's `skin` block.
enum class MaterialType { unlit, lambert, blinn, skin };

struct Material {
  MaterialType type = MaterialType::lambert;  // "type" (required)
  glm::vec3 color{0.8f, 0.8f, 0.8f};          // "color": linear albedo, each in [0, 1]
  shading::BasicParams basic;                 // "specular" [3], "shininess" (blinn)
  std::filesystem::path color_map;            // "color_map": resolved against the scene folder
  // "normal_map": a tangent-space normal map (glTF / OpenGL convention: red along +u, green
  // toward the top of the image, blue out of the surface), stored linear; needs mesh uvs.
  std::filesystem::path normal_map;
  bool double_sided = false;                  // "double_sided"
  shading::SkinParams skin;                   // "skin": {...} (type "skin" only)
};

struct Transform {
  glm::vec3 translate{0.0f};   // "translate"
  glm::vec3 rotate_deg{0.0f};  // "rotate_deg": about X, then Y, then Z
  glm::vec3 scale{1.0f};       // "scale": a number or [3]; no component zero

  // T * Rz * Ry * Rx * S: scale first, then rotate about X, Y, Z, then translate.
  glm::mat4 matrix() const;
};

struct SceneObject {
  std::string name;                      // "name" (optional; defaults to "objects[i]")
  std::string mesh;                      // "mesh" as written (built-in spec or path)
  std::optional<BuiltinSpec> builtin;    // set when `mesh` is a built-in spec
  std::filesystem::path mesh_path;       // set when `mesh` is a file: resolved, exists
  Transform transform;                   // "transform"
  Material material;                     // "material" (required)
  std::optional<fur::FurParams> fur;     // "fur": present only for furry objects
  // "fur.length_map": resolved against the scene folder and readable; empty without one. An
  // image whose first channel (linear, in [0, 1]) scales the fur's length at each base vertex's
  // texture coordinate: 0 grows no fur there.
  std::filesystem::path fur_length_map;
};

// `animation.camera.orbit`: the eye circles `target` about the world +y axis,
//   eye = target + distance (cos(el) sin(az), sin(el), cos(el) cos(az)),
// so azimuth 0 looks from +z, 90 from +x; elevation 90 would look straight down. Fields
// left out of the JSON are constants taken from the scene camera.
struct CameraOrbit {
  VectorTrack target;         // "target": a point
  ScalarTrack azimuth_deg;    // "azimuth_deg": any finite angle (degrees)
  ScalarTrack elevation_deg;  // "elevation_deg": in (-90, 90)
  ScalarTrack distance;       // "distance": > 0
  bool operator==(const CameraOrbit&) const = default;
};

// `animation.camera.path`: eye and target move freely (component-wise interpolation).
struct CameraPath {
  VectorTrack eye;     // "eye"
  VectorTrack target;  // "target"
  bool operator==(const CameraPath&) const = default;
};

// `animation.lights[i]`: tracks for scene light `light`; unset members stay static.
struct LightTracks {
  size_t light = 0;                      // "light": index into the scene's lights
  std::optional<ScalarTrack> intensity;  // "intensity": >= 0
  std::optional<VectorTrack> direction;  // "direction": unit (directional lights only)
  bool operator==(const LightTracks&) const = default;
};

// `animation.fur[i]`: tracks for the fur of object `object`, whose fur block must hold
// the `wind` / `gravity` block being animated (its other fields stay as written there).
struct FurTracks {
  size_t object = 0;                             // "object": index or name
  std::optional<VectorTrack> wind_direction;     // "wind.direction": unit
  std::optional<ScalarTrack> wind_strength;      // "wind.strength": in [0, 1000]
  std::optional<VectorTrack> gravity_direction;  // "gravity.direction": unit
  std::optional<ScalarTrack> gravity_strength;   // "gravity.strength": in [0, 1000]
  bool operator==(const FurTracks&) const = default;
};

struct Animation {
  int frames = 1;     // "frames": >= 1
  double fps = 24.0;  // "fps": > 0; frame k is at time k / fps seconds
  // "camera": {"orbit": {...}} or {"path": {...}}; at most one is set.
  std::optional<CameraOrbit> orbit;
  std::optional<CameraPath> path;
  std::vector<LightTracks> lights;  // "lights": at most one entry per light
  std::vector<FurTracks> fur;       // "fur": at most one entry per object
};

struct Scene {
  std::filesystem::path file;  // the scene file, for messages and relative paths
  ImageSettings image;
  Camera camera;
  std::vector<Light> lights;
  std::vector<SceneObject> objects;  // at least one
  std::optional<Animation> animation;
  Quality quality;  // "quality": {"preset": ..., knob: value, ...}; the CLI's flags override it
};

// Reads and validates a scene file. Mesh files are checked to exist and be readable
// but not loaded (see load_scene_meshes). Throws InputError(scene file, field path,
// reason) for: unreadable file, malformed JSON (with line and column), missing or
// unsupported "pelt" version, unknown key (with "did you mean"), wrong type,
// non-finite or out-of-range number, wrong array length, missing required field,
// unknown enum value, missing or unreadable mesh or colour-map file.
Scene load_scene(const std::filesystem::path& file);
// The same from JSON text; `file` names it in messages and anchors relative paths.
Scene parse_scene(const std::string& text, const std::filesystem::path& file);

// The camera of frame `frame` (0-based): the scene camera with the animation's orbit or
// path applied. Pure; returns scene.camera unchanged when the camera is not animated.
Camera camera_at(const Scene& scene, int frame);

// One object's geometry in object space; the object's transform is NOT baked in, it is
// returned as `model` (apply with bake_transform when world-space positions are wanted).
struct SceneMesh {
  LoadedMesh loaded;
  glm::mat4 model{1.0f};
};

// Loads every object's mesh (built-in or file), in object order. A mesh file's own
// errors keep its file and element (`v 12`, ...) and add the object's field path to the
// reason, e.g. "bunny.obj: v 12: position is NaN (in objects[1].mesh of scene.json)".
// Each mesh is checked against `budget` (max_faces; glTF images against
// max_texture_side) before its arrays are built; a built-in spec over max_faces is
// refused as InputError(scene file, `objects[i].mesh`, ...). The one-argument form uses
// the default Budget.
std::vector<SceneMesh> load_scene_meshes(const Scene& scene, const Budget& budget);
std::vector<SceneMesh> load_scene_meshes(const Scene& scene);

// Positions by `model`, normals by its inverse transpose (renormalised); flips the
// triangles when `model` mirrors, so the winding stays counter-clockwise from outside.
void bake_transform(Mesh& mesh, const glm::mat4& model);

}  // namespace pelt::io
