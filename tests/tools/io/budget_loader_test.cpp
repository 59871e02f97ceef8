// The loaders' budget checks (io::Budget): mesh faces for OBJ, glTF and built-in meshes,
// texture sides for image files and glTF images. Each limit is refused with the numbers
// and the flag, a request exactly at the limit is accepted, and where it can be shown the
// refusal comes before the work the budget protects (the parser, the decoder, the
// allocation).
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/base64.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/budget.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"
#include "tools/io/scene.h"

namespace pelt::io {
namespace budget_loader_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

std::filesystem::path data_dir() {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  return std::filesystem::path(root ? root : ".") / "tools" / "data";
}

Budget faces(uint64_t n) {
  Budget b;
  b.max_faces = n;
  return b;
}

Budget texture_side(int n) {
  Budget b;
  b.max_texture_side = n;
  return b;
}

// Runs `f`, expecting an InputError whose field is `field` and whose reason holds every
// one of `parts`; returns the error's text for further checks.
template <typename F>
std::string expect_refused(F&& f, const std::string& field, const std::vector<std::string>& parts) {
  try {
    f();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field, field) << e.what();
    for (const std::string& p : parts) EXPECT_NE(e.reason.find(p), std::string::npos) << "`" << p << "` in " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

// --- OBJ ---------------------------------------------------------------------------

// A quad (2 triangles), a pentagon (3) and a triangle (1): 6 triangles.
const std::string kObjFaces =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n"
    "f 1 2 3 4\n"
    "f 1 2 3 5 4\n"
    "f 1 2 3\n";

TEST(BudgetObj, ExactlyAtTheLimitIsAccepted) {
  TempDir dir;
  const auto f = dir.write("six.obj", kObjFaces);
  const LoadedMesh l = load_mesh_file(f, faces(6));
  EXPECT_EQ(l.mesh.triangle_count(), 6u);
}

TEST(BudgetObj, OneOverTheLimitIsRefusedWithBothNumbersAndTheFlag) {
  TempDir dir;
  const auto f = dir.write("six.obj", kObjFaces);
  const std::string what = expect_refused([&] { load_mesh_file(f, faces(5)); }, "",
                                          {"6 triangles", "more than the budget of 5", "--max-faces"});
  EXPECT_EQ(what.rfind(f.string(), 0), 0u) << what;  // the message starts with the file
}

// A face index of 0 is refused by the corner check, but the file is refused for its size
// first; within budget, the face's own error.
TEST(BudgetObj, RefusedBeforeTinyobjloaderParses) {
  TempDir dir;
  const auto f = dir.write("garbage_after.obj", kObjFaces + "f 0 0 0\n");
  expect_refused([&] { load_mesh_file(f, faces(6)); }, "", {"7 triangles", "--max-faces"});
  expect_refused([&] { load_mesh_file(f, faces(7)); }, "f 4", {"vertex index 0: OBJ numbers its records from 1"});
}

// A malformed number after the faces would stop the number check; the budget is still
// judged on every face of the file first.
TEST(BudgetObj, RefusedBeforeTheNumberCheck) {
  TempDir dir;
  const auto f = dir.write("bad_number_after.obj", kObjFaces + "v 1 abc 0\n");
  expect_refused([&] { load_mesh_file(f, faces(5)); }, "", {"6 triangles", "--max-faces"});
  expect_refused([&] { load_mesh_file(f, faces(6)); }, "v 6", {"`abc` is not a number"});
}

// --max-memory is checked before the parse from the records the prescan counted: the least a
// parse holds (16 bytes a position, 12 a corner, 9 a face, ... and pelt itself). At that figure
// the file loads, a byte below it is refused naming the counts, before a malformed record after
// them is read.
TEST(BudgetObj, MemoryBelowWhatTheParseHoldsIsRefusedBeforeIt) {
  TempDir dir;
  std::string text;
  for (int i = 0; i < 100000; ++i) text += "v 0 0 0\n";
  text += "v 1 0 0\nv 0 1 0\nf 1 100001 100002\n";
  const auto f = dir.write("many_points.obj", text);
  const uint64_t need = kProcessBaselineBytes + 100002 * 16 + 3 * 12 + 9;
  Budget b;
  b.max_memory_bytes = need;
  EXPECT_EQ(load_mesh_file(f, b).mesh.triangle_count(), 1u);
  b.max_memory_bytes = need - 1;
  const std::string what = expect_refused([&] { load_mesh_file(f, b); }, "",
                                          {"reading it holds at least " + describe_bytes(need),
                                           "100002 positions, 0 texture coordinates, 0 normals and 1 faces of 3 corners",
                                           "more than the budget of " + describe_bytes(need - 1), "--max-memory"});
  EXPECT_EQ(what.rfind(f.string(), 0), 0u) << what;
  const auto bad = dir.write("bad_after.obj", text + "v 1 abc 0\n");
  expect_refused([&] { load_mesh_file(bad, b); }, "", {"reading it holds at least", "--max-memory"});
  // A file pelt mends first (here for its byte-order mark) also holds the mended text.
  const auto marked = dir.write("marked.obj", "\xEF\xBB\xBF" + text);
  b.max_memory_bytes = need;
  expect_refused([&] { load_mesh_file(marked, b); }, "", {"reading it holds at least " +
                                                              describe_bytes(need + std::filesystem::file_size(marked))});
}

TEST(BudgetObj, BunnyAtItsOwnCount) {
  const auto f = data_dir() / "bunny.obj";
  const uint64_t n = load_mesh_file(f).mesh.triangle_count();
  EXPECT_EQ(load_mesh_file(f, faces(n)).mesh.triangle_count(), n);
  expect_refused([&] { load_mesh_file(f, faces(n - 1)); }, "", {std::to_string(n) + " triangles"});
}

// --- glTF --------------------------------------------------------------------------


// One triangle (3 positions, 3 uint16 indices in a data-URI buffer) drawn by the nodes
// given; `index_count` is what the index accessor claims; `extra` is appended inside the
// top-level object (images, materials, ...), `material` is the primitive's material or -1.
std::string gltf(const std::string& scene_nodes, const std::string& nodes, uint64_t index_count = 3,
                 const std::string& extra = "", int material = -1) {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint16_t idx[4] = {0, 1, 2, 0};
  std::string bytes(reinterpret_cast<const char*>(pos), sizeof pos);
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  const std::string mat = material >= 0 ? ",\"material\":" + std::to_string(material) : "";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":)" + scene_nodes + R"(}],
  "nodes":)" + nodes + R"(,
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1)" + mat + R"(}]}],
  "buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" + base64(bytes) + R"("}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
               {"bufferView":1,"componentType":5123,"count":)" + std::to_string(index_count) +
         R"(,"type":"SCALAR"}])" + extra + "}";
}

