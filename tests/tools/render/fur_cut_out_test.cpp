// Fur on a surface that its mesh file cuts out (glTF alphaMode MASK) grows only where the surface
// is kept: a strand rooted in a hole is not drawn, shells and fins alike (FurCutMap). Until
// 2026-11-28 the fur grew over the holes, floating over nothing.
#include <gtest/gtest.h>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tests/tools/render/two_quads_gltf.h"
#include "tools/io/image_io.h"

namespace pelt::render::test {
namespace fur_cut_out_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// front.png: 4 x 4 green texels, alpha 0 in the left half (u < 0.5) and 1 in the right, or 0
// everywhere.
void write_front(const SceneDir& dir, bool all_cut) {
  std::vector<uint8_t> px;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) px.insert(px.end(), {0, 255, 0, uint8_t(all_cut || x < 2 ? 0 : 255)});
  io::write_image_atomic(dir.path() / "front.png", 4, 4, 4, io::PixelType::u8, px.data());
}

const std::string kFrontMask = R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
// The back quad cut away whole by its factor's alpha (no map: MaterialShader's alpha is the factor).
const std::string kBackGone = R"({"name":"back","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0]}})";

// The two quads of two_quads_gltf.h with `back` as material 0, furry, seen from the front in a
// black frame. The maps are read trilinear (render_at's default quality): the cut's edge is blurred
// over a texel's width either side of u = 0.5, cut where the alpha is under 0.5.
io::Scene furry_quads(const SceneDir& dir, const std::string& back, bool back_uvs = true,
                      const std::string& fur_extra = "") {
  std::string gltf = two_quads_gltf(kFrontMask, back_uvs);
  const std::string from = R"("materials":[{"name":"back"},)";
  gltf.replace(gltf.find(from), from.size(), R"("materials":[)" + back + ",");
  dir.write("quads.gltf", gltf);
  return front_view_scene(dir, "quads.gltf", R"({"type": "lambert"})",
                          R"(, "fur": {"shells": 6, "texture_size": 32, "density": 30, "fins": "all",
                                       "root_color": [1, 0.2, 0.2], "tip_color": [1, 0.6, 0.6])" +
                              fur_extra + "}");
}

const float* pixel(const FrameImage& img, int x, int y) { return &img.color[(size_t(y) * 64 + size_t(x)) * 4]; }
bool black(const float* p) { return p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f; }

// Pixels of the front quad (columns 10-54 on screen, its left half u < 0.5 left of 32) that are
// not black, in its left half away from the cut's edge, and in its right half.
struct Lit {
  int left = 0, right = 0;
};
Lit lit(const FrameImage& img) {
  Lit l;
  for (int y = 14; y < 50; ++y) {
    for (int x = 13; x < 28; ++x) l.left += !black(pixel(img, x, y));
    for (int x = 37; x < 52; ++x) l.right += !black(pixel(img, x, y));
  }
  return l;
}

// The front quad's left half cut, the back quad gone (a cut per part) or cut alike (one material:
// one cut-out for the whole mesh): nothing is drawn over the left half (the surface, its shells
// and the fins of its diagonal edge cut alike), while the right half keeps its surface and fur.
// Per-vertex and per-pixel lighting, one and two threads.
TEST(FurCutOut, NoStrandGrowsInAHole) {
  SceneDir dir;
  write_front(dir, false);
  for (const bool per_part : {true, false}) {
    const io::Scene s = furry_quads(dir, per_part ? kBackGone : R"({"name":"back",)" + kFrontMask.substr(1));
    for (const FurLighting lighting : {FurLighting::vertex, FurLighting::pixel}) {
      const FrameImage one = render_at(s, {}, 1, lighting), two = render_at(s, {}, 2, lighting);
      const Lit l = lit(two);
      EXPECT_EQ(l.left, 0) << per_part << " " << int(lighting);
      EXPECT_EQ(l.right, 15 * 36) << per_part << " " << int(lighting);
      EXPECT_TRUE(same_pixels(one, two)) << per_part << " " << int(lighting);
    }
  }
}

