// The price of each translucent sort mode: error of `none`, `layer` and `tile` against
// the exact per-pixel sort on a furry box, bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/frame.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/scene.h"
#include "tools/render/fur_object.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {
namespace {

std::vector<float> render_sorted(const io::Scene& scene, io::SortQuality sort) {
  io::Quality q;
  q.sort = sort;
  return render_at(scene, q).color;
}

TEST(FurSort, EveryModeStaysCloseToTheExactPerPixelSort) {
  const io::Scene scene = io::parse_scene(furry_box_scene(R"("fins": "all", "gravity": {})"), "t.json");
  const std::vector<float> exact = render_sorted(scene, io::SortQuality::exact);
  EXPECT_EQ(image_rmse(exact, render_sorted(scene, io::SortQuality::exact)), 0.0);
  const double none = image_rmse(render_sorted(scene, io::SortQuality::none), exact);
  const double layer = image_rmse(render_sorted(scene, io::SortQuality::layer), exact);
  const double tile = image_rmse(render_sorted(scene, io::SortQuality::tile), exact);
  const double surface = image_rmse(render_sorted(scene, io::SortQuality::surface), exact);
  std::printf("fur sort RMSE vs exact: none %.5f, layer %.5f, tile %.5f, surface %.5f\n", none, layer, tile, surface);
  // Measured on this scene (none 0.023, layer 0.0029, tile 0.0024, surface 0.0022, 0.0034 before
  // culled shells stopped holding others back; tile was
  // 0.004 before a quad's two halves sorted as one, and fins keyed in runs of three quads left
  // it there), bounded with headroom.
  EXPECT_LT(none, 0.04);
  EXPECT_LT(layer, 0.005);
  EXPECT_LT(tile, 0.005);
  EXPECT_LT(surface, 0.005);
  EXPECT_LT(layer, none);
  EXPECT_GT(none, 0.0);  // fins over shells really are out of order somewhere
}

// Where the strands lean far across quad edges, the tile order keys each quad by its own mean
// depth and draws some inner layers over a neighbour's outer ones (dark seams); the surface
// order keeps each layer after the layers below it that it leans over.
TEST(FurSort, TheSurfaceOrderRemovesTheSeamsOfFurLeaningFar) {
  for (const char* wind : {R"("wind": {"direction": [1, 0, 0.3], "strength": 3.0})",
                           R"("wind": {"direction": [-0.4, 0.2, 1], "strength": 2.0})",
                           R"("gravity": {"strength": 1.0, "stability": 50})"}) {
    // No animation block: a still, drawn at the wind's pose.
    std::string json = furry_box_scene(std::string(R"("fins": "all", )") + wind);
    const size_t anim = json.find(R"("animation")");
    json.erase(anim, json.find('}', anim) + 2 - anim);
    const io::Scene scene = io::parse_scene(json, "t.json");
    const std::vector<float> exact = render_sorted(scene, io::SortQuality::exact);
    const double tile = image_rmse(render_sorted(scene, io::SortQuality::tile), exact);
    const double surface = image_rmse(render_sorted(scene, io::SortQuality::surface), exact);
    const double layer = image_rmse(render_sorted(scene, io::SortQuality::layer), exact);
    std::printf("%s: RMSE vs exact: tile %.5f, surface %.5f, layer %.5f\n", wind, tile, surface, layer);
    // Measured: tile 0.0166, 0.0102, 0.0151; surface 0.0083, 0.0046, 0.0066 (layer 0.0044,
    // 0.0043, 0.0094: on one closed surface drawing layer by layer is nearly exact, but it
    // draws parts of a mesh in front of others layer by layer together).
    EXPECT_LT(surface, 0.6 * tile);
    EXPECT_LT(surface, 0.01);
  }
}

// A mesh of several parts with folds (the teapot: the lid inside the rim, the lip of the rim, the
// spout through the body), under full wind. The keys of shells culled as facing away used to pass
// the surface order's chain from the hidden side of a fold to the visible one, pulling fur in
// front of parts that lie before it: 1.79x the tile order's error here (0.00331 against 0.00185),
// 1.14x since (0.00210). What is left is where the spout goes through the body, two parts at one
// depth, which no per-triangle key separates.
TEST(FurSort, TheSurfaceOrderStaysNearTheTileOrderOnTheTeapot) {
  const io::Scene scene = io::parse_scene(R"({"pelt": 1,
  "image": {"width": 256, "height": 192},
  "camera": {"eye": [3.94, 2.54, 5.75], "target": [0, 0, 0], "fovy_deg": 45, "near": 3.0, "far": 12.0},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5], "intensity": 0.65},
             {"type": "ambient", "intensity": 0.35}],
  "objects": [{"mesh": "teapot:5", "material": {"type": "lambert", "color": [0.8, 0.58, 0.36]},
               "fur": {"shells": 16, "length": 0.1, "density": 30, "texture_size": 128, "fins": "silhouette",
                       "gravity": {"strength": 1.0}, "wind": {"direction": [1, 0.2, 0.6], "strength": 1.0}}}]})",
                                          "t.json");
  const std::vector<float> exact = render_sorted(scene, io::SortQuality::exact);
  const double tile = image_rmse(render_sorted(scene, io::SortQuality::tile), exact);
  const double surface = image_rmse(render_sorted(scene, io::SortQuality::surface), exact);
  std::printf("teapot: RMSE vs exact: tile %.5f, surface %.5f\n", tile, surface);
  EXPECT_LT(surface, 1.3 * tile);
}

