// The price of each translucent sort mode: error of `none`, `layer` and `tile` against
// the exact per-pixel sort on a furry box, bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/scene.h"
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
  std::printf("fur sort RMSE vs exact: none %.5f, layer %.5f, tile %.5f\n", none, layer, tile);
  // Measured on this scene (none 0.022, layer 0.0006, tile 0.0023; tile was 0.004 before a
  // quad's two halves sorted as one), bounded with headroom: drawing each layer's fins right
  // after its shell is nearly exact here.
  EXPECT_LT(none, 0.04);
  EXPECT_LT(layer, 0.005);
  EXPECT_LT(tile, 0.005);
  EXPECT_LT(layer, none);
  EXPECT_GT(none, 0.0);  // fins over shells really are out of order somewhere
}

}  // namespace
}  // namespace pelt::render::test