// The fur is there to be cut: the same scene without the MASK (the front quad opaque) draws fur
// over the left half, redder than the green surface under it.
TEST(FurCutOut, TheFurIsDrawnWhereNothingIsCut) {
  SceneDir dir;
  write_front(dir, false);
  std::string gltf = two_quads_gltf(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})");
  dir.write("quads.gltf", gltf);
  const io::Scene bare = front_view_scene(dir, "quads.gltf", R"({"type": "lambert"})");
  const io::Scene furry = front_view_scene(dir, "quads.gltf", R"({"type": "lambert"})",
                                           R"(, "fur": {"shells": 6, "texture_size": 32, "density": 30,
                                                        "root_color": [1, 0.2, 0.2], "tip_color": [1, 0.6, 0.6]})");
  const FrameImage a = render_at(bare, {}), b = render_at(furry, {});
  int redder = 0;
  for (int y = 14; y < 50; ++y)
    for (int x = 13; x < 28; ++x) redder += pixel(b, x, y)[0] > pixel(a, x, y)[0] + 0.05f;
  EXPECT_GT(redder, 100);
}

// Every face cut away, by one cut-out for the whole mesh (both quads in one material: one part,
// no per-face list) or by one per part (the back by its factor, the front by its map): the frame
// is black from the front and from an oblique view where the fins of the quads' edges stand in
// sight (cut by their edge's face's part), under every sort (the layer and none orders index the
// fins per layer) and both lightings.
TEST(FurCutOut, AMeshCutAwayWholeGrowsNoFur) {
  SceneDir dir;
  write_front(dir, true);
  for (const bool per_part : {false, true}) {
    io::Scene s = furry_quads(dir, per_part ? kBackGone : R"({"name":"back",)" + kFrontMask.substr(1));
    ASSERT_EQ(SceneRenderer(s, RenderSettings{}).maps_drawn(0).size(), per_part ? 2u : 1u);
    for (const glm::vec3 eye : {glm::vec3(0.0f, 0.0f, 4.0f), glm::vec3(3.0f, 1.2f, 2.4f)}) {
      s.camera.eye = eye;
      for (const io::SortQuality sort : {io::SortQuality::tile, io::SortQuality::layer, io::SortQuality::none,
                                         io::SortQuality::surface, io::SortQuality::exact})
        for (const FurLighting lighting : {FurLighting::vertex, FurLighting::pixel}) {
          io::Quality q;
          q.sort = sort;
          const FrameImage img = render_at(s, q, 2, lighting);
          int lit = 0;
          for (size_t p = 0; p + 3 < img.color.size(); p += 4) lit += !black(&img.color[p]);
          EXPECT_EQ(lit, 0) << "per part " << per_part << ", eye x " << eye.x << ", sort " << int(sort)
                            << ", lighting " << int(lighting);
        }
    }
  }
}

// Faces cut away whole are not drawn at all, where their shells and fins used to be rasterized,
// shaded and zeroed: outside the front quad, where only the back quad (gone) lies, no translucent
// fragment passes the depth test under any sort (the overdraw AOV), while the front quad's kept
// half has its fur. Its left half, cut by its map, still blends zeroed fragments: that cut is
// per texel.
TEST(FurCutOut, APartCutAwayWholeIsNotRasterized) {
  SceneDir dir;
  write_front(dir, false);
  const io::Scene s = furry_quads(dir, kBackGone);
  for (const io::SortQuality sort : {io::SortQuality::tile, io::SortQuality::layer, io::SortQuality::none,
                                     io::SortQuality::surface, io::SortQuality::exact}) {
    RenderSettings rs;
    io::Quality q;
    q.sort = sort;
    rs.quality = q;
    rs.aov = Aov::overdraw;
    SceneRenderer r(s, rs);
    FrameImage img;
    FrameStats st;
    r.render(0, img, st);
    ASSERT_EQ(img.overdraw.size(), 64u * 64u);
    uint32_t outside = 0, kept = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const uint32_t n = img.overdraw[size_t(y) * 64 + size_t(x)];
        if (x < 8 || x > 56 || y < 8 || y > 56) outside += n;
        if (x >= 37 && x < 52 && y >= 14 && y < 50) kept += n > 0;
      }
    EXPECT_EQ(outside, 0u) << "sort " << int(sort);
    EXPECT_EQ(kept, 15u * 36u) << "sort " << int(sort);
  }
}

