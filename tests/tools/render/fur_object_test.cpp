// FurObject's bookkeeping: which stages a frame reports, when a frame is re-simulated, and how
// a bad fur block is reported.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/input_error.h"

namespace pelt::render::test {
namespace {

// Brings `rig` up to date for its frame under fresh stats, draws in `sort`, returns the stats.
FrameStats run_frame(FurRig& rig, FurSort sort, std::vector<raster::DrawCall>* draws = nullptr) {
  FrameStats stats;
  rig.frame.sort = sort;
  rig.fur.update(rig.frame, rig.lights, stats);
  std::vector<raster::DrawCall> d;
  rig.fur.append_draws(d);
  if (draws) *draws = d;
  return stats;
}

// `fins: all` builds its fin list once, and again whenever merged fins follow a moving pose or
// the sort wants the other layout: every such rebuild is the frame's "fins" stage, with its
// time (it used to be done untimed, and --stats said the stage had not run).
TEST(FurObjectStats, EveryFinListRebuildIsTheFinsStage) {
  const Mesh base = io::make_builtin_mesh("box:3");
  FurRig rig("box:3", small_fur(8, fur::FinMode::all), "box");
  FurDrawOptions merged;
  merged.merge_fins = true;
  FrameStats setup;
  FurObject fur(base, small_fur(8, fur::FinMode::all), merged, FurOrigin{"s.json", "objects[0]"}, setup);
  FurFrame frame = rig.frame;
  auto run = [&](FurSort sort) {
    FrameStats stats;
    frame.sort = sort;
    fur.update(frame, rig.lights, stats);
    std::vector<raster::DrawCall> d;
    fur.append_draws(d);
    return stats.stage("fins");
  };
  EXPECT_TRUE(run(FurSort::tile).ran);  // the first list
  EXPECT_FALSE(run(FurSort::tile).ran);  // nothing changed
  frame.gravity = fur::GravityParams{};  // the pose moves: the merged fins with it
  const StageRecord moved = run(FurSort::tile);
  EXPECT_TRUE(moved.ran);
  EXPECT_GT(moved.ms, 0.0);
  EXPECT_FALSE(run(FurSort::tile).ran);
  EXPECT_TRUE(run(FurSort::layer).ran);  // another layout
  // Unmerged fins under the test rig: the first frame builds the list, later frames reuse it.
  EXPECT_TRUE(run_frame(rig, FurSort::tile).stage("fins").ran);
  EXPECT_FALSE(run_frame(rig, FurSort::tile).stage("fins").ran);
}

// A wind of strength 0 with gusts pushes nothing: a static scene is simulated once, not in
// every frame (it used to re-run "wind" and "fur_pose" every frame for identical images). An
// animated strength that leaves 0 is wind again, and back at 0 the fur is the gravity pose.
TEST(FurObjectStats, WindOfStrengthZeroIsNotResimulated) {
  FurRig rig("box:3", small_fur(8, fur::FinMode::off), "box");
  rig.frame.gravity = fur::GravityParams{};
  fur::WindParams still;
  still.strength = 0.0f;
  still.gust_scale = 0.5f;
  still.gust_frequency = 0.5f;
  rig.frame.wind = still;
  std::vector<raster::DrawCall> draws;
  run_frame(rig, FurSort::tile, &draws);
  const std::vector<glm::vec3> first(draws[0].positions, draws[0].positions + draws[0].vertex_count);
  for (int frame = 1; frame < 4; ++frame) {
    rig.frame.frame = frame;
    rig.frame.time_seconds = frame / 24.0;
    const FrameStats stats = run_frame(rig, FurSort::tile, &draws);
    EXPECT_FALSE(stats.stage("wind").ran) << "frame " << frame;
    EXPECT_FALSE(stats.stage("fur_pose").ran) << "frame " << frame;
    EXPECT_FALSE(stats.stage("fur_lighting").ran) << "frame " << frame;
    EXPECT_EQ(std::vector<glm::vec3>(draws[0].positions, draws[0].positions + draws[0].vertex_count), first);
  }
  // An animated strength, 0 at frames 3 and 5, 2 at frame 4.
  fur::WindParams blowing = still;
  blowing.strength = 2.0f;
  rig.frame.frame = 4;
  rig.frame.time_seconds = 4 / 24.0;
  rig.frame.wind = blowing;
  FrameStats stats = run_frame(rig, FurSort::tile, &draws);
  EXPECT_TRUE(stats.stage("wind").ran);
  EXPECT_NE(std::vector<glm::vec3>(draws[0].positions, draws[0].positions + draws[0].vertex_count), first);
  rig.frame.frame = 5;
  rig.frame.time_seconds = 5 / 24.0;
  rig.frame.wind = still;
  stats = run_frame(rig, FurSort::tile, &draws);
  EXPECT_TRUE(stats.stage("fur_pose").ran);
  EXPECT_EQ(std::vector<glm::vec3>(draws[0].positions, draws[0].positions + draws[0].vertex_count), first);
}

// The project's input-error rule: "FILE: JSON-PATH: REASON". Fur set-up errors used to name the
// object ("bunny: fur.comb.field: ...") instead of the scene file and the field's path.
TEST(FurObjectErrors, NameTheSceneFileAndTheFieldsJsonPath) {
  const FurOrigin origin{"/scenes/furry.json", "objects[2]"};
  FrameStats setup;
  fur::FurParams combed = small_fur(4, fur::FinMode::off);
  combed.comb = fur::CombParams{};
  combed.comb->field = fur::CombField::uv;
  Mesh no_uvs = io::make_builtin_mesh("box:3");
  no_uvs.uvs.clear();
  try {
    FurObject fur(no_uvs, combed, {}, origin, setup);
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file, "/scenes/furry.json");
    EXPECT_EQ(e.field, "objects[2].fur.comb.field");
    EXPECT_EQ(std::string(e.what()).rfind("/scenes/furry.json: objects[2].fur.comb.field: ", 0), 0u) << e.what();
  }
  Mesh far = io::make_builtin_mesh("box:3");
  far.positions[0].x = std::numeric_limits<float>::infinity();
  try {
    FurObject fur(far, small_fur(4, fur::FinMode::off), {}, origin, setup);
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file, "/scenes/furry.json");
    EXPECT_EQ(e.field, "objects[2].fur.mesh.positions");
  }
}

}  // namespace
}  // namespace pelt::render::test
