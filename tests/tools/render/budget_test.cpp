// check_scene_budget, estimate_memory and check_memory_budget (tools/render/budget_check.h):
// each limit refused with the field, both numbers and the flag; a request exactly at the
// limit accepted; the estimate built from counts and headers only.
#include "tools/render/budget_check.h"

#include <atomic>
#include <chrono>
#include <climits>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "fur/fur_geometry.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tests/tools/render/two_quads_gltf.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render {
namespace {

using test::SceneDir;


// A bare sphere, then a furry box; the image 100 x 50.
std::string two_objects(int shells = 16, int texture_size = 256, const std::string& extra = "") {
  return R"({"pelt": 1, "image": {"width": 100, "height": 50},
  "objects": [{"mesh": "sphere:8", "material": {"type": "lambert"}},
              {"mesh": "box:2", "material": {"type": "lambert"},
               "fur": {"shells": )" +
         std::to_string(shells) + R"(, "texture_size": )" + std::to_string(texture_size) + "}}]" + extra + "}";
}

template <typename F>
io::InputError refusal(F&& f) {
  try {
    f();
  } catch (const io::InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted";
  return io::InputError("", "", "");
}

void expect_reason_has(const io::InputError& e, const std::vector<std::string>& parts) {
  for (const std::string& p : parts) EXPECT_NE(e.reason.find(p), std::string::npos) << "`" << p << "` in " << e.what();
}

// --- check_scene_budget ---------------------------------------------------------------

TEST(SceneBudget, ImagePixelsAtTheLimitAcceptedOneMoreRefused) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects());
  io::Budget b;
  b.max_pixels = 5000;
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, b));      // the scene's 100 x 50
  EXPECT_NO_THROW(check_scene_budget(s, 200, 25, 1, b));   // an override of the same size
  const io::InputError e = refusal([&] { check_scene_budget(s, 201, 25, 1, b); });
  EXPECT_EQ(e.file, (dir.path() / "scene.json").string());
  EXPECT_EQ(e.field, "image.width");
  expect_reason_has(e, {"201 x 25 = 5025 pixels", "more than the budget of 5000 pixels", "--max-pixels"});
  b.max_pixels = 4999;
  expect_reason_has(refusal([&] { check_scene_budget(s, 0, 0, 1, b); }), {"100 x 50 = 5000 pixels"});
}

// Image buffers large enough that a budget refusing them is above the process's own footprint
// (a smaller budget is refused for the process first, as TooSmallForAnyRender shows).
constexpr int kBigW = 4000, kBigH = 1100;

TEST(SceneBudget, ImageBuffersAgainstTheMemoryBudget) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects());
  EXPECT_EQ(image_bytes(100, 50, 1), 5000u * 36);       // two float RGBA and the 8-bit file
  EXPECT_EQ(image_bytes(100, 50, 4), 5000u * (36 + 48));  // plus a sample image and a double sum
  io::Budget b;
  b.max_memory_bytes = image_bytes(kBigW, kBigH, 1);
  ASSERT_GE(b.max_memory_bytes, kProcessBaselineBytes);
  EXPECT_NO_THROW(check_scene_budget(s, kBigW, kBigH, 1, b));
  // Only the supersampling buffers make it too large: the spp is named.
  io::InputError e = refusal([&] { check_scene_budget(s, kBigW, kBigH, 4, b); });
  EXPECT_EQ(e.field, "quality.spp");
  expect_reason_has(e, {"4 samples per pixel", describe_bytes(image_bytes(kBigW, kBigH, 4)),
                        describe_bytes(b.max_memory_bytes), "--max-memory"});
  b.max_memory_bytes -= 1;
  e = refusal([&] { check_scene_budget(s, kBigW, kBigH, 1, b); });
  EXPECT_EQ(e.field, "image.width");
}

