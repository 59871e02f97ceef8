#include "tools/io/scene.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"
#include "tools/io/json_fields.h"

namespace pelt::io {
namespace scene_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

std::filesystem::path data_dir() {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  return std::filesystem::path(root ? root : ".") / "tools" / "data";
}

// A complete scene using every key of version 1; tests below break one thing at a time.
std::string full_scene(const std::filesystem::path& data) {
  return R"({
  "pelt": 1,
  "image": {"width": 640, "height": 480, "background": [0.1, 0.2, 0.3, 1.0]},
  "camera": {"eye": [0, 2, 8], "target": [0, 1, 0], "up": [0, 2, 0], "fovy_deg": 40, "near": 0.5, "far": 50},
  "lights": [
    {"type": "directional", "direction": [0, 0, 2], "color": [1, 0.9, 0.8], "intensity": 2},
    {"type": "point", "position": [1, 5, 1], "intensity": 10},
    {"type": "ambient", "color": [0.2, 0.2, 0.25]}
  ],
  "objects": [
    {"name": "floor", "mesh": "plane:4", "transform": {"scale": 5},
     "material": {"type": "lambert", "color": [0.5, 0.5, 0.5], "double_sided": true}},
    {"name": "bunny", "mesh": ")" + (data / "bunny.obj").string() + R"(",
     "transform": {"translate": [1, 0, -2], "rotate_deg": [0, 90, 0], "scale": [2, 2, 2]},
     "material": {"type": "blinn", "color": [0.8, 0.6, 0.4], "specular": [0.5, 0.5, 0.5], "shininess": 64},
     "fur": {"shells": 12, "length": 0.05, "fins": "all", "gravity": {"strength": 0.5},
             "wind": {"direction": [1, 0, 1], "strength": 2}}},
    {"mesh": "teapot:3", "material": {"type": "unlit", "color_map": "tex.png"},
     "fur": {"use_color_map": true, "length_map": "tex.png"}},
    {"name": "head", "mesh": "head.obj",
     "material": {"type": "skin", "skin": {"Eta": 1.3, "SkinColor": [0.9, 0.6, 0.5],
                                           "multiple_scattering": "normal_blur"}}}
  ],
  "animation": {"frames": 48, "fps": 24}
})";
}

struct SceneFixture : ::testing::Test {
  TempDir dir;
  std::filesystem::path write_scene(const std::string& text) {
    dir.write("tex.png", "not decoded at load time");
    dir.write("head.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    return dir.write("scene.json", text);
  }
  // Replaces the first occurrence of `from` in the full scene by `to`.
  std::string edited(const std::string& from, const std::string& to) {
    std::string s = full_scene(data_dir());
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
  }
  void expect_error(const std::string& text, const std::string& field, const std::string& reason_part) {
    const auto file = write_scene(text);
    try {
      load_scene(file);
      FAIL() << "accepted; expected an error at " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, file.string());
      EXPECT_EQ(e.field, field) << e.what();
      EXPECT_NE(e.reason.find(reason_part), std::string::npos) << e.what();
    }
  }
};

// A key given twice: the JSON reader would keep the later value without a word.
TEST_F(SceneFixture, RepeatedKeyNamesItsPlace) {
  const std::string reason = "given twice in the same object";
  expect_error(edited(R"("height": 480)", R"("height": 480, "width": 320)"), "image.width", reason);
  expect_error(edited(R"("shininess": 64)", R"("shininess": 64, "type": "lambert")"), "objects[1].material.type",
               reason);
  expect_error(edited(R"("intensity": 10})", R"("intensity": 10, "intensity": 1})"), "lights[1].intensity", reason);
  expect_error(edited(R"("animation": {"frames": 48, "fps": 24})",
                      R"("animation": {"frames": 48, "fps": 24}, "animation": {"frames": 2})"),
               "animation", reason);
  // Arrays of objects count their elements whatever they hold, and the same key in two
  // objects is no repeat.
  expect_error(edited(R"("lights": [)", R"("lights": [[1, {"a": 1}], {"a": 1, "b": 2, "b": 3}, )"), "lights[1].b",
               reason);
  EXPECT_NO_THROW(load_scene(write_scene(full_scene(data_dir()))));
}

