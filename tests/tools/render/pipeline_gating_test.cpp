// Simulate only what a scene calls for: the frame stats prove which stages ran.
#include <gtest/gtest.h>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {
namespace {

struct Frames {
  std::vector<FrameStats> stats;
  std::vector<FrameImage> images;
};

Frames render_frames(const std::string& json, int frames, int threads = 1) {
  const io::Scene scene = io::parse_scene(json, "test.json");
  RenderSettings rs;
  rs.threads = threads;
  SceneRenderer r(scene, rs);
  Frames run;
  for (int f = 0; f < frames; ++f) {
    FrameImage img;
    FrameStats st;
    r.render(f, img, st);
    run.stats.push_back(st);
    run.images.push_back(std::move(img));
  }
  return run;
}

int count_ran(const Frames& run, const char* stage) {
  int n = 0;
  for (const FrameStats& s : run.stats) n += s.stage(stage).ran;
  return n;
}

// Meshes are loaded (and timed) only by the renderer that loads them: a caller's meshes are
// taken as given, one per object, and draw the same image.
TEST(Gating, MeshesAreLoadedOnlyWhenNotGiven) {
  const io::Scene scene = io::parse_scene(bare_box_scene(1), "test.json");
  RenderSettings rs;
  rs.threads = 1;
  SceneRenderer loads(scene, rs);
  SceneRenderer given(scene, io::load_scene_meshes(scene, rs.budget), rs);
  FrameImage a, b;
  FrameStats sa, sb;
  loads.render(0, a, sa);
  given.render(0, b, sb);
  EXPECT_TRUE(sa.stage("meshes").ran);
  EXPECT_FALSE(sb.stage("meshes").ran);
  EXPECT_EQ(a.color, b.color);
  EXPECT_THROW(SceneRenderer(scene, std::vector<io::SceneMesh>{}, rs), std::invalid_argument);
}

TEST(Gating, SceneWithoutFurBuildsNoShellsAndSimulatesNothing) {
  const Frames run = render_frames(bare_box_scene(3), 3);
  for (const char* stage :
       {"textures", "fur_geometry", "fur_textures", "gravity", "wind", "fur_pose", "fur_lighting", "fins"})
    EXPECT_EQ(count_ran(run, stage), 0) << stage;
  EXPECT_EQ(count_ran(run, "raster_tiles"), 3);
  EXPECT_EQ(run.stats[0].triangles(), 108u);  // box:3, no fur triangles
}

// A colour map is read and mip-mapped once, at set-up, and reported in frame 0 only.
TEST(Gating, ColourMapIsBuiltOnceAndReportedAsTextures) {
  SceneDir dir;
  std::vector<uint8_t> px(16 * 8 * 3, 180);
  io::write_image_atomic(dir.path() / "map.png", 16, 8, 3, io::PixelType::u8, px.data());
  const io::Scene scene = dir.scene(R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "objects": [{"mesh": "plane:1", "material": {"type": "lambert", "color_map": "map.png"}}],
      "animation": {"frames": 3}})");
  RenderSettings rs;
  rs.threads = 1;
  SceneRenderer r(scene, rs);
  int ran = 0;
  for (int f = 0; f < 3; ++f) {
    FrameImage img;
    FrameStats st;
    r.render(f, img, st);
    ran += st.stage("textures").ran;
    if (f == 0) {
      EXPECT_TRUE(st.stage("textures").ran);
    }
  }
  EXPECT_EQ(ran, 1);
}

TEST(Gating, FurWithoutWindRunsNoWindStageInAnyFrame) {
  const Frames run = render_frames(furry_box_scene(R"("gravity": {})", 5), 5);
  EXPECT_EQ(count_ran(run, "wind"), 0);
  EXPECT_EQ(count_ran(run, "gravity"), 1);        // inputs never change
  EXPECT_EQ(count_ran(run, "fur_geometry"), 1);   // built once, reported in frame 0
  EXPECT_EQ(count_ran(run, "fur_textures"), 1);
}

TEST(Gating, StaticHundredFrameRenderSimulatesOnce) {
  const Frames run = render_frames(furry_box_scene(R"("gravity": {}, "wind": {"gust_scale": 0})", 100), 100);
  EXPECT_EQ(count_ran(run, "gravity"), 1);
  EXPECT_EQ(count_ran(run, "wind"), 1);  // a steady wind: one field, one wind pose
  EXPECT_TRUE(run.stats[0].stage("fur_pose").ran);
  // The swing between the two poses is the only per-frame fur work.
  EXPECT_EQ(count_ran(run, "raster_tiles"), 100);
}

// Every frame but frame 0, which is at rest in the swing (t = 0: the gravity pose alone, so no
// wind is pushed for it).
TEST(Gating, GustingWindIsReevaluatedEveryFrameAndNothingElse) {
  const Frames run = render_frames(furry_box_scene(R"("wind": {"gust_frequency": 1.0, "gust_scale": 0.5})", 6), 6);
  EXPECT_FALSE(run.stats[0].stage("wind").ran);
  EXPECT_EQ(count_ran(run, "wind"), 5);
  EXPECT_EQ(count_ran(run, "gravity"), 0);
  EXPECT_EQ(count_ran(run, "fur_textures"), 1);
}

// Gravity of strength 0 bends nothing: no gravity pass, in any frame, and the frames are the
// bytes of fur without a gravity block.
TEST(Gating, GravityOfStrengthZeroRunsNoGravityPass) {
  const Frames zero = render_frames(furry_box_scene(R"("gravity": {"strength": 0})", 3), 3);
  const Frames none = render_frames(furry_box_scene("", 3), 3);
  EXPECT_EQ(count_ran(zero, "gravity"), 0);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(zero.images[f].color, none.images[f].color) << "frame " << f;
}