// A still renders into one float image; a GIF adds its encoder's buffers to a sequence's. The
// budget that a sequence's buffers exceed by a byte takes a still, and refuses a GIF naming it.
TEST(SceneBudget, AStillHoldsOneImageAndAGifItsEncoderToo) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects());
  EXPECT_EQ(image_bytes(100, 50, 1, ImageOutput::still), 5000u * 20);
  EXPECT_EQ(image_bytes(100, 50, 1, ImageOutput::sequence), 5000u * 36);
  EXPECT_EQ(image_bytes(100, 50, 1, ImageOutput::gif), 5000u * (36 + kGifBytesPerPixel));
  EXPECT_EQ(image_bytes(100, 50, 4, ImageOutput::still), 5000u * (20 + 48));
  io::Budget b;
  b.max_memory_bytes = image_bytes(kBigW, kBigH, 1) - 1;
  EXPECT_NO_THROW(check_scene_budget(s, kBigW, kBigH, 1, b, ImageOutput::still));
  EXPECT_THROW(check_scene_budget(s, kBigW, kBigH, 1, b, ImageOutput::sequence), io::InputError);
  b.max_memory_bytes = image_bytes(kBigW, kBigH, 1);
  expect_reason_has(refusal([&] { check_scene_budget(s, kBigW, kBigH, 1, b, ImageOutput::gif); }),
                    {"image written as a GIF needs", describe_bytes(image_bytes(kBigW, kBigH, 1, ImageOutput::gif))});
  const MemoryEstimate seq = estimate_memory(s, io::load_scene_meshes(s), 0, 0, 1, 1);
  const MemoryEstimate gif = estimate_memory(s, io::load_scene_meshes(s), 0, 0, 1, 1, true, ImageOutput::gif);
  EXPECT_EQ(gif.total - seq.total, 5000u * kGifBytesPerPixel);
}

// A budget below what pelt takes before any scene is refused before any mesh loads, naming
// --max-memory, not the image or a mesh.
TEST(SceneBudget, TooSmallForAnyRender) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects());
  io::Budget b;
  b.max_memory_bytes = kProcessBaselineBytes - 1;
  const io::InputError e = refusal([&] { check_scene_budget(s, 0, 0, 1, b); });
  EXPECT_EQ(e.field, "--max-memory");
  expect_reason_has(e, {"pelt itself", describe_bytes(kProcessBaselineBytes), "is too small for any render"});
  b.max_memory_bytes = kProcessBaselineBytes;
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, b));
}

TEST(SceneBudget, ShellsAtTheLimitAcceptedOneLessRefused) {
  SceneDir dir;
  io::Scene s = dir.scene(two_objects(16));
  io::Budget b;
  b.max_shells = 16;
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, b));
  b.max_shells = 15;
  io::InputError e = refusal([&] { check_scene_budget(s, 0, 0, 1, b); });
  EXPECT_EQ(e.field, "objects[1].fur.shells");
  expect_reason_has(e, {"16 fur shells", "more than the budget of 15", "--max-shells"});
  // A quality override sets every fur block's shells: it is what is judged, and named.
  s.quality.shells = 8;
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, b));
  s.quality.shells = 64;
  e = refusal([&] { check_scene_budget(s, 0, 0, 1, b); });
  EXPECT_EQ(e.field, "quality.shells");
  expect_reason_has(e, {"64 fur shells"});
}

TEST(SceneBudget, FurTextureSizeAtTheLimitAcceptedOneLessRefused) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 512));
  io::Budget b;
  b.max_texture_side = 512;
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, b));
  b.max_texture_side = 511;
  const io::InputError e = refusal([&] { check_scene_budget(s, 0, 0, 1, b); });
  EXPECT_EQ(e.field, "objects[1].fur.texture_size");
  expect_reason_has(e, {"512 x 512 texels", "more than the budget of 511", "--max-texture-side"});
}

TEST(SceneBudget, DefaultBudgetAcceptsTheShippedScale) {
  SceneDir dir;
  EXPECT_NO_THROW(check_scene_budget(dir.scene(two_objects(128, 4096)), 8192, 8192, 1, io::Budget{}));
}

// --- estimate_memory ------------------------------------------------------------------

uint64_t mipmapped(uint64_t texels) { return texels * 16 / 3 + 4; }

// The blurred normals' pair budget (shading::NormalBlurBudget), from the renderer: sphere:16 has
// 16 x 7 + 2 = 114 positions, and at radius 1e6 each reaches all 114, 12996 pairs. The refusal
// names the object's radius, the count, the budget and the flag, before any search has run.
TEST(BlurPairBudget, AtTheLimitAcceptedOneLessRefusedNamingTheRadius) {
  SceneDir dir;
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 20, "height": 20},
      "objects": [{"mesh": "box:2", "material": {"type": "lambert"}},
                  {"mesh": "sphere:16", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur",
                   "normal_blur_radius": [1e6, 0.1, 0.05]}}}]})");
  const auto meshes = io::load_scene_meshes(s);
  RenderSettings rs;
  rs.threads = 2;
  rs.budget.max_blur_pairs = 114 * 114;
  EXPECT_NO_THROW(SceneRenderer(s, meshes, rs));
  rs.budget.max_blur_pairs = 114 * 114 - 1;
  const io::InputError e = refusal([&] { SceneRenderer r(s, meshes, rs); });
  EXPECT_EQ(e.file, (dir.path() / "scene.json").string());
  EXPECT_EQ(e.field, "objects[1].material.skin.normal_blur_radius");
  expect_reason_has(e, {"about 12996 (source, neighbour) vertex pairs", "more than the budget of 12995 pairs",
                        "(raise it with --max-blur-pairs)", "a smaller radius reaches fewer"});
}

