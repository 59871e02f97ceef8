// Bad scene input through the real `pelt render`: exit code 2, a message naming the
// scene file, the field and the reason, and no output file.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/cli/run_pelt.h"
#include "tools/io/image_io.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

struct BadScene {
  const char* name;
  std::string json;     // the scene file's text
  const char* message;  // expected in stderr after "shot.json: "
  std::vector<std::pair<std::string, std::string>> files = {};  // extra files beside the scene
};

void PrintTo(const BadScene& b, std::ostream* os) { *os << b.name; }

std::string scene_with_object(const std::string& object) {
  return R"({"pelt": 1, "image": {"width": 32, "height": 24}, "objects": [)" + object + "]}";
}

class RenderBadScene : public ::testing::TestWithParam<BadScene> {};

TEST_P(RenderBadScene, ExitCode2NamingFieldAndReasonAndNoOutput) {
  const BadScene& b = GetParam();
  TempDir dir;
  const fs::path scene = dir.write("shot.json", b.json);
  for (const auto& [name, text] : b.files) dir.write(name, text);
  const fs::path out = dir.path() / "out" / "image.png";
  const Result r = run_pelt({"render", scene.string(), "-o", out.string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("shot.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

const char* kBox = R"({"mesh": "box:2", "material": {"type": "lambert"}})";

INSTANTIATE_TEST_SUITE_P(
    Scenes, RenderBadScene,
    ::testing::Values(
        BadScene{"MalformedJson", R"({"pelt": 1, "objects": [)", "malformed JSON"},
        BadScene{"UnknownKey", scene_with_object(R"({"mesh": "box:2", "materail": {"type": "lambert"}})"),
                 "objects[0].materail: unknown key `materail` (did you mean `material`?)"},
        BadScene{"WrongType", scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "transform": {"scale": "big"}})"),
                 "objects[0].transform.scale"},
        BadScene{"OutOfRange", R"({"pelt": 1, "image": {"width": 0}, "objects": [)" + std::string(kBox) + "]}",
                 "image.width"},
        BadScene{"ZeroScale", scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "transform": {"scale": [1, 0, 1]}})"),
                 "objects[0].transform.scale"},
        BadScene{"MissingMesh", scene_with_object(R"({"mesh": "nowhere.obj", "material": {"type": "lambert"}})"),
                 "objects[0].mesh"},
        // The path's NUL is shown (as \0), not the end of the message.
        BadScene{"NulInPath", scene_with_object(R"({"mesh": "dec.obj\u0000x", "material": {"type": "lambert"}})"),
                 "dec.obj\\0x` holds a NUL character, which no file path can hold"},
        BadScene{"NanInMesh", scene_with_object(R"({"mesh": "bad.obj", "material": {"type": "lambert"}})"),
                 "v 2: ", {{"bad.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"}}},
        BadScene{"IndexOutOfRange", scene_with_object(R"({"mesh": "idx.obj", "material": {"type": "lambert"}})"),
                 "idx.obj", {{"idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"}}},
        // tinyobjloader's triangulation used to drop this quad, and the frame rendered with a hole.
        BadScene{"QuadIndexPastTheEnd", scene_with_object(R"({"mesh": "quad.obj", "material": {"type": "lambert"}})"),
                 "quad.obj: f 2: vertex index 99 out of range (4 vertices)",
                 {{"quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 99\n"}}},
        // An image's own name is not enough to find who asked for it (a scene's own
        // `color_map` is checked when the scene is read).
        BadScene{"MeshNamesAMissingColourMap", scene_with_object(R"({"mesh": "tex.obj", "material": {"type": "lambert"}})"),
                 "gone.png: image file not found (the color_map that tex.obj names, in objects[0].mesh of ",
                 {{"tex.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\n"
                              "f 1/1 2/2 3/3\n"},
                  {"m.mtl", "newmtl a\nmap_Kd gone.png\n"}}},
        BadScene{"BadFurField", scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "fur": {"shells": 1}})"),
                 "objects[0].fur.shells"},
        BadScene{"FurTextureCoordinatesWord",
                 scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"},
                                       "fur": {"texture_coordinates": "uv"}})"),
                 "objects[0].fur.texture_coordinates"},
        BadScene{"FurTextureRepeatZero",
                 scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "fur": {"texture_repeat": 0}})"),
                 "objects[0].fur.texture_repeat"},
        BadScene{"FurMeshCoordinatesWithoutUvs",
                 scene_with_object(R"({"mesh": "nouv3.obj", "material": {"type": "lambert"},
                                       "fur": {"texture_coordinates": "mesh"}})"),
                 "shot.json: objects[0].fur.texture_coordinates: ",
                 {{"nouv3.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}}},
        // Found when the fur is built, after the scene is read: still the scene file and the path.
        BadScene{"FurCombAlongMissingUvs",
                 scene_with_object(R"({"name": "bunny", "mesh": "nouv2.obj", "material": {"type": "lambert"},
                                       "fur": {"comb": {"field": "uv"}}})"),
                 "shot.json: objects[0].fur.comb.field: ",
                 {{"nouv2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}}},
        BadScene{"BadSkinField", scene_with_object(R"({"mesh": "box:2", "material": {"type": "skin", "skin": {"Eta": 0}}})"),
                 "objects[0].material.skin.Eta"},
        // color and intensity each within their ranges, their product beyond the shader's.
        BadScene{"LightRadianceBeyondTheShader",
                 R"({"pelt": 1, "image": {"width": 32, "height": 24}, "lights": [{"type": "point", "position": [0, 3, 0],
                     "color": [10, 10, 10], "intensity": 200000}], "objects": [)" + std::string(kBox) + "]}",
                 "lights[0].intensity: color x intensity must be at most 1e6 in every channel"},
        BadScene{"PointLightBeyondTheShader",
                 R"({"pelt": 1, "image": {"width": 32, "height": 24}, "lights": [{"type": "point",
                     "position": [0, 1e31, 0]}], "objects": [)" + std::string(kBox) + "]}",
                 "lights[0].position: each coordinate must be within [-1e30, 1e30]"},
        // Scene numbers are 32-bit floats: these would become infinite or 0 past the range checks.
        BadScene{"NumberBeyondAFloat", scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "transform": {"translate": [1e39, 0, 0]}})"),
                 "objects[0].transform.translate[0]: number 1e+39 is beyond a 32-bit float's range"},
        BadScene{"NumberBelowAFloat", scene_with_object(R"({"mesh": "box:2", "material": {"type": "lambert"}, "transform": {"scale": 1e-50}})"),
                 "objects[0].transform.scale: number 1e-50 is too small for a 32-bit float"},
        BadScene{"UnknownVersion", R"({"pelt": 2.5, "objects": [)" + std::string(kBox) + "]}",
                 "pelt: unsupported format version 2.5"},
        // Without uvs every pixel would read one texel of the map.
        BadScene{"ColourMapWithoutUvs", scene_with_object(R"({"mesh": "nouv.obj", "material": {"type": "lambert"}})"),
                 "objects[0].mesh: a color_map needs texture coordinates, and mesh `nouv.obj` has none (the file's "
                 "material `a` names the map)",
                 {{"nouv.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"},
                  {"m.mtl", "newmtl a\nmap_Kd c.ppm\n"}, {"c.ppm", "P3\n1 1\n255\n255 0 0\n"}}},
        // Faces of a plain material have uvs, the mapped material's faces none: the map would read
        // one texel there, and the message counts them (until 2026-11-27 the uvs of every face were
        // dropped, and a map on the faces that had them refused too).
        BadScene{"ColourMapWhereSomeFacesLackUvs", scene_with_object(R"({"mesh": "some.obj", "material": {"type": "lambert"}})"),
                 "objects[0].mesh: a color_map needs texture coordinates, and 1 triangle of mesh `some.obj` that it "
                 "is drawn on has none (faces of material `a`, which names the map)",
                 {{"some.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl plain\n"
                               "f 1/1 2/2 3/3\nusemtl a\nf 1 3 2\n"},
                  {"m.mtl", "newmtl a\nmap_Kd c.ppm\nnewmtl plain\n"}, {"c.ppm", "P3\n1 1\n255\n255 0 0\n"}}}),
    [](const ::testing::TestParamInfo<BadScene>& info) { return std::string(info.param.name); });

