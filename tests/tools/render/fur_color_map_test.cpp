// Fur that takes the object's colour map (fur.use_color_map): the strand colour times the map
// under it, and nothing else changes.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/varyings.h"

namespace pelt::render::test {
namespace fur_color_map_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// A furry box whose material reads `map` (a flat colour, written into `dir`), its fur with
// `fur_extra`; sort exact and every fin, so that the whole fur pipeline runs.
io::Scene map_scene(const SceneDir& dir, const std::vector<uint8_t>& rgb, const std::string& fur_extra) {
  std::vector<uint8_t> px;
  for (int i = 0; i < 8 * 8; ++i) px.insert(px.end(), rgb.begin(), rgb.end());
  const std::string file = "map_" + std::to_string(rgb[0]) + "_" + std::to_string(rgb[1]) + "_" +
                           std::to_string(rgb[2]) + ".png";
  io::write_image_atomic(dir.path() / file, 8, 8, 3, io::PixelType::u8, px.data());
  std::string json = furry_box_scene(R"("fins": "all", "gravity": {}, "wind": {})" +
                                     (fur_extra.empty() ? "" : ", " + fur_extra));
  const std::string material = R"("type": "lambert", "color": [0.3, 0.2, 0.1])";
  json.replace(json.find(material), material.size(), material + R"(, "color_map": ")" + file + '"');
  return dir.scene(json);
}

FrameImage render(const io::Scene& scene, int threads = 2, io::Precision precision = io::Precision::simd,
                  FurLighting lighting = FurLighting::vertex) {
  io::Quality q;
  q.precision = precision;
  return render_at(scene, q, threads, lighting);
}

// A white map multiplies the strands by 1: the image is the one without the option, up to the
// sampler's weighted sum of equal texels, which may round a float step below 1 (measured: at
// most 6e-8, in 797 of the 76,800 channels).
// Per-pixel lighting too, whose varyings put the mesh uv after twelve floats instead of eight.
TEST(FurColorMap, AWhiteMapChangesNothing) {
  SceneDir dir;
  const std::vector<uint8_t> white = {255, 255, 255};
  for (const FurLighting lighting : {FurLighting::vertex, FurLighting::pixel}) {
    const FrameImage with = render(map_scene(dir, white, R"("use_color_map": true)"), 2, io::Precision::simd, lighting);
    const FrameImage without = render(map_scene(dir, white, ""), 2, io::Precision::simd, lighting);
    ASSERT_EQ(with.color.size(), without.color.size());
    for (size_t i = 0; i < with.color.size(); ++i)
      ASSERT_NEAR(with.color[i], without.color[i], 1e-6f) << i << (lighting == FurLighting::pixel ? " per pixel" : "");
  }
}

// A red map keeps every pixel's red channel (the base's and the strands' red are multiplied by
// 1 either way) and takes green and blue out of the strands' colour, leaving their specular.
TEST(FurColorMap, ARedMapRemovesGreenAndBlueFromTheStrandsOnly) {
  SceneDir dir;
  const std::vector<uint8_t> white = {255, 255, 255}, red = {255, 0, 0};
  const FrameImage a = render(map_scene(dir, white, R"("use_color_map": true)"));
  const FrameImage b = render(map_scene(dir, red, R"("use_color_map": true)"));
  const FrameImage plain = render(map_scene(dir, red, ""));
  ASSERT_EQ(a.color.size(), b.color.size());
  double green_a = 0, green_b = 0, green_plain = 0;
  for (size_t i = 0; i < a.color.size(); i += 4) {
    ASSERT_EQ(a.color[i], b.color[i]) << "red of pixel " << i / 4;
    ASSERT_EQ(a.color[i + 3], b.color[i + 3]) << "alpha of pixel " << i / 4;
    ASSERT_LE(b.color[i + 1], a.color[i + 1]) << "green of pixel " << i / 4;
    green_a += a.color[i + 1];
    green_b += b.color[i + 1];
    green_plain += plain.color[i + 1];
  }
  // The fur covers the base wholly, so most of the frame's green was the strands': measured
  // 0.47 of the white map's, and 0.47 of the red base's under plain fur.
  EXPECT_LT(green_b, 0.7 * green_a);
  EXPECT_LT(green_b, 0.7 * green_plain);
}

TEST(FurColorMap, SameImageOnAnyThreadCountAndCloseToTheDoubleReference) {
  SceneDir dir;
  const io::Scene scene = map_scene(dir, {200, 120, 40}, R"("use_color_map": true)");
  const FrameImage two = render(scene, 2);
  EXPECT_TRUE(same_pixels(render(scene, 1), two));
  EXPECT_TRUE(same_pixels(render(scene, 3), two));
  // The float kernels against the double references (sampling and lighting): measured 8e-9 RMSE.
  EXPECT_LT(image_rmse(render(scene, 2, io::Precision::double_precision).color, two.color), 1e-6);
}

// A 1 x 1 white colour map, and 4 shells with every fin reading the colour map.
raster::Texture white_texel() {
  raster::Texture map;
  const uint8_t texel[4] = {255, 255, 255, 255};
  EXPECT_FALSE(raster::Texture::from_rgba8(1, 1, texel, raster::TexelEncoding::Srgb, map).has_value());
  return map;
}
fur::FurParams colour_fur() {
  fur::FurParams params = small_fur(4, fur::FinMode::all);
  params.use_color_map = true;
  return params;
}

// Every fur vertex's record ends with its base vertex's mesh uv, in each varying layout (grey,
// coloured and per-pixel light) and in the shell and fin arrays alike, also after the light
// turns from grey to coloured and the records are laid out again.
TEST(FurColorMap, EveryLayoutEndsWithTheMeshUv) {
  const raster::Texture map = white_texel();
  const fur::FurParams params = colour_fur();
  for (const FurLighting lighting : {FurLighting::vertex, FurLighting::pixel}) {
    FurDrawOptions options;
    options.color_maps = {{&map, {}}};
    options.lighting = lighting;
    const Mesh base = io::make_builtin_mesh("box:3");
    FrameStats stats;
    FurObject fur(base, params, options, FurOrigin{"rig", ""}, stats);
    FurFrame frame;
    frame.eye = glm::vec3(3.0f, 2.0f, 4.0f);
    frame.clip_from_world = glm::perspective(glm::radians(45.0f), 1.0f, 1.0f, 20.0f) *
                            glm::lookAt(frame.eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    const std::vector<shading::Light> grey = {{shading::Light::Type::Ambient, {0, 0, 0}, {1.0f, 1.0f, 1.0f}}};
    const std::vector<shading::Light> tinted = {{shading::Light::Type::Ambient, {0, 0, 0}, {1.0f, 0.5f, 0.25f}}};
    const fur::FurGeometry& g = fur.geometry();
    ASSERT_EQ(g.mesh_uvs.size(), g.base_vertex_count);
    for (const auto* lights : {&grey, &tinted}) {
      fur.update(frame, *lights, stats);
      std::vector<raster::DrawCall> draws;
      fur.append_draws(draws);
      ASSERT_EQ(draws.size(), 2u);  // shells and fins
      const int expected = lighting == FurLighting::pixel ? FurPixelVaryings::kCount
                           : lights == &grey             ? FurGreyVaryings::kCount
                                                         : FurVaryings::kCount;
      for (const raster::DrawCall& d : draws) {
        ASSERT_EQ(int(d.varying_count), expected + FurMapUv::kCount);
        for (uint32_t i = 0; i < d.vertex_count; ++i) {
          const float* at = d.varyings + size_t{i} * d.varying_count + expected;
          const glm::vec2 uv = g.mesh_uvs[i % g.base_vertex_count];
          ASSERT_EQ(at[0], uv.x) << "vertex " << i;
          ASSERT_EQ(at[1], uv.y) << "vertex " << i;
        }
      }
    }
  }
}

// Faces of several colour maps: each fin quad takes its edge's first face's map, in every order
// of the fin draws (per layer, one quad per edge and pair of layers, in the layer sort; merged
// runs per edge in the tile sort).
TEST(FurColorMap, EachFinQuadTakesItsEdgesFirstFacesMap) {
  const raster::Texture map = white_texel();
  const fur::FurParams params = colour_fur();
  const Mesh base = io::make_builtin_mesh("box:3");
  FurDrawOptions options;
  options.color_maps = {{&map, {}}, {&map, {}}, {&map, {}}};
  for (size_t f = 0; f < base.triangle_count(); ++f) options.face_color_map.push_back(f % 4 == 3 ? kNoFurColorMap : f % 4);
  FrameStats stats;
  FurObject fur(base, params, options, FurOrigin{"rig", ""}, stats);
  const fur::FurGeometry& g = fur.geometry();
  ASSERT_EQ(g.counts.base_faces, base.triangle_count());
  FurFrame frame;
  frame.eye = glm::vec3(3.0f, 2.0f, 4.0f);
  frame.clip_from_world = glm::perspective(glm::radians(45.0f), 1.0f, 1.0f, 20.0f) *
                          glm::lookAt(frame.eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  const std::vector<shading::Light> grey = {{shading::Light::Type::Ambient, {0, 0, 0}, {1.0f, 1.0f, 1.0f}}};
  frame.sort = FurSort::layer;
  fur.update(frame, grey, stats);
  const size_t edges = g.edges.size();
  ASSERT_EQ(fur.fin_quad_maps().size(), edges * (g.layers - 1));
  for (size_t q = 0; q < fur.fin_quad_maps().size(); ++q)
    ASSERT_EQ(fur.fin_quad_maps()[q], options.face_color_map[g.edges[q % edges].face0]) << "quad " << q;
  // The tile sort's runs: each edge's quads one after another, in edge order, one or more each.
  frame.sort = FurSort::tile;
  fur.update(frame, grey, stats);
  std::vector<raster::DrawCall> draws;
  fur.append_draws(draws);
  ASSERT_EQ(draws.size(), 2u);
  const raster::DrawCall& fins = draws[1];
  ASSERT_EQ(fur.fin_quad_maps().size(), size_t{fins.triangle_count} / 2);
  const uint32_t n = g.base_vertex_count;
  for (size_t q = 0; q < fur.fin_quad_maps().size(); ++q) {
    // The quad's root corners are its edge's ends on some layer: find the edge by them.
    const uint32_t* tri = fins.indices + 6 * q;
    std::vector<uint32_t> ends;
    for (int k = 0; k < 6; ++k) ends.push_back(tri[k] % n);
    size_t e = 0;
    for (; e < edges; ++e)
      if (std::all_of(ends.begin(), ends.end(), [&](uint32_t v) { return v == g.edges[e].a || v == g.edges[e].b; }))
        break;
    ASSERT_LT(e, edges) << "quad " << q;
    EXPECT_EQ(fur.fin_quad_maps()[q], options.face_color_map[g.edges[e].face0]) << "quad " << q;
  }
}

// The shader reads the map at the mesh uv slot it is given: a map red on its left half and blue
// on its right colours white strands red at u = 0.25 and blue at u = 0.75, whatever the strand
// uv, under a white unit light with no specular.
TEST(FurColorMap, TheShaderReadsTheMapAtTheMeshUv) {
  raster::Texture map;
  const uint8_t texels[8] = {255, 0, 0, 255, 0, 0, 255, 255};
  ASSERT_FALSE(raster::Texture::from_rgba8(2, 1, texels, raster::TexelEncoding::Srgb, map).has_value());
  raster::TextureArray shells;
  const uint8_t strand[2 * 4 * 4] = {255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255,
                                     255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  ASSERT_FALSE(raster::TextureArray::from_la8_layers(4, 4, 1, strand, shells).has_value());
  const glm::vec3 tint(1.0f);
  FurShaderSetup su;
  su.shells = &shells;
  su.shell_tint = &tint;
  su.base_faces = 1;
  const FurColorMap only{&map, {}};
  su.color_maps = &only;
  su.color_map_count = 1;
  su.sampler.filter = raster::Filter::Nearest;
  su.map_filter = raster::Filter::Nearest;
  FurShader shader(su);
  shader.set_grey_lighting(true);
  shader.set_map_uv_slot(FurGreyVaryings::kCount);

  constexpr int kLanes = 16;
  alignas(64) float strand_u[kLanes], strand_v[kLanes], diffuse[kLanes], specular[kLanes], map_u[kLanes],
      map_v[kLanes], out[4][kLanes];
  alignas(64) uint32_t primitive[kLanes] = {};
  for (int l = 0; l < kLanes; ++l) {
    strand_u[l] = 0.1f * float(l);
    strand_v[l] = 0.5f;
    diffuse[l] = 1.0f;
    specular[l] = 0.0f;
    map_u[l] = l < 8 ? 0.25f : 0.75f;
    map_v[l] = 0.5f;
  }
  const uint16_t mask = 0xFFFF;
  const int32_t zero = 0;
  raster::FragmentBatch b;
  b.blocks = 1;
  b.mask = &mask;
  b.block_x = b.block_y = &zero;
  b.primitive = primitive;
  b.varying[FurGreyVaryings::kUv] = strand_u;
  b.varying[FurGreyVaryings::kUv + 1] = strand_v;
  b.varying[FurGreyVaryings::kDiffuse] = diffuse;
  b.varying[FurGreyVaryings::kSpecular] = specular;
  b.varying[FurGreyVaryings::kCount] = map_u;
  b.varying[FurGreyVaryings::kCount + 1] = map_v;
  for (int c = 0; c < 4; ++c) b.out[c] = out[c];
  shader.shade(b);
  for (int l = 0; l < kLanes; ++l) {
    const bool red = l < 8;
    EXPECT_FLOAT_EQ(out[0][l], red ? 1.0f : 0.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[1][l], 0.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[2][l], red ? 0.0f : 1.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[3][l], 1.0f) << "lane " << l;
  }
  // Where the mesh file places the map (MapPlacement) holds for the fur as for the surface:
  // u' = 1 - u swaps the halves.
  FurColorMap flipped{&map, {}};
  flipped.placement.m = {-1.0f, 0.0f, 1.0f, 0.0f, 1.0f, 0.0f};
  su.color_maps = &flipped;
  FurShader placed(su);
  placed.set_grey_lighting(true);
  placed.set_map_uv_slot(FurGreyVaryings::kCount);
  placed.shade(b);
  for (int l = 0; l < kLanes; ++l) {
    EXPECT_FLOAT_EQ(out[0][l], l < 8 ? 0.0f : 1.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[2][l], l < 8 ? 1.0f : 0.0f) << "lane " << l;
  }

  // Several maps, per face: of two base faces (layer 1's primitives 2 and 3), face 0 takes map 1
  // (green) and face 1 none (white), whichever half of the red-blue map its lanes lie on; one
  // block holds both faces. A fin quad takes its own map (set_fin_maps): quads 0 and 1 (primitives
  // 0-1 and 2-3), maps 0 (the red-blue map, at the lanes' u) and 1.
  raster::Texture green;
  const uint8_t green_texel[4] = {0, 255, 0, 255};
  ASSERT_FALSE(raster::Texture::from_rgba8(1, 1, green_texel, raster::TexelEncoding::Srgb, green).has_value());
  const FurColorMap maps[2] = {{&map, {}}, {&green, {}}};
  const uint32_t face_map[2] = {1, kNoFurColorMap};
  su.base_faces = 2;
  su.color_maps = maps;
  su.color_map_count = 2;
  su.face_color_map = face_map;
  FurShader per_face(su);
  per_face.set_grey_lighting(true);
  per_face.set_map_uv_slot(FurGreyVaryings::kCount);
  for (int l = 0; l < kLanes; ++l) primitive[l] = l % 4 < 2 ? 2 : 3;
  per_face.shade(b);
  for (int l = 0; l < kLanes; ++l) {
    const bool face0 = l % 4 < 2;
    EXPECT_FLOAT_EQ(out[0][l], face0 ? 0.0f : 1.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[1][l], 1.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[2][l], face0 ? 0.0f : 1.0f) << "lane " << l;
  }
  raster::Texture fin;
  const uint8_t fin_texels[2 * 2] = {255, 255, 255, 255};
  ASSERT_FALSE(raster::Texture::from_la8(2, 1, fin_texels, fin).has_value());
  FurShaderSetup fu = su;
  fu.fins = true;
  fu.fin = &fin;
  fu.fin_tint_root = glm::vec3(1.0f);
  fu.face_color_map = face_map;  // any: the fins take their quads' maps
  FurShader fins(fu);
  fins.set_grey_lighting(true);
  fins.set_map_uv_slot(FurGreyVaryings::kCount);
  const uint32_t quad_map[2] = {0, 1};
  fins.set_fin_maps(quad_map);
  for (int l = 0; l < kLanes; ++l) primitive[l] = l % 4 < 2 ? 1 : 2;  // quads 0 and 1
  fins.shade(b);
  for (int l = 0; l < kLanes; ++l) {
    const bool quad0 = l % 4 < 2, red = l < 8;
    EXPECT_FLOAT_EQ(out[0][l], quad0 && red ? 1.0f : 0.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[1][l], quad0 ? 0.0f : 1.0f) << "lane " << l;
    EXPECT_FLOAT_EQ(out[2][l], quad0 && !red ? 1.0f : 0.0f) << "lane " << l;
  }
}

TEST(FurColorMap, AnObjectWithoutAColourMapIsRefusedNamingTheField) {
  const io::Scene scene = io::parse_scene(furry_box_scene(R"("use_color_map": true)"), "fur_map.json");
  try {
    render(scene);
    FAIL() << "rendered";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file, "fur_map.json");
    EXPECT_EQ(e.field, "objects[0].fur.use_color_map");
    EXPECT_NE(e.reason.find("colour map"), std::string::npos) << e.reason;
  }
}

TEST(FurColorMap, TheFieldTakesOnlyABoolean) {
  try {
    io::parse_scene(furry_box_scene(R"("use_color_map": 1)"), "fur_map.json");
    FAIL() << "parsed";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "objects[0].fur.use_color_map");
  }
  EXPECT_TRUE(io::parse_scene(furry_box_scene(R"("use_color_map": false)"), "f.json").objects[0].fur->use_color_map ==
              false);
}

}  // namespace fur_color_map_test
}  // namespace pelt::render::test