// The draws of a fur whose every third face a cut-out without a map cuts away (its factor 0):
// those faces' shells are single points in every layer, and the fins of the edges whose first
// face they are are not listed, in every order (per-layer and root-to-tip fin lists, quads
// merged or not); the other faces and edges keep all of theirs.
TEST(FurCutOut, TheDrawsHoldNothingOfTheFacesCutAway) {
  for (const bool merge : {false, true}) {
    FurDrawOptions options;
    options.merge_fins = merge;
    options.cut_maps = {FurCutMap{{}, 0.0f, 0.5f}};
    const Mesh box = io::make_builtin_mesh("box:3");
    for (uint32_t f = 0; f < box.triangle_count(); ++f) options.face_cut_map.push_back(f % 3 == 0 ? 0u : kNoFurCut);
    FurRig rig("box:3", small_fur(5, fur::FinMode::all), "box", options);
    const fur::FurGeometry& g = rig.fur.geometry();
    const uint32_t faces = box.triangle_count(), n = g.base_vertex_count;
    std::vector<std::pair<uint32_t, uint32_t>> kept_edges;
    for (const fur::FurEdge& e : g.edges)
      if (e.face0 % 3 != 0) kept_edges.push_back(std::minmax(e.a % n, e.b % n));
    std::sort(kept_edges.begin(), kept_edges.end());
    for (const FurSort sort : {FurSort::tile, FurSort::layer, FurSort::none, FurSort::exact}) {
      size_t shells = 0, fin_triangles = 0;
      std::vector<std::pair<uint32_t, uint32_t>> fin_edges;
      for (const raster::DrawCall& d : rig.draws(sort)) {
        const bool fin = d.indices < g.shell_indices.data() || d.indices >= g.shell_indices.data() + g.shell_indices.size();
        for (uint32_t t = 0; t < d.triangle_count; ++t) {
          const uint32_t* i = d.indices + 3 * size_t{t};
          if (!fin) {
            const size_t face = size_t(i - g.shell_indices.data()) / 3 % faces;
            const bool point = i[0] == i[1] && i[1] == i[2];
            EXPECT_EQ(point, face % 3 == 0) << "face " << face;
            shells += !point;
            continue;
          }
          ++fin_triangles;
          // A fin triangle's corners lie on two chains: its edge's ends.
          uint32_t a = i[0] % n, b = a;
          for (int k = 1; k < 3; ++k)
            if (i[k] % n != a) b = i[k] % n;
          fin_edges.push_back(std::minmax(a, b));
        }
      }
      EXPECT_EQ(shells, size_t{faces - (faces + 2) / 3} * 5) << int(sort);
      std::sort(fin_edges.begin(), fin_edges.end());
      fin_edges.erase(std::unique(fin_edges.begin(), fin_edges.end()), fin_edges.end());
      EXPECT_EQ(fin_edges, kept_edges) << int(sort) << " merge " << merge;
      if (!merge || sort == FurSort::layer || sort == FurSort::none) {  // per-layer quads: 4 a fin
        EXPECT_EQ(fin_triangles, kept_edges.size() * 4 * 2) << int(sort);
      }
    }
  }
}

// A mesh whose every face is cut away makes nothing for its fur, on its first frame or any
// other: no strand textures, pose, light, wind or fin list, and no fragment; the same mesh with
// half of one quad kept makes them all.
TEST(FurCutOut, AMeshCutAwayWholeMakesNothingForItsFur) {
  for (const bool all_cut : {true, false}) {
    SceneDir dir;
    write_front(dir, all_cut);
    io::Scene s = furry_quads(dir, kBackGone, true, R"(, "wind": {"direction": [1, 0, 0], "strength": 1})");
    s.animation.emplace().frames = 3;  // the wind swings: every frame makes a pose
    SceneRenderer r(s, RenderSettings{});
    const char* const stages[] = {"fur_textures", "wind", "fur_pose", "fur_lighting", "fins"};
    bool ran[std::size(stages)] = {};
    for (int frame : {0, 1, 2}) {
      FrameImage img;
      FrameStats st;
      r.render(frame, img, st);
      for (size_t k = 0; k < std::size(stages); ++k) ran[k] |= st.stage(stages[k]).ran;
      EXPECT_EQ(st.raster.fragments_blended == 0, all_cut) << "frame " << frame;
    }
    for (size_t k = 0; k < std::size(stages); ++k) EXPECT_EQ(ran[k], !all_cut) << stages[k];
  }
}