// The default budget refuses sphere:1024 at the default radius (about 2.6 x 10^10 pairs, which
// searched on one core would take most of an hour) at once: the estimate's 64 searches and the
// welded graph, not the blur. (sphere:2048, four times the vertices and the neighbours of each,
// about 2.5 x 10^11 pairs, is refused the same way in 5.6 s, most of it making the mesh.)
TEST(BlurPairBudget, DefaultBudgetRefusesALargeSphereAtOnce) {
  SceneDir dir;
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 20, "height": 20},
      "objects": [{"mesh": "sphere:1024", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur"}}}]})");
  const auto meshes = io::load_scene_meshes(s);
  RenderSettings rs;
  rs.threads = 2;
  const auto start = std::chrono::steady_clock::now();
  const io::InputError e = refusal([&] { SceneRenderer r(s, meshes, rs); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(e.field, "objects[0].material.skin.normal_blur_radius");
  expect_reason_has(e, {"more than the budget of 4294967296 pairs", "of its 523266 welded vertices"});
  EXPECT_LT(seconds, 60.0) << "the refusal waits for no blur";
}

TEST(MemoryEstimate, PartsFollowTheCounts) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 256));
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 2, 1);
  // sphere mesh; box mesh, fur geometry, fur textures; image; scratch; then the rasterizer's
  // set-ups of the sphere, the box and the fur; the process itself.
  ASSERT_EQ(e.parts.size(), 10u);
  EXPECT_EQ(e.parts[0].field, "objects[0].mesh");
  EXPECT_EQ(e.parts[1].field, "objects[1].mesh");
  EXPECT_EQ(e.parts[2].field, "objects[1].fur.shells");
  EXPECT_EQ(e.parts[3].field, "objects[1].fur.texture_size");
  EXPECT_EQ(e.parts[4].field, "image.width");
  EXPECT_EQ(e.parts[5].field, "--threads");
  EXPECT_EQ(e.parts[6].field, "objects[0].mesh");
  EXPECT_EQ(e.parts[7].field, "objects[1].mesh");
  EXPECT_EQ(e.parts[8].field, "objects[1].fur.shells");
  EXPECT_EQ(e.parts[9].bytes, kProcessBaselineBytes);
  // The rasterizer: 48 bytes a vertex (clip position, front-end vertex) and 140 a triangle (a
  // set-up triangle of 128, a bin entry, its sort scratch), plus 16 KiB an object.
  EXPECT_EQ(e.parts[7].bytes, meshes[1].loaded.mesh.positions.size() * 48 +
                                  meshes[1].loaded.mesh.triangle_count() * 140 + 16384);

  // Mesh: positions and normals, uvs, 8 varyings a vertex; three indices a triangle.
  const Mesh& box = meshes[1].loaded.mesh;
  EXPECT_EQ(e.parts[1].bytes, box.positions.size() * (24 + 8 + 32) + box.triangle_count() * 12);
  // Strand textures: 16 shells and the fin texture mipmapped, the unmipped sources (2 bytes a
  // shell texel, 6 a fin texel: RGBA8 and luminance-alpha), and two layers' mip working sets at
  // once (2 threads).
  const uint64_t texels = 256 * 256;
  EXPECT_EQ(e.parts[3].bytes, 17 * mipmapped(texels) + texels * (16 * 2 + 6) + 2 * texels * 12);
  EXPECT_EQ(e.parts[4].bytes, image_bytes(100, 50, 1));
  const MemoryEstimate four = estimate_memory(s, meshes, 0, 0, 4, 1);
  EXPECT_EQ(four.parts[5].bytes, 2 * e.parts[5].bytes);
  // The exact sort: each worker's fragment lists at their cap, 48 bytes a fragment, after the scratch.
  const MemoryEstimate exact = estimate_memory(s, meshes, 0, 0, 2, 1, true, ImageOutput::sequence, true);
  ASSERT_EQ(exact.parts.size(), 11u);
  EXPECT_EQ(exact.parts[6].field, "--sort");
  EXPECT_EQ(exact.parts[6].bytes, 2 * uint64_t(raster::kExactFragmentCap) * 48);
  EXPECT_EQ(exact.total, e.total + exact.parts[6].bytes);

  uint64_t sum = 0;
  for (const MemoryPart& p : e.parts) sum += p.bytes;
  EXPECT_EQ(e.total, sum);
  EXPECT_EQ(&e.largest(), &e.parts[3]);  // the process (most of a small scene) is never named

  // More shells: more fur geometry, textures and set-ups; the meshes do not change.
  const io::Scene s32 = dir.scene(two_objects(32, 256));
  const MemoryEstimate e32 = estimate_memory(s32, meshes, 0, 0, 2, 1);
  EXPECT_GT(e32.parts[2].bytes, e.parts[2].bytes * 19 / 10);
  EXPECT_EQ(e32.parts[3].bytes, 33 * mipmapped(texels) + texels * (32 * 2 + 6) + 2 * texels * 12);
  EXPECT_EQ(e32.parts[1].bytes, e.parts[1].bytes);
}