TEST_F(SceneFixture, FullSceneRoundTrip) {
  const Scene s = load_scene(write_scene(full_scene(data_dir())));
  EXPECT_EQ(s.image.width, 640);
  EXPECT_EQ(s.image.height, 480);
  EXPECT_EQ(s.image.background, glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
  EXPECT_EQ(s.camera.eye, glm::vec3(0, 2, 8));
  EXPECT_EQ(s.camera.up, glm::vec3(0, 1, 0));  // normalised
  EXPECT_EQ(s.camera.fovy_deg, 40.0f);
  EXPECT_EQ(s.camera.near, 0.5f);
  EXPECT_EQ(s.camera.far, 50.0f);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, LightType::directional);
  EXPECT_EQ(s.lights[0].direction, glm::vec3(0, 0, 1));
  EXPECT_EQ(s.lights[0].intensity, 2.0f);
  EXPECT_EQ(s.lights[1].type, LightType::point);
  EXPECT_EQ(s.lights[1].position, glm::vec3(1, 5, 1));
  EXPECT_EQ(s.lights[1].color, glm::vec3(1, 1, 1));
  EXPECT_EQ(s.lights[2].type, LightType::ambient);
  ASSERT_EQ(s.objects.size(), 4u);
  const SceneObject& floor = s.objects[0];
  EXPECT_EQ(floor.name, "floor");
  ASSERT_TRUE(floor.builtin.has_value());
  EXPECT_EQ(floor.builtin->shape, BuiltinShape::plane);
  EXPECT_EQ(floor.transform.scale, glm::vec3(5));
  EXPECT_TRUE(floor.material.double_sided);
  EXPECT_FALSE(floor.fur.has_value());
  const SceneObject& bunny = s.objects[1];
  EXPECT_FALSE(bunny.builtin.has_value());
  EXPECT_EQ(bunny.mesh_path, data_dir() / "bunny.obj");
  EXPECT_EQ(bunny.material.type, MaterialType::blinn);
  EXPECT_EQ(bunny.material.basic.shininess, 64.0f);
  EXPECT_EQ(bunny.material.basic.specular[1], 0.5f);
  ASSERT_TRUE(bunny.fur.has_value());
  EXPECT_EQ(bunny.fur->shells, 12);
  EXPECT_EQ(bunny.fur->fins, fur::FinMode::all);
  ASSERT_TRUE(bunny.fur->gravity.has_value());
  EXPECT_EQ(bunny.fur->gravity->strength, 0.5f);
  ASSERT_TRUE(bunny.fur->wind.has_value());
  EXPECT_FALSE(bunny.fur->comb.has_value());
  EXPECT_EQ(s.objects[2].name, "objects[2]");
  EXPECT_EQ(s.objects[2].material.color_map, dir.path() / "tex.png");
  EXPECT_TRUE(s.objects[2].fur->use_color_map);
  EXPECT_EQ(s.objects[2].fur_length_map, dir.path() / "tex.png");
  EXPECT_FALSE(s.objects[1].fur->use_color_map);
  EXPECT_TRUE(s.objects[1].fur_length_map.empty());
  EXPECT_EQ(s.objects[3].mesh_path, dir.path() / "head.obj");
  EXPECT_EQ(s.objects[3].material.type, MaterialType::skin);
  EXPECT_EQ(s.objects[3].material.skin.Eta, 1.3f);
  EXPECT_EQ(s.objects[3].material.skin.multiple_scattering, shading::MultipleScattering::normal_blur);
  ASSERT_TRUE(s.animation.has_value());
  EXPECT_EQ(s.animation->frames, 48);
  EXPECT_EQ(s.animation->fps, 24.0);

  const auto meshes = load_scene_meshes(s);
  ASSERT_EQ(meshes.size(), 4u);
  EXPECT_EQ(meshes[0].loaded.mesh.triangle_count(), 32u);
  EXPECT_EQ(meshes[1].loaded.mesh.triangle_count(), 3674u);
  EXPECT_EQ(meshes[2].loaded.mesh.triangle_count(), 552u);
  EXPECT_EQ(meshes[3].loaded.mesh.triangle_count(), 1u);
  // Transform: scale, rotate about Y by 90 deg, translate. (1,0,0) -> (2,0,0) -> (0,0,-2) -> (1,0,-4).
  const glm::vec4 p = meshes[1].model * glm::vec4(1, 0, 0, 1);
  EXPECT_NEAR(p.x, 1.0f, 1e-6f);
  EXPECT_NEAR(p.y, 0.0f, 1e-6f);
  EXPECT_NEAR(p.z, -4.0f, 1e-6f);
}