// Three instances of the one-triangle mesh: a root with two children, all drawing it.
const std::string kThreeInstances =
    R"([{"mesh":0,"children":[1,2]},{"mesh":0,"translation":[2,0,0]},{"mesh":0,"translation":[4,0,0]}])";

TEST(BudgetGltf, EveryInstanceCountsAndTheLimitItselfIsAccepted) {
  TempDir dir;
  const auto f = dir.write("three.gltf", gltf("[0]", kThreeInstances));
  EXPECT_EQ(load_mesh_file(f, faces(3)).mesh.triangle_count(), 3u);
  expect_refused([&] { load_mesh_file(f, faces(2)); }, "",
                 {"3 triangles", "more than the budget of 2", "--max-faces"});
}

// Sixty levels of nodes that list the same child twice draw the triangle 2^60 times.
// The count is memoised per node, so it is instant, and the file is refused before a
// single position is copied (building it would never finish).
TEST(BudgetGltf, ExponentialInstancingIsCountedAndRefused) {
  std::string nodes = "[";
  for (int i = 0; i < 60; ++i) nodes += "{\"children\":[" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]},";
  nodes += "{\"mesh\":0}]";
  TempDir dir;
  const auto f = dir.write("dag.gltf", gltf("[0]", nodes));
  expect_refused([&] { load_mesh_file(f); }, "", {std::to_string(uint64_t{1} << 60) + " triangles", "--max-faces"});
}

// The counts come from the JSON: an index accessor claiming 3e9 indices is refused for its
// size before the accessor is checked against (or read from) its 6-byte buffer view.
TEST(BudgetGltf, ClaimedAccessorCountIsRefusedBeforeItIsRead) {
  TempDir dir;
  const auto f = dir.write("claims.gltf", gltf("[0]", R"([{"mesh":0}])", 3000000000ull));
  expect_refused([&] { load_mesh_file(f); }, "", {"1000000000 triangles", "--max-faces"});
  Budget big;
  big.max_faces = uint64_t{1} << 40;
  expect_refused([&] { load_mesh_file(f, big); }, "accessors[1]", {"runs past the end"});
}

// --- image headers -----------------------------------------------------------------

uint32_t crc32(const std::string& bytes) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

void put32(std::string& s, uint32_t v) {
  for (int k = 3; k >= 0; --k) s.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
}