// The estimate is judged against what SceneRenderer actually holds once built: never
// below it (the estimate counts the peak, with transient buffers), and not wildly above.
TEST(MemoryEstimate, BoundsWhatTheRendererHolds) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 128));
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 1, 1);
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer r(s, meshes, rs);
  const uint64_t held = r.memory_estimate();
  EXPECT_GE(e.renderer_total(), held);
  EXPECT_LE(e.renderer_total(), held * 5 / 2);
  // After a frame of the surface sort, which also holds the pose in clip space and a key per
  // shell triangle.
  io::Quality q;
  q.sort = io::SortQuality::surface;
  rs.quality = q;
  SceneRenderer drawn(s, meshes, rs);
  FrameImage img;
  FrameStats st;
  drawn.render(0, img, st);
  EXPECT_TRUE(st.stage("fur_sort").ran);
  EXPECT_GT(drawn.memory_estimate(), held);
  EXPECT_GE(e.renderer_total(), drawn.memory_estimate());
}

// The counts a fur geometry part's text gives: "..., N vertices, M shell and fin triangles".
struct FurPartCounts {
  uint64_t vertices = 0, triangles = 0;
};
FurPartCounts fur_part_counts(const std::string& what) {
  const auto number_before = [&](const char* word) {
    const size_t at = what.find(word);
    if (at == std::string::npos) throw std::logic_error("no `" + std::string(word) + "` in " + what);
    return std::stoull(what.substr(what.rfind(' ', at - 1) + 1));
  };
  return {number_before(" vertices"), number_before(" shell and fin triangles")};
}

// A colour map adds the mesh uv to every fur vertex's shell and fin varyings and keeps the mesh uvs per
// base vertex; a length map keeps a scale per base vertex and is read whole while the fur is built.
// The estimate counts both (it was about 5 % low for furry objects with fins before), and still
// bounds what the renderer holds.
TEST(MemoryEstimate, TheFurMapsAreCounted) {
  SceneDir dir;
  const uint8_t grey[4] = {128, 128, 128, 128};
  io::write_image_atomic(dir.path() / "map.png", 2, 2, 1, io::PixelType::u8, grey);
  auto scene = [&](const std::string& fur_extra) {
    return dir.scene(R"({"pelt": 1, "image": {"width": 100, "height": 50},
      "objects": [{"mesh": "box:2", "material": {"type": "lambert", "color_map": "map.png"},
                   "fur": {"shells": 16, "texture_size": 64)" + fur_extra + "}}]}");
  };
  const io::Scene plain = scene(""), both = scene(R"(, "use_color_map": true, "length_map": "map.png")");
  const auto meshes = io::load_scene_meshes(plain);
  const MemoryEstimate a = estimate_memory(plain, meshes, 0, 0, 1, 1);
  const MemoryEstimate b = estimate_memory(both, meshes, 0, 0, 1, 1);
  ASSERT_EQ(b.parts.size(), a.parts.size() + 1);
  const size_t geo = 2;  // mesh, colour map, fur geometry
  ASSERT_EQ(a.parts[geo].field, "objects[0].fur.shells");
  // The counts as the estimate makes them (16 layers of the base's vertices and faces); the map's
  // list per base face and per fin quad besides.
  const FurPartCounts n = fur_part_counts(a.parts[geo].what);
  const uint64_t base = n.vertices / 16, faces = meshes[0].loaded.mesh.triangle_count(), fins = n.triangles - 16 * faces;
  EXPECT_EQ(b.parts[geo].bytes - a.parts[geo].bytes,
            n.vertices * 2 * 2 * sizeof(float) + base * (8 + 4) + (faces + fins / 2) * 4);
  bool length_map_part = false;
  for (const MemoryPart& p : b.parts) length_map_part |= p.field == "objects[0].fur.length_map";
  EXPECT_TRUE(length_map_part);
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer r(both, meshes, rs);
  EXPECT_GE(b.renderer_total(), r.memory_estimate());
}