TEST_F(SceneFixture, MinimalSceneTakesDefaults) {
  const Scene s = load_scene(write_scene(R"({"pelt": 1, "objects": [{"mesh": "box:2", "material": {"type": "lambert"}}]})"));
  EXPECT_EQ(s.image.width, 1024);
  EXPECT_EQ(s.image.height, 768);
  EXPECT_EQ(s.camera.fovy_deg, 45.0f);
  EXPECT_EQ(s.camera.up, glm::vec3(0, 1, 0));
  EXPECT_TRUE(s.lights.empty());
  EXPECT_FALSE(s.animation.has_value());
}

TEST_F(SceneFixture, RotationOrderIsXThenYThenZ) {
  Transform t;
  t.rotate_deg = glm::vec3(90, 90, 0);
  // X first: (0,1,0) -> (0,0,1); then Y: (0,0,1) -> (1,0,0).
  const glm::vec4 p = t.matrix() * glm::vec4(0, 1, 0, 1);
  EXPECT_NEAR(p.x, 1.0f, 1e-6f);
  EXPECT_NEAR(p.y, 0.0f, 1e-6f);
  EXPECT_NEAR(p.z, 0.0f, 1e-6f);
}

TEST_F(SceneFixture, CameraLooksDownMinusZ) {
  Camera c;
  c.eye = glm::vec3(0, 0, 5);
  const glm::vec4 v = c.view() * glm::vec4(0, 0, 0, 1);
  EXPECT_NEAR(v.z, -5.0f, 1e-6f);
  const glm::vec4 clip = c.projection(2.0f) * glm::vec4(0, 0, -c.near, 1);
  EXPECT_NEAR(clip.z / clip.w, -1.0f, 1e-5f);  // OpenGL depth range
}

TEST_F(SceneFixture, MalformedJsonHasLineAndColumn) {
  expect_error("{\n  \"pelt\": 1,\n  \"objects\": [,]\n}", "", "malformed JSON at line 3, column 15");
}

TEST_F(SceneFixture, VersionIsRequiredAndChecked) {
  expect_error(R"({"objects": []})", "pelt", "required field is missing");
  expect_error(edited("\"pelt\": 1", "\"pelt\": 2"), "pelt", "unsupported format version 2");
  expect_error(edited("\"pelt\": 1", "\"pelt\": \"1\""), "pelt", "got a string");
  expect_error("[1, 2]", "", "expected an object, got an array");
}

TEST_F(SceneFixture, UnknownKeySuggestsTheNearest) {
  expect_error(edited("\"fovy_deg\"", "\"fov_deg\""), "camera.fov_deg", "unknown key `fov_deg` (did you mean `fovy_deg`?)");
  expect_error(edited("\"shells\"", "\"shels\""), "objects[1].fur.shels", "did you mean `shells`?");
  expect_error(edited("\"image\"", "\"imagery_settings\""), "imagery_settings", "known keys:");
  expect_error(edited("\"Eta\"", "\"eta\""), "objects[3].material.skin.eta", "did you mean `Eta`?");
}

TEST_F(SceneFixture, QualityBlockPresetThenKnobs) {
  const auto file = write_scene(edited("\"animation\"", R"("quality": {"preset": "fast", "spp": 4, "sort": "exact",
      "multiple_scattering": "reference", "precision": "double"}, "animation")"));
  const Scene s = load_scene(file);
  Quality want = *quality_preset("fast");
  want.spp = 4;
  want.sort = SortQuality::exact;
  want.multiple_scattering = shading::MultipleScattering::reference;
  want.precision = Precision::double_precision;
  EXPECT_EQ(s.quality, want);
  EXPECT_EQ(load_scene(write_scene(full_scene(data_dir()))).quality, Quality{});  // no block: defaults
}