// An animated light that leaves the shader's range at some frame is refused before any frame is
// written (by render and by info), not when the render reaches that frame. The bound itself,
// 1e30 for a point light's coordinates, is accepted as documented.
TEST(RenderBadScene, AnimatedLightBeyondTheShaderIsRefusedBeforeAnyFrame) {
  TempDir dir;
  const fs::path scene = dir.write("shot.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "lights": [{"type": "directional", "direction": [0, 0, 1], "color": [1000000, 1, 1]}],
      "objects": [{"mesh": "box:1", "material": {"type": "lambert"}}],
      "animation": {"frames": 4,
        "lights": [{"light": 0, "intensity": {"keys": [{"frame": 0, "value": 0.5}, {"frame": 3, "value": 2}]}}]}})");
  const fs::path out = dir.path() / "out";
  for (const char* command : {"render", "info"}) {
    std::vector<std::string> args = {command, scene.string()};
    if (std::string(command) == "render")
      args.insert(args.end(), {"-o", (out / "f_#.png").string(), "--quiet", "--stats", (out / "s.json").string()});
    const Result r = run_pelt(args, dir.path());
    EXPECT_EQ(r.code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("shot.json: lights[0].intensity: color x intensity must be at most 1e6 in every channel"),
              std::string::npos)
        << command << ": " << r.err;
    EXPECT_NE(r.err.find("at frame 3"), std::string::npos) << command << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out));

  const fs::path edge = dir.write("edge.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "lights": [{"type": "point", "position": [1e30, 0, -1e30]}],
      "objects": [{"mesh": "box:1", "material": {"type": "lambert"}}]})");
  const Result r = run_pelt({"render", edge.string(), "-o", (dir.path() / "edge.png").string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
}

// A device where a file belongs is refused, not read without end: a mesh that is a link to
// /dev/zero by the scene's field, a scene read from /dev/zero at the scene size bound.
TEST(RenderBadScene, ADeviceIsRefusedNotReadForever) {
  TempDir dir;
  std::error_code ec;
  fs::create_symlink("/dev/zero", dir.path() / "zero.obj", ec);
  ASSERT_FALSE(ec) << ec.message();
  const fs::path scene =
      dir.write("shot.json", scene_with_object(R"({"mesh": "zero.obj", "material": {"type": "lambert"}})"));
  const Result mesh = run_pelt({"render", scene.string(), "-o", (dir.path() / "a.png").string(), "--quiet"}, dir.path());
  EXPECT_EQ(mesh.code, 2) << mesh.err;
  EXPECT_NE(mesh.err.find("shot.json: objects[0].mesh: mesh file"), std::string::npos) << mesh.err;
  EXPECT_NE(mesh.err.find("is not a regular file (a device, a pipe or a socket)"), std::string::npos) << mesh.err;
  EXPECT_FALSE(fs::exists(dir.path() / "a.png"));
  const Result zero = run_pelt({"info", "/dev/zero"}, dir.path());
  EXPECT_EQ(zero.code, 2) << zero.err;
  EXPECT_NE(zero.err.find("/dev/zero: is larger than 64 MiB"), std::string::npos) << zero.err;
}

// A colour map whose texel leaves [0, 1] is named by the texel, and the error says which scene
// field asked for the map (not the raster's name for its input buffer).
TEST(RenderBadScene, AColourMapTexelOutOfRangeNamesTheTexelAndTheField) {
  TempDir dir;
  std::vector<float> px(2 * 2 * 4, 0.5f);
  for (size_t a = 3; a < px.size(); a += 4) px[a] = 1.0f;  // opaque: EXR would store colour times alpha
  px[4 * 3 + 1] = 1.5f;  // texel (1, 1), green
  io::write_image_atomic(dir.path() / "hdr.exr", 2, 2, 4, io::PixelType::f32, px.data());
  const fs::path scene = dir.write(
      "shot.json", scene_with_object(R"({"mesh": "plane:1", "material": {"type": "lambert", "color_map": "hdr.exr"}})"));
  const Result r = run_pelt({"render", scene.string(), "-o", (dir.path() / "a.png").string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("hdr.exr: texel (1, 1) channel g = 1.500000 is outside [0, 1]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(in objects[0].material.color_map of "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("rgba["), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "a.png"));
}

// What a loader accepted but changed reaches the user, on stderr even with --quiet, and the
// frame renders: here the file's normals replaced, as one corner has none.
TEST(RenderMeshWarnings, AreShownAndTheFrameStillRenders) {
  TempDir dir;
  dir.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4\n");
  const fs::path scene = dir.write(
      "shot.json", scene_with_object(R"({"mesh": "quad.obj", "material": {"type": "lambert"}})"));
  const fs::path out = dir.path() / "image.png";
  for (const char* command : {"render", "info"}) {
    std::vector<std::string> args = {command, scene.string()};
    if (std::string(command) == "render") args.insert(args.end(), {"-o", out.string(), "--quiet"});
    const Result r = run_pelt(args, dir.path());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("pelt: warning: quad.obj (objects[0].mesh): not every vertex has a normal: all normals "
                         "computed from the triangles"),
              std::string::npos)
        << command << ": " << r.err;
  }
  EXPECT_TRUE(fs::exists(out));
}

// `pelt --version` answers with the project's version and exit code 0, no subcommand needed;
// without either, pelt asks for a subcommand (exit 2).
TEST(PeltVersion, PrintsTheProjectVersion) {
  TempDir dir;
  const Result v = run_pelt({"--version"}, dir.path());
  EXPECT_EQ(v.code, 0) << v.err;
  EXPECT_EQ(v.out, "pelt 0.1\n");
  const Result none = run_pelt({}, dir.path());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("pelt: error: `pelt` needs a command: render, info, bench, tradeoff"), std::string::npos) << none.err;
}

}  // namespace
}  // namespace pelt::cli_test