// Fur over a cut-out (alphaMode MASK with a map) reads the map's alpha, copied, at the mesh uvs as a
// colour map is read: the estimate counts the copy and the uvs, and still bounds what the renderer
// holds. A cut by the factor alone reads no map and counts neither.
TEST(MemoryEstimate, AFurCutOutsMeshUvsAreCounted) {
  SceneDir dir;
  const uint8_t texels[4 * 4] = {0, 255, 0, 0, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255, 0, 0};
  io::write_image_atomic(dir.path() / "front.png", 2, 2, 4, io::PixelType::u8, texels);
  int files = 0;
  auto scene = [&](const std::string& front) {
    const std::string name = "quads" + std::to_string(files++) + ".gltf";
    dir.write(name, test::two_quads_gltf(front));
    return front_view_scene(dir, name, R"({"type": "lambert"})", R"(, "fur": {"shells": 8, "texture_size": 32})");
  };
  const std::string map = R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0}})";
  const io::Scene opaque = scene("{" + map + "}"), cut = scene(R"({"alphaMode":"MASK",)" + map + "}");
  const io::Scene by_factor = scene(R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.2]}})");
  const MemoryEstimate a = estimate_memory(opaque, io::load_scene_meshes(opaque), 0, 0, 1, 1);
  const MemoryEstimate b = estimate_memory(cut, io::load_scene_meshes(cut), 0, 0, 1, 1);
  const MemoryEstimate c = estimate_memory(by_factor, io::load_scene_meshes(by_factor), 0, 0, 1, 1);
  const auto fur_geometry = [](const MemoryEstimate& e) -> const MemoryPart& {
    for (const MemoryPart& p : e.parts)
      if (p.kind == "fur geometry") return p;
    throw std::logic_error("no fur geometry part");
  };
  const FurPartCounts n = fur_part_counts(fur_geometry(a).what);
  const uint64_t base = n.vertices / 8, fins = n.triangles - 8 * 4;  // two quads: 4 base faces
  EXPECT_EQ(fur_geometry(b).bytes - fur_geometry(a).bytes,
            n.vertices * 2 * 2 * sizeof(float) + base * 8 + (4 + fins / 2) * 4);
  EXPECT_EQ(fur_geometry(c).bytes, fur_geometry(a).bytes);
  // The map comes with its alpha copied for the fur (cut_alpha_texture), 2 bytes a texel and levels.
  const auto colour_map = [](const MemoryEstimate& e) -> const MemoryPart& {
    for (const MemoryPart& p : e.parts)
      if (p.kind == "colour maps") return p;
    throw std::logic_error("no colour map part");
  };
  EXPECT_EQ(colour_map(b).bytes - colour_map(a).bytes, 4 * 2 + (4 * 4 * 4 / 3 + 4) / 2);
  EXPECT_NE(colour_map(b).what.find("its alpha for the fur's cut-out"), std::string::npos) << colour_map(b).what;
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer r(cut, io::load_scene_meshes(cut), rs);
  EXPECT_GE(b.renderer_total(), r.memory_estimate());
}

// Fur without fins builds no fin texture, coordinates, varyings or triangles: the estimate counts
// none, and still bounds what the renderer holds, which is less than with fins.
TEST(MemoryEstimate, FurWithoutFinsCountsNoFins) {
  SceneDir dir;
  const std::string fins_off = R"({"pelt": 1, "image": {"width": 100, "height": 50},
  "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
               "fur": {"shells": 16, "texture_size": 256, "fins": "off"}}]})";
  const std::string fins_on = R"({"pelt": 1, "image": {"width": 100, "height": 50},
  "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
               "fur": {"shells": 16, "texture_size": 256}}]})";
  const io::Scene off = dir.scene(fins_off);
  const io::Scene on = dir.scene(fins_on);
  const auto meshes = io::load_scene_meshes(off);
  const MemoryEstimate e = estimate_memory(off, meshes, 0, 0, 2, 1);
  const MemoryEstimate with = estimate_memory(on, meshes, 0, 0, 2, 1);
  ASSERT_EQ(e.parts[2].field, "objects[0].fur.texture_size");
  const uint64_t texels = 256 * 256;
  EXPECT_EQ(e.parts[2].bytes, 16 * mipmapped(texels) + texels * 16 * 2 + 2 * texels * 12);
  EXPECT_LT(e.parts[1].bytes, with.parts[1].bytes);
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer without_fins(off, meshes, rs);
  const SceneRenderer with_fins(on, meshes, rs);
  EXPECT_EQ(without_fins.fur_geometry(0)->counts.fin_faces, 0u);
  EXPECT_TRUE(without_fins.fur_geometry(0)->fin_indices.empty());
  EXPECT_TRUE(without_fins.fur_geometry(0)->fin_uvs.empty());
  EXPECT_LT(without_fins.memory_estimate(), with_fins.memory_estimate());
  EXPECT_GE(estimate_memory(off, meshes, 0, 0, 1, 1).renderer_total(), without_fins.memory_estimate());
}