TEST_F(SceneFixture, CombFieldFromTheUvLayout) {
  const Scene s = load_scene(write_scene(edited("\"gravity\": {\"strength\": 0.5}",
      R"("gravity": {"strength": 0.5}, "comb": {"field": "uv", "uv_direction": [0, -1], "weight": 0.4})")));
  ASSERT_TRUE(s.objects[1].fur->comb);
  EXPECT_EQ(s.objects[1].fur->comb->field, fur::CombField::uv);
  EXPECT_EQ(s.objects[1].fur->comb->uv_direction, glm::vec2(0, -1));
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"field": "radial"})"),
               "objects[1].fur.comb.field", "must be \"uniform\" or \"uv\"");
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"field": "uv", "uv_direction": [0, 0]})"),
               "objects[1].fur.comb.uv_direction", "non-zero");
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"uv_direction": [1]})"),
               "objects[1].fur.comb.uv_direction", "");
  // Each field reads one direction: the other is refused, not silently unused.
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"field": "uniform", "uv_direction": [0, 1]})"),
               "objects[1].fur.comb.uv_direction", "applies to a comb with \"field\": \"uv\"");
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"uv_direction": [0, 1]})"),
               "objects[1].fur.comb.uv_direction", "this comb is uniform");
  expect_error(edited("\"gravity\": {\"strength\": 0.5}", R"("comb": {"field": "uv", "direction": [1, 0, 0]})"),
               "objects[1].fur.comb.direction", "applies to a uniform comb");
}

TEST_F(SceneFixture, QualityBlockErrorsNameTheKnob) {
  auto with = [&](const std::string& block) { return edited("\"animation\"", "\"quality\": " + block + ", \"animation\""); };
  expect_error(with(R"({"spp": 3})"), "quality.spp", "must be a square number of samples from 1 to 64");
  expect_error(with(R"({"spp": 81})"), "quality.spp", "must be a square number");
  expect_error(with(R"({"shells": 1})"), "quality.shells", "must be an integer in [2, 128]");
  expect_error(with(R"({"shells": 2000000})"), "quality.shells", "must be an integer in [2, 128]");
  expect_error(with(R"({"spp": 1048576})"), "quality.spp", "must be a square number of samples from 1 to 64");
  expect_error(with(R"({"sort": "depth"})"), "quality.sort", "unknown value `depth` (none, layer, tile, surface, exact)");
  expect_error(with(R"({"filter": "anisotropic"})"), "quality.filter", "(nearest, bilinear, bilinear_mip, trilinear)");
  expect_error(with(R"({"precision": "half"})"), "quality.precision", "(simd, double)");
  expect_error(with(R"({"preset": "ultra"})"), "quality.preset", "unknown preset `ultra` (default, fast");
  expect_error(with(R"({"sppp": 4})"), "quality.sppp", "did you mean `spp`?");
  expect_error(with(R"({"spp": "4"})"), "quality.spp", "expected a number, got a string");
  expect_error(with(R"({"fins": 1})"), "quality.fins", "expected a string");
}

TEST_F(SceneFixture, WrongType) {
  expect_error(edited("\"width\": 640", "\"width\": \"640\""), "image.width", "expected a number, got a string");
  expect_error(edited("\"double_sided\": true", "\"double_sided\": 1"), "objects[0].material.double_sided",
               "expected true or false");
  expect_error(edited("\"scale\": 5", "\"scale\": \"big\""), "objects[0].transform.scale",
               "expected a number or an array of 3 numbers");
  expect_error(edited("\"lights\": [", "\"lights\": {\"a\": ["), "", "malformed JSON");
}

TEST_F(SceneFixture, OutOfRange) {
  expect_error(edited("\"width\": 640", "\"width\": 0"), "image.width", "must be in [1, 16384], got 0");
  expect_error(edited("\"height\": 480", "\"height\": 20000"), "image.height", "must be in [1, 16384]");
  expect_error(edited("\"width\": 640", "\"width\": 64.5"), "image.width", "expected a whole number");
  expect_error(edited("\"fovy_deg\": 40", "\"fovy_deg\": 180"), "camera.fovy_deg", "must be in (0, 180)");
  expect_error(edited("\"near\": 0.5", "\"near\": 0"), "camera.near", "must be in (0,");
  expect_error(edited("\"far\": 50", "\"far\": 0.25"), "camera.far", "must be greater than near");
  expect_error(edited("\"scale\": 5", "\"scale\": 0"), "objects[0].transform.scale", "must be non-zero");
  expect_error(edited("\"scale\": [2, 2, 2]", "\"scale\": [2, 0, 2]"), "objects[1].transform.scale[1]",
               "must be non-zero");
  expect_error(edited("\"shininess\": 64", "\"shininess\": 0"), "objects[1].material.shininess", "must be in [1, 256]");
  expect_error(edited("\"intensity\": 2", "\"intensity\": -1"), "lights[0].intensity", "must be in [0,");
  expect_error(edited("\"frames\": 48", "\"frames\": 0"), "animation.frames", "must be in [1,");
  expect_error(edited("\"fps\": 24", "\"fps\": 0"), "animation.fps", "must be in (0,");
  expect_error(edited("\"color\": [0.5, 0.5, 0.5]", "\"color\": [0.5, 1.5, 0.5]"), "objects[0].material.color[1]",
               "must be in [0, 1], got 1.5");
  expect_error(edited("\"shells\": 12", "\"shells\": 1"), "objects[1].fur.shells", "must be an integer in [2, 128]");
  // Counts far out of range still get their own field's range and reason, not a parser bound.
  expect_error(edited("\"shells\": 12", "\"shells\": 2000000"), "objects[1].fur.shells",
               "must be an integer in [2, 128] (layer 0 sits on the base surface");
  expect_error(edited("\"shells\": 12", "\"shells\": 12, \"texture_size\": 1048576"), "objects[1].fur.texture_size",
               "must be a power of two in [16, 4096], got 1048576");
  expect_error(edited("\"Eta\": 1.3", "\"Eta\": 9"), "objects[3].material.skin.Eta", "must be in [0.25, 4]");
}

