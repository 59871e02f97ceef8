// Small scenes for the frame-pipeline tests, as JSON text.
#pragma once

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/tools/io/temp_dir.h"

#include "tools/io/quality.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/scene.h"
#include "tools/render/fur_object.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {

// A furry box seen from a three-quarter view. `fur_extra` is spliced into the fur block.
inline std::string furry_box_scene(const std::string& fur_extra, int frames = 1) {
  return R"({"pelt": 1,
  "image": {"width": 160, "height": 120, "background": [0.05, 0.05, 0.08]},
  "camera": {"eye": [3.5, 2.5, 5.0], "target": [0, 0, 0], "fovy_deg": 45, "near": 0.5, "far": 30},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]},
             {"type": "ambient", "color": [0.3, 0.3, 0.35]}],
  "animation": {"frames": )" +
         std::to_string(frames) + R"(, "fps": 24},
  "objects": [{"mesh": "box:7", "material": {"type": "lambert", "color": [0.3, 0.2, 0.1]},
               "fur": {"shells": 16, "texture_size": 64)" +
         (fur_extra.empty() ? "" : ", " + fur_extra) + R"(}}]})";
}

inline std::string bare_box_scene(int frames) {
  return R"({"pelt": 1, "image": {"width": 64, "height": 48},
  "camera": {"eye": [3, 2, 4], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}],
  "animation": {"frames": )" +
         std::to_string(frames) + R"(, "fps": 24},
  "objects": [{"mesh": "box:3", "material": {"type": "lambert"}}]})";
}

// Fur of `shells` layers with 32x32 strand textures and `fins`: small enough for the tests that
// drive a FurObject by hand.
inline fur::FurParams small_fur(int shells, fur::FinMode fins) {
  fur::FurParams params;
  params.shells = shells;
  params.texture_size = 32;
  params.fins = fins;
  return params;
}

// A fur object driven by hand (update, append_draws) on a built-in mesh, under a white ambient
// light, seen from (3, 2, 4) through a 45-degree square frustum.
struct FurRig {
  FurRig(const std::string& mesh, const fur::FurParams& params, const std::string& name,
         const FurDrawOptions& options = {})
      : base(io::make_builtin_mesh(mesh)), fur(base, params, options, FurOrigin{name, ""}, stats) {
    frame.eye = glm::vec3(3.0f, 2.0f, 4.0f);
    frame.clip_from_world = clip;
  }
  Mesh base;
  FrameStats stats;
  FurObject fur;
  std::vector<shading::Light> lights = {{shading::Light::Type::Ambient, {0, 0, 0}, {1.0f, 1.0f, 1.0f}}};
  FurFrame frame;
  glm::mat4 clip = glm::perspective(glm::radians(45.0f), 1.0f, 1.0f, 20.0f) *
                   glm::lookAt(glm::vec3(3.0f, 2.0f, 4.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0));

  // The draws of the current frame, after bringing the object up to date for it.
  std::vector<raster::DrawCall> draws(FurSort sort) {
    frame.sort = sort;
    fur.update(frame, lights, stats);
    std::vector<raster::DrawCall> d;
    fur.append_draws(d);
    return d;
  }
};

// A scratch folder for scenes that refer to files, removed with the object.
class SceneDir : public io::TempDir {
 public:
  io::Scene scene(const std::string& json) const { return io::parse_scene(json, path() / "scene.json"); }
};

// Mesh file `mesh` of `dir` seen from (0, 0, 4) down -z, 40 degrees, in a 64 x 64 black frame
// under a unit ambient light: the view of the tests of meshes' materials (two quads of
// two_quads_gltf.h and their OBJ twins). `quality`: the members of the scene's quality block.
inline io::Scene front_view_scene(const SceneDir& dir, const std::string& mesh, const std::string& material,
                                  const std::string& object_extra = "", const std::string& quality = "") {
  return dir.scene(R"({"pelt": 1, "image": {"width": 64, "height": 64, "background": [0, 0, 0]},
      "camera": {"eye": [0, 0, 4], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": [{"type": "ambient", "intensity": 1}],)" +
                   (quality.empty() ? std::string() : R"("quality": {)" + quality + "},") +
                   R"("objects": [{"mesh": ")" + (dir.path() / mesh).string() + R"(", "material": )" + material +
                   object_extra + "}]}");
}

// Frame 0 of `scene` at quality `q`.
inline FrameImage render_at(const io::Scene& scene, const io::Quality& q, int threads = 2,
                            FurLighting lighting = FurLighting::vertex) {
  RenderSettings rs;
  rs.threads = threads;
  rs.quality = q;
  rs.fur_lighting = lighting;
  SceneRenderer r(scene, rs);
  FrameImage img;
  FrameStats st;
  r.render(0, img, st);
  return img;
}

// The same size and every float the same, bit for bit.
inline bool same_pixels(const FrameImage& a, const FrameImage& b) {
  return a.color.size() == b.color.size() &&
         std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(float)) == 0;
}

// RMSE over the RGB channels of two RGBA float images of the same size.
inline double image_rmse(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4, ++n)
    for (int c = 0; c < 3; ++c) sum += (double(a[i + c]) - b[i + c]) * (double(a[i + c]) - b[i + c]);
  return n ? std::sqrt(sum / (3.0 * double(n))) : 0.0;
}

}  // namespace pelt::render::test