// The box mapping copies vertices where its planes meet, which depends on how the object is
// turned: the estimate counts them on the mesh as the scene places it, as the renderer builds it.
TEST(MemoryEstimate, FurGeometryCountsTheBoxCopiesOfTheTurnedMesh) {
  SceneDir dir;
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 20, "height": 20},
      "objects": [{"mesh": "sphere:24", "material": {"type": "lambert"},
                   "transform": {"rotate_deg": [20, 30, 0]},
                   "fur": {"shells": 4, "texture_size": 16, "texture_coordinates": "box"}}]})");
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 1, 1);
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer r(s, meshes, rs);
  const size_t built = r.fur_geometry(0)->counts.shell_vertices;
  ASSERT_EQ(e.parts[1].field, "objects[0].fur.shells");
  EXPECT_NE(e.parts[1].what.find(": " + std::to_string(built) + " vertices,"), std::string::npos) << e.parts[1].what;
  // Unturned, the sphere's copies are others (the test would not see a count taken before the turn).
  EXPECT_NE(fur::fur_base_vertex_count(meshes[0].loaded.mesh, *s.objects[0].fur) * 4, built);
}

TEST(MemoryEstimate, ColourMapSizedFromItsHeader) {
  SceneDir dir;
  std::vector<uint8_t> px(64 * 32 * 3, 200);
  io::write_image_atomic(dir.path() / "map.png", 64, 32, 3, io::PixelType::u8, px.data());
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 10, "height": 10},
      "objects": [{"mesh": "plane:1", "material": {"type": "lambert", "color_map": "map.png"}}]})");
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 1, 1);
  ASSERT_EQ(e.parts.size(), 6u);  // mesh, map, image, scratch, the rasterizer's set-up, the process
  EXPECT_EQ(e.parts[1].field, "objects[0].material.color_map");
  // Float RGBA as read, the file's 3 bytes a texel, the mip chain's working set (4 + 32 / 4),
  // the mipmapped 8-bit texture.
  EXPECT_EQ(e.parts[1].bytes, 2048u * (16 + 3 + 12) + mipmapped(2048));
  EXPECT_NE(e.parts[1].what.find("64 x 32"), std::string::npos) << e.parts[1].what;
}

// A mesh whose materials give two map sets: each image counted once (the colour map both
// draw), the normal map once, and the parts' vertex copies counted exactly; the estimate still
// bounds what the renderer holds.
TEST(MemoryEstimate, MapSetsCountEachImageOnceAndThePartsCopies) {
  SceneDir dir;
  std::vector<uint8_t> px(16 * 8 * 3, 200);
  io::write_image_atomic(dir.path() / "c.png", 16, 8, 3, io::PixelType::u8, px.data());
  io::write_image_atomic(dir.path() / "n.png", 8, 8, 3, io::PixelType::u8, px.data());
  dir.write("m.mtl", "newmtl a\nmap_Kd c.png\nnewmtl b\nmap_Kd c.png\nnorm n.png\n");
  // Two triangles of each material, taking turns: 4 vertices each, those of the middle column in both.
  dir.write("p.obj", "mtllib m.mtl\nv -1 0 1\nv 0 0 1\nv 1 0 1\nv -1 0 -1\nv 0 0 -1\nv 1 0 -1\n"
                     "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 1\nvt 0.5 1\nvt 1 1\nvn 0 1 0\n"
                     "usemtl a\nf 1/1/1 2/2/1 5/5/1\nusemtl b\nf 2/2/1 3/3/1 6/6/1\nusemtl a\nf 1/1/1 5/5/1 4/4/1\n"
                     "usemtl b\nf 2/2/1 6/6/1 5/5/1\n");
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 10, "height": 10},
      "objects": [{"mesh": "p.obj", "material": {"type": "lambert"}}]})");
  const auto meshes = io::load_scene_meshes(s);
  ASSERT_EQ(meshes[0].loaded.maps.size(), 2u);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 1, 1);
  int colour = 0, normal = 0, split = 0;
  for (const MemoryPart& p : e.parts) {
    colour += p.kind == "colour maps";
    normal += p.kind == "normal maps";
    if (p.what.find("parts by material") != std::string::npos) {
      ++split;
      EXPECT_NE(p.what.find("mesh drawn in 2 parts by material, 8 vertex copies"), std::string::npos) << p.what;
    }
  }
  EXPECT_EQ(colour, 1);
  EXPECT_EQ(normal, 1);
  EXPECT_EQ(split, 1);
  RenderSettings rs;
  rs.threads = 1;
  const SceneRenderer r(s, meshes, rs);
  EXPECT_GE(e.renderer_total(), r.memory_estimate());
}