// The documented ranges at their edges (README, scene format): far must exceed near, not equal
// it (a zero-depth frustum); a directional light's direction is required, not defaulted; the
// background's channels are >= 0 and its alpha at most 1; a light's colour at most 1e6 even
// where its intensity would keep the product in range.
TEST_F(SceneFixture, RangeEdgesAndRequiredDirection) {
  expect_error(edited("\"far\": 50", "\"far\": 0.5"), "camera.far", "must be greater than near");
  // The rasterizer keeps no vertex nearer than raster::kMinW: a nearer plane would let what lies
  // between vanish (until 2026-11-28 a plane of 3e-7 at 9e-7 from the eye drew nothing, exit 0).
  expect_error(edited("\"near\": 0.5", "\"near\": 3e-8"), "camera.near",
               "must be at least 1e-06, the nearest view depth pelt draws, got 3e-08");
  EXPECT_EQ(load_scene(write_scene(edited("\"near\": 0.5", "\"near\": 1e-6"))).camera.near, 1e-6f);
  expect_error(edited("\"direction\": [0, 0, 2], ", ""), "lights[0].direction", "required field is missing");
  expect_error(edited("\"background\": [0.1, 0.2, 0.3, 1.0]", "\"background\": [0.1, -0.2, 0.3, 1.0]"),
               "image.background[1]", "must be >= 0");
  expect_error(edited("\"background\": [0.1, 0.2, 0.3, 1.0]", "\"background\": [0.1, 0.2, 0.3, 1.5]"),
               "image.background[3]", "alpha must be in [0, 1]");
  expect_error(edited("\"color\": [1, 0.9, 0.8], \"intensity\": 2", "\"color\": [1, 2e6, 0.8], \"intensity\": 0.1"),
               "lights[0].color[1]", "must be in [0, 1e+06]");
}

TEST_F(SceneFixture, NonFiniteNumber) {
  // JSON has no NaN or infinity; a number beyond double range is the way to write one.
  expect_error(edited("\"eye\": [0, 2, 8]", "\"eye\": [0, 2e999, 8]"), "", "number overflow parsing '2e999'");
  JsonFields js("f.json");
  try {
    js.number(nlohmann::json(INFINITY), "camera.eye[1]");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f.json: camera.eye[1]: number is not finite");
  }
}

TEST_F(SceneFixture, WrongArrayLength) {
  expect_error(edited("\"eye\": [0, 2, 8]", "\"eye\": [0, 2]"), "camera.eye", "expected 3 numbers, got 2");
  expect_error(edited("\"background\": [0.1, 0.2, 0.3, 1.0]", "\"background\": [0.1, 0.2]"), "image.background",
               "expected 3 to 4 numbers, got 2");
}

TEST_F(SceneFixture, BadDirectionsAndCamera) {
  expect_error(edited("\"direction\": [0, 0, 2]", "\"direction\": [0, 0, 0]"), "lights[0].direction", "non-zero");
  expect_error(edited("\"target\": [0, 1, 0]", "\"target\": [0, 2, 8]"), "camera.target", "must differ from eye");
  expect_error(edited("\"up\": [0, 2, 0]", "\"up\": [0, -2, -16]"), "camera.up", "parallel");
  expect_error(edited("\"direction\": [1, 0, 1]", "\"direction\": [0, 0, 0]"), "objects[1].fur.wind.direction",
               "non-zero");
  // Short but not zero: told the bound, as the fur block's directions are.
  expect_error(edited("\"direction\": [0, 0, 2]", "\"direction\": [0, 0, 5e-7]"), "lights[0].direction",
               "must have a length above 1e-06 (it is normalised, and a shorter one would be mostly rounding), got "
               "length 5e-07");
  expect_error(edited("\"direction\": [1, 0, 1]", "\"direction\": [0, 5e-7, 0]"), "objects[1].fur.wind.direction",
               "must have a length above 1e-06");
}