// A frame at rest in the swing (t = 0, frame 0) shows the gravity pose alone: it pushes no wind
// and is the bytes of the same fur without wind.
TEST(Gating, AFrameAtRestInTheSwingPushesNoWind) {
  const Frames windy = render_frames(furry_box_scene(R"("gravity": {}, "wind": {"gust_scale": 0})", 2), 2);
  const Frames calm = render_frames(furry_box_scene(R"("gravity": {})", 1), 1);
  EXPECT_FALSE(windy.stats[0].stage("wind").ran);
  EXPECT_TRUE(windy.stats[1].stage("wind").ran);
  EXPECT_EQ(windy.images[0].color, calm.images[0].color);
  EXPECT_NE(windy.images[1].color, calm.images[0].color);
}

// Fur writes neither depth nor id: those AOVs draw no fur and make none of its poses, nor its
// strand textures (until 2026-11-27 built at set-up: 145 ms of a 64 x 48 depth frame of box_fur).
TEST(Gating, DepthAndIdAovsMakeNoFurPoses) {
  for (Aov aov : {Aov::depth, Aov::id}) {
    const io::Scene scene = io::parse_scene(furry_box_scene(R"("gravity": {}, "wind": {})", 2), "test.json");
    RenderSettings rs;
    rs.threads = 1;
    rs.aov = aov;
    SceneRenderer r(scene, rs);
    for (int f = 0; f < 2; ++f) {
      FrameImage img;
      FrameStats st;
      r.render(f, img, st);
      for (const char* stage : {"gravity", "wind", "fur_pose", "fur_lighting", "fins", "fur_textures"})
        EXPECT_FALSE(st.stage(stage).ran) << stage << " frame " << f;
      if (f == 0) {
        EXPECT_TRUE(st.stage("fur_geometry").ran);  // built: it checks the fur block
      }
      EXPECT_EQ(st.triangles(), 588u) << "frame " << f;  // box:7's base alone
    }
  }
}

// Blurred normals are built for a skin whose multiple_scattering is normal_blur, and only for
// it: no other epidermis reads them, so --stats must not report the stage (README: "once per
// `normal_blur` skin mesh").
TEST(Gating, NormalBlurRunsOnlyForNormalBlurSkin) {
  for (const char* mode : {"paper", "reference", "off", "normal_blur"}) {
    const std::string json = R"({"pelt": 1, "image": {"width": 32, "height": 24},
        "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]},
        "objects": [{"mesh": "sphere:12", "material": {"type": "skin", "skin": {"multiple_scattering": ")" +
                             std::string(mode) + R"("}}}], "animation": {"frames": 2}})";
    const Frames run = render_frames(json, 2);
    EXPECT_EQ(count_ran(run, "normal_blur"), std::string(mode) == "normal_blur" ? 1 : 0) << mode;
  }
}

TEST(Gating, StaticFurIsPosedOnceAndFinsWeighedOnce) {
  const Frames run = render_frames(furry_box_scene("", 4), 4);
  EXPECT_EQ(count_ran(run, "fur_pose"), 1);
  EXPECT_EQ(count_ran(run, "fins"), 1);  // the camera never moves
  EXPECT_EQ(count_ran(run, "fur_lighting"), 1);
  for (int f = 1; f < 4; ++f) EXPECT_EQ(run.images[f].color, run.images[0].color) << f;
}

// The surface sort's keys are made only for that sort, and again only when the pose or the
// camera moves: once for a static furry box, every frame while a gusting wind moves it.
TEST(Gating, SurfaceSortKeysAreMadeOnlyWhenThePoseOrCameraMoves) {
  auto with_surface = [](std::string json) {
    json.insert(json.find('{') + 1, R"("quality": {"sort": "surface"}, )");
    return json;
  };
  EXPECT_EQ(count_ran(render_frames(furry_box_scene("", 4), 4), "fur_sort"), 0);
  EXPECT_EQ(count_ran(render_frames(with_surface(furry_box_scene("", 4)), 4), "fur_sort"), 1);
  const std::string gusts = furry_box_scene(R"("wind": {"strength": 1, "gust_frequency": 0.5, "gust_scale": 0.3})", 4);
  EXPECT_EQ(count_ran(render_frames(with_surface(gusts), 4), "fur_sort"), 4);
}

TEST(Gating, FurryBoxIsIdenticalOnOneAndTwoThreads) {
  const std::string json = furry_box_scene(R"("gravity": {}, "wind": {})", 3);
  const Frames one = render_frames(json, 3, 1), two = render_frames(json, 3, 2);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(one.images[f].color, two.images[f].color) << f;
  // The surface sort's keys too come out the same whatever the threads.
  std::string surface = json;
  surface.insert(surface.find('{') + 1, R"("quality": {"sort": "surface"}, )");
  const Frames s1 = render_frames(surface, 3, 1), s2 = render_frames(surface, 3, 2);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(s1.images[f].color, s2.images[f].color) << "surface " << f;
  EXPECT_NE(s1.images[2].color, one.images[2].color);  // the order is not the tile one's
}

TEST(Gating, FrameKAloneEqualsFrameKInARange) {
  const std::string json = furry_box_scene(R"("gravity": {}, "wind": {})", 8);
  const Frames all = render_frames(json, 8);
  const io::Scene scene = io::parse_scene(json, "test.json");
  SceneRenderer r(scene, RenderSettings{});
  FrameImage img;
  FrameStats st;
  r.render(5, img, st);
  EXPECT_EQ(img.color, all.images[5].color);
}

}  // namespace
}  // namespace pelt::render::test
