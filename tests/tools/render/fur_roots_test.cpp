// Shell 0 lies on the base mesh and is depth-tested less-equal against it, so its vertices
// must be the base's bit for bit in every pose the animation lerps, or its fragments fail the
// test wherever rounding puts them an ulp behind the base (stripes of missing roots).
#include <gtest/gtest.h>

#include <vector>

#include "tests/tools/render/render_test_scenes.h"

namespace pelt::render::test {
namespace {

TEST(FurRoots, ShellZeroStaysOnTheBaseInEveryAnimatedPose) {
  const fur::FurParams params = small_fur(8, fur::FinMode::off);
  FurRig rig("box:3", params, "roots");
  rig.frame.gravity = fur::GravityParams{};
  fur::WindParams wind;
  wind.direction = glm::vec3(1.0f, 0.2f, 0.6f);
  rig.frame.wind = wind;
  const std::vector<glm::vec3>& base = rig.base.positions;
  const size_t n = base.size();
  const size_t tip = n * (params.shells - 1);  // vertex 0's tip
  glm::vec3 tip0(0.0f);
  bool moved = false;
  for (int frame = 0; frame < 48; ++frame) {
    rig.frame.frame = frame;
    rig.frame.time_seconds = frame / 24.0;
    const std::vector<raster::DrawCall> draws = rig.draws(FurSort::tile);
    ASSERT_EQ(draws.size(), 1u);  // the shells
    const raster::DrawCall& shells = draws[0];
    ASSERT_EQ(shells.vertex_count, n * params.shells);
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(shells.positions[i].x, base[i].x) << "frame " << frame << " vertex " << i;
      ASSERT_EQ(shells.positions[i].y, base[i].y) << "frame " << frame << " vertex " << i;
      ASSERT_EQ(shells.positions[i].z, base[i].z) << "frame " << frame << " vertex " << i;
    }
    if (frame == 0) tip0 = shells.positions[tip];
    moved |= shells.positions[tip] != tip0;  // the poses really are lerped
  }
  EXPECT_TRUE(moved);
}

}  // namespace
}  // namespace pelt::render::test