TEST_F(SceneFixture, MissingRequiredField) {
  expect_error(edited("\"objects\": [", "\"objects_\": ["), "objects_", "unknown key `objects_` (did you mean `objects`?)");
  expect_error(R"({"pelt": 1})", "objects", "required field is missing");
  expect_error(R"({"pelt": 1, "objects": []})", "objects", "at least one object");
  expect_error(edited("\"mesh\": \"plane:4\", ", ""), "objects[0].mesh", "required field is missing");
  expect_error(edited("\"type\": \"lambert\", ", ""), "objects[0].material.type", "required field is missing");
  expect_error(edited("\"position\": [1, 5, 1], ", ""), "lights[1].position", "required field is missing");
}

TEST_F(SceneFixture, UnknownEnumValues) {
  expect_error(edited("\"type\": \"lambert\"", "\"type\": \"lambertian\""), "objects[0].material.type",
               "did you mean `lambert`?");
  expect_error(edited("\"type\": \"point\"", "\"type\": \"spot\""), "lights[1].type", "unknown light type `spot`");
  expect_error(edited("\"fins\": \"all\"", "\"fins\": \"some\""), "objects[1].fur.fins", "\"off\", \"all\" or");
  expect_error(edited("\"normal_blur\"", "\"blur\""), "objects[3].material.skin.multiple_scattering", "");
  expect_error(edited("\"mesh\": \"plane:4\"", "\"mesh\": \"plain:4\""), "objects[0].mesh", "did you mean `plane`?");
  expect_error(edited("\"mesh\": \"plane:4\"", "\"mesh\": \"plane:0\""), "objects[0].mesh", "must be positive");
  // A key valid for one material type is not silently accepted by another.
  expect_error(edited("\"double_sided\": true", "\"shininess\": 3"), "objects[0].material.shininess", "unknown key");
}

TEST_F(SceneFixture, MissingFiles) {
  expect_error(edited("\"head.obj\"", "\"nothere.obj\""), "objects[3].mesh", "not found");
  expect_error(edited("\"tex.png\"", "\"nothere.png\""), "objects[2].material.color_map", "not found");
  expect_error(edited("\"length_map\": \"tex.png\"", "\"length_map\": \"nothere.png\""), "objects[2].fur.length_map",
               "length map `");
  expect_error(edited("\"length_map\": \"tex.png\"", "\"length_map\": 3"), "objects[2].fur.length_map", "");
  expect_error(edited("\"color_map\": \"tex.png\"", "\"normal_map\": \"nothere.png\""),
               "objects[2].material.normal_map", "normal map `");
  dir.write("sub/file.txt", "");
  expect_error(edited("\"head.obj\"", "\"sub\""), "objects[3].mesh", "is a folder");
  TempDir other;
  const auto missing = other.path() / "none.json";
  try {
    load_scene(missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, missing.string());
    EXPECT_EQ(e.reason, "scene file not found");
  }
}

TEST_F(SceneFixture, MeshErrorsNameTheMeshFileAndTheObject) {
  const auto scene_file = write_scene(full_scene(data_dir()));
  const auto bad = dir.write("head.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  const Scene s = load_scene(scene_file);
  try {
    load_scene_meshes(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, bad.string());
    EXPECT_EQ(e.field, "v 3");
    EXPECT_EQ(e.reason, "position is NaN (in objects[3].mesh of " + scene_file.string() + ")");
  }
}

TEST(BakeTransform, MirrorKeepsOutwardWinding) {
  Mesh m = make_box(1);
  bake_transform(m, glm::scale(glm::mat4(1.0f), glm::vec3(-2, 1, 1)));
  double volume = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
    volume += glm::dot(a, glm::cross(b, c)) / 6;
  }
  EXPECT_NEAR(volume, 16.0, 1e-5);
  for (size_t i = 0; i < m.positions.size(); ++i)
    EXPECT_GT(glm::dot(m.normals[i], m.positions[i]), 0.0f);
}

}  // namespace scene_test
}  // namespace pelt::io