// A mesh cut away whole keeps its geometry (counts, `pelt info`) and nothing per frame: no pose,
// tangents, light or varyings, which FurObject::memory_bytes (the renderer's memory estimate)
// would count at some 200 bytes a fur vertex (207 here before it kept none). Textures off in
// both, so the strand textures (never made for it) do not hide the difference; the object
// without a cut-out keeps them all.
TEST(FurCutOut, AMeshCutAwayWholeKeepsNoFrameBuffers) {
  FurDrawOptions cut;
  cut.textures = false;
  cut.cut_maps = {FurCutMap{{}, 0.0f, 0.5f}};
  FurDrawOptions uncut;
  uncut.textures = false;
  FurRig gone("box:3", small_fur(5, fur::FinMode::all), "box", cut);
  FurRig kept("box:3", small_fur(5, fur::FinMode::all), "box", uncut);
  auto geometry_bytes = [](const fur::FurGeometry& g) {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    return bytes(g.positions) + bytes(g.shell_uvs) + bytes(g.fin_uvs) + bytes(g.layer) + bytes(g.shell_indices) +
           bytes(g.fin_indices) + bytes(g.edges) + bytes(g.mesh_uvs) + bytes(g.length_scale);
  };
  const size_t vertices = gone.fur.geometry().positions.size();
  ASSERT_EQ(vertices, kept.fur.geometry().positions.size());
  ASSERT_EQ(geometry_bytes(gone.fur.geometry()), geometry_bytes(kept.fur.geometry()));
  const size_t gone_extra = gone.fur.memory_bytes() - geometry_bytes(gone.fur.geometry());
  const size_t kept_extra = kept.fur.memory_bytes() - geometry_bytes(kept.fur.geometry());
  EXPECT_LT(gone_extra, vertices) << "bytes beside the geometry: under one a fur vertex";
  EXPECT_GT(kept_extra, 100 * vertices);
  EXPECT_TRUE(gone.draws(FurSort::tile).empty());
}

// The layer order hands each layer's fin shader its own stretch of the fin list, and of each fin's
// cut with it (FurObject::set_view): a fin of layer s must read its own quad's cut, not that of
// another layer's or edge's. With the quads' parts cut unlike (the back gone, the front's left half
// cut), from far enough and oblique that both quads and their fins are in sight, every order draws
// fur over the same pixels (blending order changes a colour, never whether a strand is there); the
// per-tile and exact orders index the whole list at once. (An offset one quad off in the layer
// order drew 7 pixels more.)
TEST(FurCutOut, EveryOrderCutsTheSameFins) {
  SceneDir dir;
  write_front(dir, false);
  io::Scene s = furry_quads(dir, kBackGone);
  s.camera.eye = glm::vec3(6.0f, 2.4f, 4.8f);
  const auto covered = [&](io::SortQuality sort, fur::FinMode fins) {
    io::Quality q;
    q.sort = sort;
    q.fins = fins;
    const FrameImage img = render_at(s, q);
    std::vector<bool> mask;
    for (size_t p = 0; p + 3 < img.color.size(); p += 4) mask.push_back(!black(&img.color[p]));
    return mask;
  };
  const auto count = [](const std::vector<bool>& m) { return std::count(m.begin(), m.end(), true); };
  const std::vector<bool> tile = covered(io::SortQuality::tile, fur::FinMode::all);
  ASSERT_GT(count(tile), count(covered(io::SortQuality::tile, fur::FinMode::off)) + 30);  // fins in sight
  for (const io::SortQuality sort : {io::SortQuality::layer, io::SortQuality::none, io::SortQuality::exact}) {
    const std::vector<bool> other = covered(sort, fur::FinMode::all);
    EXPECT_TRUE(other == tile) << "sort " << int(sort) << ": " << count(other) << " pixels, tile " << count(tile);
  }
}