void chunk(std::string& png, const char* type, const std::string& data) {
  put32(png, static_cast<uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  png += body;
  put32(png, crc32(body));
}

// A PNG whose IHDR claims width x height (8-bit RGBA) followed by an empty IDAT and IEND:
// a valid header for any reader, no pixels behind it.
std::string claimed_png(uint32_t width, uint32_t height) {
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  put32(ihdr, width);
  put32(ihdr, height);
  ihdr += std::string("\x08\x06\x00\x00\x00", 5);
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", "");
  chunk(png, "IEND", "");
  return png;
}

std::optional<EncodedImageSize> size_of(const std::string& bytes) {
  return encoded_image_size(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

TEST(BudgetImageHeader, PngSizeFromIhdr) {
  const auto s = size_of(claimed_png(100000, 70000));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, 100000);
  EXPECT_EQ(s->height, 70000);
  EXPECT_FALSE(size_of(claimed_png(100000, 70000).substr(0, 23)));  // cut inside IHDR
  EXPECT_FALSE(size_of(claimed_png(0, 5)));
}

TEST(BudgetImageHeader, JpegSizeFromTheFirstFrameHeader) {
  // SOI, an APP0 segment, a DHT-coded C4 segment (not a frame), then SOF2: precision 8,
  // height 300, width 500.
  std::string jpeg("\xFF\xD8", 2);
  jpeg += std::string("\xFF\xE0\x00\x06JF\x00\x00", 8);
  jpeg += std::string("\xFF\xC4\x00\x04\x00\x00", 6);
  jpeg += std::string("\xFF\xFF\xC2\x00\x0B\x08\x01\x2C\x01\xF4\x01\x01\x11\x00", 14);
  const auto s = size_of(jpeg);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, 500);
  EXPECT_EQ(s->height, 300);
  EXPECT_FALSE(size_of(jpeg.substr(0, 20)));  // cut before the frame header's sizes
  // Scan data before any frame header: no size.
  EXPECT_FALSE(size_of(std::string("\xFF\xD8\xFF\xDA\x00\x02", 6)));
  EXPECT_FALSE(size_of("GIF89a....."));
  EXPECT_FALSE(encoded_image_size(nullptr, 0));
}

TEST(BudgetImageHeader, ShippedPngMatchesOpenImageIo) {
  const auto file = data_dir() / "BoxTextured-glTF" / "CesiumLogoFlat.png";
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto s = size_of(bytes);
  const ImageHeader h = read_image_header(file);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, h.width);
  EXPECT_EQ(s->height, h.height);
}

// --- image files -------------------------------------------------------------------

TEST(BudgetImageFile, SideAtTheLimitIsReadOneLessIsRefused) {
  TempDir dir;
  const auto f = dir.path() / "20x10.png";
  std::vector<uint8_t> px(20 * 10 * 4, 128);
  write_image_atomic(f, 20, 10, 4, PixelType::u8, px.data());
  const ImageRGBA img = read_image_rgba(f, ColorEncoding::srgb, texture_side(20));
  EXPECT_EQ(img.width, 20);
  EXPECT_EQ(img.height, 10);
  expect_refused([&] { read_image_rgba(f, ColorEncoding::srgb, texture_side(19)); }, "",
                 {"20 x 10 texels", "more than the budget of 19", "--max-texture-side"});
  const ImageHeader h = read_image_header(f);
  EXPECT_EQ(h.width, 20);
  EXPECT_EQ(h.height, 10);
  EXPECT_EQ(h.channels, 4);
  EXPECT_EQ(h.bytes_per_channel, 1);
}

// 100000 x 100000 RGBA would be 40 GB of file pixels before any conversion: the header
// alone decides, with the default budget. The side is beyond what the rasterizer samples, so
// the message gives no advice to raise a budget that cannot let it through.
TEST(BudgetImageFile, HugeClaimedPngIsRefusedFromItsHeader) {
  TempDir dir;
  const auto f = dir.write("huge.png", claimed_png(100000, 100000));
  expect_refused([&] { read_image_rgba(f); }, "",
                 {"100000 x 100000 texels", "more than 16384, the largest the rasterizer samples"});
  try {
    read_image_rgba(f);
  } catch (const InputError& e) {
    EXPECT_EQ(e.reason.find("--max-texture-side"), std::string::npos) << e.what();
  }
}

// --- glTF images ------------------------------------------------------------------

std::string image_extra(const std::string& png) {
  return R"(,"images":[{"uri":"data:image/png;base64,)" + base64(png) + R"("}],
  "textures":[{"source":0}],
  "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])";
}

TEST(BudgetGltfImage, HugeClaimedEmbeddedPngIsRefusedBeforeDecoding) {
  TempDir dir;
  const auto f = dir.write("huge_image.gltf",
                           gltf("[0]", R"([{"mesh":0}])", 3, image_extra(claimed_png(100000, 100000)), 0));
  const std::string what = expect_refused([&] { load_mesh_file(f); }, "images[0]",
                                          {"100000 x 100000 texels", "more than 16384, the largest the rasterizer samples"});
  EXPECT_EQ(what.rfind(f.string(), 0), 0u) << what;
}