// The default `fin_quads: merged`: in the sorts that merge (tile, surface, exact) a fin's quads
// span several layers where its chains run straight (fewer triangles than eq. 1's one quad per
// pair of layers) and each merged quad is keyed alone; `none` draws eq. 1's quads, alone too.
TEST(FurSort, MergedFinQuadsAreKeyedAlone) {
  const fur::FurParams params = small_fur(16, fur::FinMode::all);
  FurDrawOptions merge;
  merge.merge_fins = true;
  FurRig rig("box:3", params, "merged", merge);
  const uint32_t layer_triangles = rig.draws(FurSort::none)[1].triangle_count;
  for (FurSort sort : {FurSort::tile, FurSort::surface, FurSort::exact, FurSort::none}) {
    const std::vector<raster::DrawCall> draws = rig.draws(sort);
    ASSERT_EQ(draws.size(), 2u);  // shells, then fins
    EXPECT_EQ(draws[1].sort_group, 2u) << int(sort);
    if (sort == FurSort::none) {
      EXPECT_EQ(draws[1].triangle_count, layer_triangles);
    } else {
      EXPECT_LT(draws[1].triangle_count, layer_triangles * 4 / 5) << int(sort);
    }
  }
}

// With `fin_quads: layer`, the fin list per sort mode: the paper's (and the harness's)
// layer-then-edge order for `none` and `layer`; for `tile` and `exact` fin by fin, root to tip,
// every triangle sharing an edge with the one before it within a fin, and the tile sort keys runs
// of three quads.
TEST(FurSort, TileAndExactDrawEachFinAsAStripKeyedInRunsOfThreeQuads) {
  const fur::FurParams params = small_fur(16, fur::FinMode::all);
  FurRig rig("box:3", params, "strips");
  const uint32_t quads_per_fin = params.shells - 1;
  for (FurSort sort : {FurSort::none, FurSort::tile, FurSort::exact, FurSort::none}) {
    const std::vector<raster::DrawCall> draws = rig.draws(sort);
    ASSERT_EQ(draws.size(), 2u);  // shells, then fins
    const raster::DrawCall& fins = draws[1];
    ASSERT_EQ(fins.triangle_count % (2 * quads_per_fin), 0u);
    const uint32_t edges = fins.triangle_count / (2 * quads_per_fin);
    const bool strips = sort != FurSort::none;
    EXPECT_EQ(fins.sort_group, strips ? 6u : 2u) << int(sort);
    // Layer of a fin triangle: its lowest vertex's layer.
    auto layer = [&](uint32_t t) {
      const uint32_t* v = fins.indices + 3 * size_t{t};
      return std::min({v[0], v[1], v[2]}) / uint32_t(rig.base.positions.size());
    };
    for (uint32_t t = 0; t < fins.triangle_count; ++t) {
      const uint32_t quad = t / 2;
      const uint32_t want = strips ? quad % quads_per_fin : quad / edges;
      ASSERT_EQ(layer(t), want) << int(sort) << " triangle " << t;
      if (strips && quad % quads_per_fin + t % 2 > 0) {
        ASSERT_TRUE(raster::triangles_share_edge(fins.indices + 3 * size_t{t - 1}, fins.indices + 3 * size_t{t}))
            << int(sort) << " triangle " << t;
      }
    }
  }
}

}  // namespace
}  // namespace pelt::render::test