// A MASK whose map's alphas all reach the cutoff (exporters mark opaque textures MASK) cuts nothing:
// the fur reads no map for it, so the renderer holds what it holds for the mesh OPAQUE (no alpha
// copy, no mesh uvs per fur vertex) and draws the same bytes, and the surface is drawn opaque,
// each pixel shaded once (an alpha-tested draw shades its pixels twice).
TEST(FurCutOut, AMaskThatCutsNothingCostsTheFurNothing) {
  SceneDir dir;
  std::vector<uint8_t> px;
  for (int k = 0; k < 16; ++k) px.insert(px.end(), {0, 255, 0, uint8_t(200 + k)});
  io::write_image_atomic(dir.path() / "front.png", 4, 4, 4, io::PixelType::u8, px.data());
  const std::string map = R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0}})";
  const auto scene = [&](const std::string& name, const std::string& front) {
    dir.write(name, two_quads_gltf(front));
    return front_view_scene(dir, name, R"({"type": "lambert"})",
                            R"(, "fur": {"shells": 6, "texture_size": 32, "density": 30, "fins": "all"})");
  };
  const io::Scene mask = scene("mask.gltf", R"({"alphaMode":"MASK",)" + map + "}");
  const io::Scene opaque = scene("opaque.gltf", "{" + map + "}");
  EXPECT_EQ(SceneRenderer(mask, RenderSettings{}).memory_estimate(),
            SceneRenderer(opaque, RenderSettings{}).memory_estimate());
  EXPECT_TRUE(same_pixels(render_at(mask, {}), render_at(opaque, {})));
  const auto shaded = [](const io::Scene& s) {
    SceneRenderer r(s, RenderSettings{});
    FrameImage img;
    FrameStats st;
    r.render(0, img, st);
    return st.raster.lanes_shaded;
  };
  EXPECT_EQ(shaded(mask), shaded(opaque));
}

// A mesh some of whose faces have no uvs lays its strands by the box mapping, the uvs set aside;
// the cut-out is still read at them.
TEST(FurCutOut, FacesWithoutUvsBesideDoNotLoseTheCut) {
  SceneDir dir;
  write_front(dir, false);
  const io::Scene s = furry_quads(dir, kBackGone, false);
  const Lit l = lit(render_at(s, {}));
  EXPECT_EQ(l.left, 0);
  EXPECT_EQ(l.right, 15 * 36);
}

// The cut follows the surface's own test: with alphaCutoff 0 nothing is cut (alpha 0 reaches 0),
// so the left half's green surface has red fur over it again.
TEST(FurCutOut, TheCutoffDecidesForTheFurToo) {
  SceneDir dir;
  write_front(dir, false);
  std::string gltf = two_quads_gltf(R"({"alphaMode":"MASK","alphaCutoff":0,)"
                                    R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})");
  const std::string from = R"("materials":[{"name":"back"},)";
  gltf.replace(gltf.find(from), from.size(), R"("materials":[)" + kBackGone + ",");
  dir.write("quads.gltf", gltf);
  const io::Scene s = front_view_scene(dir, "quads.gltf", R"({"type": "lambert"})",
                                       R"(, "fur": {"shells": 6, "texture_size": 32, "density": 30, "fins": "all",
                                                    "root_color": [1, 0, 0], "tip_color": [1, 0, 0]})");
  const FrameImage img = render_at(s, {});
  int red = 0;
  for (int y = 14; y < 50; ++y)
    for (int x = 13; x < 28; ++x) red += pixel(img, x, y)[0] > 0.05f;
  EXPECT_GT(red, 15 * 36 * 9 / 10);  // every strand kept: under half were with the cutoff read as exclusive
}

}  // namespace fur_cut_out_test
}  // namespace pelt::render::test