TEST(MemoryEstimate, SaturatesInsteadOfWrapping) {
  EXPECT_EQ(image_bytes(INT_MAX, INT_MAX, 64), UINT64_MAX);  // 84 bytes x 4.6e18 pixels
  EXPECT_EQ(io::sat_mul(uint64_t{1} << 40, uint64_t{1} << 30), UINT64_MAX);
  EXPECT_EQ(io::sat_add(UINT64_MAX - 1, 5), UINT64_MAX);
  EXPECT_EQ(describe_bytes(uint64_t{8} << 30), "8589934592 bytes (8.0 GiB)");
  EXPECT_EQ(describe_bytes(1536), "1536 bytes (1.5 KiB)");
}

// --- check_memory_budget --------------------------------------------------------------

TEST(MemoryBudget, EstimateAtTheLimitAcceptedOneLessRefusedNamingTheLargestPart) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 256));
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 2, 1);
  io::Budget b;
  b.max_memory_bytes = e.total;
  EXPECT_NO_THROW(check_memory_budget(s, meshes, 0, 0, 2, b));
  b.max_memory_bytes = e.total - 1;
  const io::InputError err = refusal([&] { check_memory_budget(s, meshes, 0, 0, 2, b); });
  EXPECT_EQ(err.file, (dir.path() / "scene.json").string());
  EXPECT_EQ(err.field, "objects[1].fur.texture_size");
  expect_reason_has(err, {describe_bytes(e.total), describe_bytes(e.total - 1), "--max-memory",
                          "fur strand textures, 17 layers of 256^2"});
}

// Many objects' parts of one kind outweighing the largest single part are named together (a
// hunt's 216 furry spheres were refused naming the image buffers, 27 MiB of 389).
TEST(MemoryBudget, ManyObjectsTogetherAreNamed) {
  SceneDir dir;
  std::string objects;
  for (int k = 0; k < 40; ++k)
    objects += std::string(k ? "," : "") + R"({"mesh": "sphere:8", "transform": {"translate": [)" +
               std::to_string(k) + R"(, 0, 0]}, "material": {"type": "lambert"}, "fur": {"texture_size": 16}})";
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 400, "height": 300}, "objects": [)" + objects + "]}");
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate e = estimate_memory(s, meshes, 0, 0, 1, 1);
  ASSERT_EQ(e.largest().field, "image.width");
  io::Budget b;
  b.max_memory_bytes = e.total - 1;
  const io::InputError err = refusal([&] { check_memory_budget(s, meshes, 0, 0, 1, b); });
  EXPECT_EQ(err.field, "image.width");
  expect_reason_has(err, {"the largest part is the image buffers, 400 x 300", "; together, the fur geometry of 40 objects "
                                                                               "take"});
}

// The depth and id AOVs draw no fur and generate no strand textures: neither the textures nor
// the fur's set-ups are counted for them.
TEST(MemoryEstimate, NoStrandTexturesForAovsWithoutFur) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 256));
  const auto meshes = io::load_scene_meshes(s);
  const MemoryEstimate colour = estimate_memory(s, meshes, 0, 0, 1, 1);
  const MemoryEstimate depth = estimate_memory(s, meshes, 0, 0, 1, 1, /*fur_drawn=*/false);
  ASSERT_EQ(depth.parts.size() + 2, colour.parts.size());
  uint64_t textures = 0, setups = 0;
  for (const MemoryPart& p : colour.parts) {
    if (p.field == "objects[1].fur.texture_size") textures = p.bytes;
    if (p.kind == "rasterizer set-ups" && p.field == "objects[1].fur.shells") setups = p.bytes;
  }
  EXPECT_GT(textures, 0u);
  EXPECT_GT(setups, 0u);
  EXPECT_EQ(depth.total + textures + setups, colour.total);
}