TEST(BudgetGltfImage, ShippedGlbImageAtTheLimitIsAccepted) {
  const auto f = data_dir() / "BoxTextured.glb";  // embeds CesiumLogoFlat.png, 211 x 211
  const LoadedMesh l = load_mesh_file(f, texture_side(211));
  EXPECT_EQ(l.color_map().pixels->width, 211);
  expect_refused([&] { load_mesh_file(f, texture_side(210)); }, "images[0]",
                 {"211 x 211 texels", "more than the budget of 210"});
}

TEST(BudgetGltfImage, ExternalImageIsCheckedToo) {
  const auto f = data_dir() / "BoxTextured-glTF" / "BoxTextured.gltf";
  EXPECT_NO_THROW(load_mesh_file(f, texture_side(211)));
  expect_refused([&] { load_mesh_file(f, texture_side(100)); }, "images[0]", {"211 x 211 texels"});
}

TEST(BudgetGltfImage, ImagesOtherThanPngOrJpegAreRefused) {
  TempDir dir;
  const std::string gif("GIF89a\x01\x00\x01\x00\x00\x00\x00;", 14);
  const auto f = dir.write("gif.gltf", gltf("[0]", R"([{"mesh":0}])", 3, image_extra(gif), 0));
  expect_refused([&] { load_mesh_file(f); }, "images[0]", {"not a PNG or JPEG"});
}

// --- built-in meshes ---------------------------------------------------------------

TEST(BudgetBuiltin, CountFormulaMatchesTheGeneratedMeshes) {
  for (const char* spec : {"box:1", "box:5", "plane:1", "plane:7", "sphere:4", "sphere:9", "sphere:16"}) {
    const BuiltinSpec s = parse_builtin_spec(spec);
    EXPECT_EQ(builtin_triangle_count(s), make_builtin_mesh(s).triangle_count()) << spec;
  }
  // The teapot drops the triangles that collapse at its patches' poles: the count is
  // what is generated before that, a bound on the result.
  for (const char* spec : {"teapot:2", "teapot:6"}) {
    const BuiltinSpec s = parse_builtin_spec(spec);
    const uint64_t bound = builtin_triangle_count(s), made = make_builtin_mesh(s).triangle_count();
    EXPECT_LE(made, bound) << spec;
    EXPECT_GE(made, bound * 9 / 10) << spec;
    EXPECT_EQ(bound, 64u * s.n * s.n);
  }
}

TEST(BudgetBuiltin, AtTheLimitAcceptedOneLessRefused) {
  const BuiltinSpec s = parse_builtin_spec("box:3");  // 108 triangles
  EXPECT_EQ(make_builtin_mesh(s, faces(108)).triangle_count(), 108u);
  expect_refused([&] { make_builtin_mesh(s, faces(107), "scene.json", "objects[2].mesh"); }, "objects[2].mesh",
                 {"`box:3`", "108 triangles", "more than the budget of 107", "--max-faces"});
  // The largest accepted sphere would be 4.2M triangles: refused at once by a small budget.
  expect_refused([&] { make_builtin_mesh(parse_builtin_spec("sphere:2048"), faces(1000)); }, "",
                 {std::to_string(2ull * 2048 * 1023) + " triangles"});
}

// --- load_scene_meshes --------------------------------------------------------------

TEST(BudgetScene, LoadSceneMeshesPassesTheBudgetToEveryMesh) {
  TempDir dir;
  const auto obj = dir.write("six.obj", kObjFaces);
  const std::string text = R"({"pelt": 1, "objects": [
      {"mesh": "plane:2", "material": {"type": "lambert"}},
      {"mesh": "six.obj", "material": {"type": "lambert"}}]})";
  const auto scene_file = dir.write("scene.json", text);
  const Scene s = load_scene(scene_file);
  EXPECT_EQ(load_scene_meshes(s, faces(8)).size(), 2u);  // plane:2 is 8, the OBJ 6
  EXPECT_EQ(load_scene_meshes(s).size(), 2u);             // the default budget
  try {
    load_scene_meshes(s, faces(7));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, scene_file.string());
    EXPECT_EQ(e.field, "objects[0].mesh");
    EXPECT_NE(e.reason.find("8 triangles"), std::string::npos) << e.what();
  }
  try {
    load_scene_meshes(s, faces(6));  // plane:2 is over too: the first refusal wins
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field, "objects[0].mesh");
  }
  const std::string only_obj = R"({"pelt": 1, "objects": [{"mesh": "six.obj", "material": {"type": "lambert"}}]})";
  const Scene s2 = load_scene(dir.write("scene2.json", only_obj));
  try {
    load_scene_meshes(s2, faces(5));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, obj.string());  // a mesh file's own error keeps its file
    EXPECT_NE(e.reason.find("6 triangles"), std::string::npos) << e.what();
    EXPECT_NE(e.reason.find("(in objects[0].mesh of " + (dir.path() / "scene2.json").string() + ")"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace budget_loader_test
}  // namespace pelt::io