// The layer sort draws the fur's vertices once per layer and per pair of layers.
TEST(MemoryEstimate, TheLayerSortSetsTheFurUpPerLayer) {
  SceneDir dir;
  io::Scene s = dir.scene(two_objects(16, 64));
  const auto meshes = io::load_scene_meshes(s);
  auto fur_setups = [&](const io::Scene& scene) {
    for (const MemoryPart& p : estimate_memory(scene, meshes, 0, 0, 1, 1).parts)
      if (p.kind == "rasterizer set-ups" && p.field == "objects[1].fur.shells") return p;
    return MemoryPart{};
  };
  const MemoryPart tile = fur_setups(s);
  s.quality.sort = io::SortQuality::layer;
  const MemoryPart layer = fur_setups(s);
  EXPECT_NE(tile.what.find(" in 2 draws a frame"), std::string::npos) << tile.what;
  EXPECT_NE(layer.what.find(" in 31 draws a frame"), std::string::npos) << layer.what;
  // 29 more draws of the same vertices, 48 bytes each a vertex; the triangles are the same.
  ASSERT_GT(layer.bytes, tile.bytes);
  EXPECT_EQ((layer.bytes - tile.bytes) % (29 * 48), 0u);
}

// A budget below what pelt itself takes refuses every render, and says so.
TEST(MemoryBudget, ABudgetBelowTheProcessItselfIsSaidToBe) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(4, 16));
  const auto meshes = io::load_scene_meshes(s);
  io::Budget b;
  b.max_memory_bytes = 100 << 20;
  const io::InputError err = refusal([&] { check_memory_budget(s, meshes, 0, 0, 1, b); });
  EXPECT_EQ(err.field, "--max-memory");
  expect_reason_has(err, {"of which pelt itself (code, shared libraries, start-up heap) takes about",
                          "is too small for any render"});
}

// Image buffers that one sample per pixel would fit in the budget are refused for their samples
// (quality.spp, which the CLI names by --spp, --quality or a tradeoff sweep's row), as
// check_scene_budget refuses them; otherwise for the image's size.
TEST(MemoryBudget, ImageBuffersOverOnlyForTheirSamplesNameTheSamples) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(16, 64));
  const auto meshes = io::load_scene_meshes(s);
  const uint64_t one = estimate_memory(s, meshes, 1000, 800, 1, 1).total;
  const MemoryEstimate four = estimate_memory(s, meshes, 1000, 800, 1, 4);
  ASSERT_EQ(four.largest().field, "image.width");
  ASSERT_LT(one, four.total - 1);
  io::Budget b;
  b.max_memory_bytes = four.total - 1;
  io::InputError err = refusal([&] { check_memory_budget(s, meshes, 1000, 800, 1, 4, b); });
  EXPECT_EQ(err.field, "quality.spp");
  expect_reason_has(err, {"the largest part is the image buffers, 1000 x 800 at 4 samples per pixel"});
  b.max_memory_bytes = one - 1;
  EXPECT_EQ(refusal([&] { check_memory_budget(s, meshes, 1000, 800, 1, 4, b); }).field, "image.width");
  EXPECT_EQ(refusal([&] { check_memory_budget(s, meshes, 1000, 800, 1, 1, b); }).field, "image.width");
}

// 96 shells of 4096^2 strand textures are over 11 GiB: refused by the default budget from
// counts alone (building them would allocate it all first).
TEST(MemoryBudget, HeavyFurRefusedByTheDefaultBudget) {
  SceneDir dir;
  const io::Scene s = dir.scene(two_objects(96, 4096));
  const auto meshes = io::load_scene_meshes(s);
  EXPECT_NO_THROW(check_scene_budget(s, 0, 0, 1, io::Budget{}));  // each request alone is allowed
  const io::InputError err = refusal([&] { check_memory_budget(s, meshes, 0, 0, 1, io::Budget{}); });
  EXPECT_EQ(err.field, "objects[1].fur.texture_size");
  expect_reason_has(err, {"8589934592 bytes (8.0 GiB)", "--max-memory", "97 layers of 4096^2"});
}

TEST(MemoryBudget, SppFromTheSceneQualityOrGiven) {
  SceneDir dir;
  io::Scene s = dir.scene(two_objects(16, 64));
  const auto meshes = io::load_scene_meshes(s);
  const uint64_t one = estimate_memory(s, meshes, 0, 0, 1, 1).total;
  const uint64_t four = estimate_memory(s, meshes, 0, 0, 1, 4).total;
  EXPECT_EQ(four - one, image_bytes(100, 50, 4) - image_bytes(100, 50, 1));
  io::Budget b;
  b.max_memory_bytes = one;
  EXPECT_NO_THROW(check_memory_budget(s, meshes, 0, 0, 1, b));
  EXPECT_THROW(check_memory_budget(s, meshes, 0, 0, 1, 4, b), io::InputError);
  s.quality.spp = 4;
  EXPECT_THROW(check_memory_budget(s, meshes, 0, 0, 1, b), io::InputError);
}

}  // namespace
}  // namespace pelt::render
