// The quality knobs and the reference renderer: every knob reaches the image (and changes it
// exactly when its setting differs from what the scene would do anyway), the reference is
// deterministic and converges to closed-form answers, and more samples or an exact sort move
// an image toward the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>

#include "shading/skin_reference.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/input_error.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {
namespace {

// Fur on a box (16 shells, silhouette fins) beside a skin sphere (paper epidermis, correct
// dermis): every knob has something to act on.
std::string knob_scene() {
  return R"({"pelt": 1,
  "image": {"width": 64, "height": 48, "background": [0.05, 0.05, 0.08]},
  "camera": {"eye": [0, 1.5, 7.0], "target": [0, 0, 0], "fovy_deg": 40, "near": 0.5, "far": 30},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]},
             {"type": "ambient", "color": [0.2, 0.2, 0.25]}],
  "objects": [
    {"mesh": "box:5", "transform": {"translate": [-1.3, 0, 0], "rotate_deg": [0, 30, 0]},
     "material": {"type": "lambert", "color": [0.3, 0.2, 0.1]},
     "fur": {"shells": 16, "texture_size": 64, "fins": "silhouette"}},
    {"mesh": "sphere:24", "transform": {"translate": [1.3, 0, 0]},
     "material": {"type": "skin", "skin": {"multiple_scattering": "paper", "single_scattering": "correct"}}}]})";
}

// The knob scene with its fur drooping under gravity: strands leaning across the shells' edges,
// where the `surface` sort's rules come into play.
std::string drooping_knob_scene() {
  std::string text = knob_scene();
  const std::string fur = R"("fins": "silhouette"})";
  const size_t at = text.find(fur);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.replace(at, fur.size(), R"("fins": "silhouette", "gravity": {"strength": 1.0}})");
  return text;
}

const io::Quality& reference_quality() {
  static const io::Quality q = *io::quality_preset("reference");
  return q;
}

// RenderSettings::color8 (bench fps's framebuffer): the bytes are raster::unorm8 of the float
// frame the same settings give, with one sample (resolved by the tiles) and with four (the
// average converted once).
TEST(Quality, TheRgba8FrameIsTheFloatFrameQuantised) {
  const io::Scene scene = io::parse_scene(knob_scene(), "knobs.json");
  for (int spp : {1, 4}) {
    io::Quality q = *io::quality_preset("default");
    q.spp = spp;
    RenderSettings rs;
    rs.threads = 2;
    rs.quality = q;
    FrameImage floats, bytes;
    FrameStats st;
    SceneRenderer(scene, rs).render(0, floats, st);
    rs.color8 = true;
    SceneRenderer(scene, rs).render(0, bytes, st);
    ASSERT_EQ(floats.color.size(), bytes.color8.size()) << "spp " << spp;
    EXPECT_TRUE(floats.color8.empty());
    EXPECT_EQ(bytes.color.empty(), spp == 1);  // one sample resolves straight to bytes
    size_t mid = 0;
    for (size_t i = 0; i < floats.color.size(); ++i) {
      ASSERT_EQ(bytes.color8[i], raster::unorm8(floats.color[i])) << "spp " << spp << " value " << i;
      mid += bytes.color8[i] > 0 && bytes.color8[i] < 255;
    }
    EXPECT_GT(mid, floats.color.size() / 4) << "spp " << spp;  // a picture, not a flat fill
  }
}

TEST(Quality, ReferenceIsDeterministicOnAnyThreadCount) {
  const io::Scene scene = io::parse_scene(knob_scene(), "knobs.json");
  const FrameImage one = render_at(scene, reference_quality(), 1);
  const FrameImage two = render_at(scene, reference_quality(), 2);
  ASSERT_EQ(one.color.size(), two.color.size());
  EXPECT_TRUE(std::equal(one.color.begin(), one.color.end(), two.color.begin()));
  EXPECT_EQ(image_rmse(one.color, two.color), 0.0);
  for (float v : one.color) ASSERT_TRUE(std::isfinite(v));
}

// Each sweep setting of each knob, one at a time from the scene's default: the image is
// bit-identical when the setting is what the scene does anyway, and differs otherwise. (The fur
// droops: on upright fur the `surface` sort holds nothing back and draws the `tile` image.)
TEST(Quality, EveryKnobSettingReachesTheRenderer) {
  const io::Scene scene = io::parse_scene(drooping_knob_scene(), "knobs.json");
  const io::Quality base;
  const std::vector<float> plain = render_at(scene, base).color;
  // What the scene does without a knob: its fur and skin blocks, the renderer's defaults.
  const std::map<std::string, std::string> as_scene = {
      {"shells", "16"},       {"fins", "silhouette"},        {"fin_quads", "merged"}, {"sort", "tile"},
      {"spp", "1"},           {"filter", "trilinear"},       {"multiple_scattering", "paper"},
      {"single_scattering", "correct"}, {"precision", "simd"}};
  int changed = 0, same = 0;
  for (std::string_view knob : io::kKnobs) {
    for (const std::string& setting : io::knob_sweep(knob)) {
      io::Quality q = base;
      ASSERT_FALSE(io::set_knob(q, knob, setting)) << knob << "=" << setting;
      const std::vector<float> img = render_at(scene, q).color;
      const bool equal = std::equal(img.begin(), img.end(), plain.begin());
      if (setting == as_scene.at(std::string(knob))) {
        EXPECT_TRUE(equal) << knob << "=" << setting << " is the scene's own setting";
        ++same;
      } else {
        EXPECT_FALSE(equal) << knob << "=" << setting << " did not change the image";
        ++changed;
      }
    }
  }
  std::printf("knob settings checked: %d change the image, %d equal the scene's own\n", changed, same);
  EXPECT_EQ(same, 9);
}

TEST(Quality, MoreSamplesAndAnExactSortMoveTowardTheReference) {
  const io::Scene scene = io::parse_scene(knob_scene(), "knobs.json");
  const std::vector<float> ref = render_at(scene, reference_quality()).color;
  auto error_with = [&](std::string_view knob, const std::string& value) {
    io::Quality q;
    EXPECT_FALSE(io::set_knob(q, knob, value));
    return image_rmse(render_at(scene, q).color, ref);
  };
  const double spp1 = error_with("spp", "1"), spp16 = error_with("spp", "16");
  const double none = error_with("sort", "none"), exact = error_with("sort", "exact");
  std::printf("RMSE vs reference: spp 1 %.5f, spp 16 %.5f; sort none %.5f, sort exact %.5f\n", spp1, spp16, none,
              exact);
  EXPECT_LT(spp16, spp1);
  EXPECT_LT(exact, none);
  EXPECT_GT(spp16, 0.0);  // the default's other knobs still differ from the reference
}

// Translucent layers: planes of constant colour and opacity (skin lit only by an ambient
// light, so every term but the ambient one is zero) composite, under the reference's exact
// per-pixel sort, to the closed form whatever order the objects are listed in.
std::string layer_object(double z, const double rgb[3], double opacity) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                R"({"mesh": "plane:2", "transform": {"translate": [0, 0, %g], "rotate_deg": [90, 0, 0], "scale": 4},
  "material": {"type": "skin", "double_sided": true, "skin": {"SkinColor": [%g, %g, %g], "Opacity": %g,
  "AmbientCoeff": 1, "Specularity": 0, "multiple_scattering": "off", "single_scattering": "off"}}})",
                z, rgb[0], rgb[1], rgb[2], opacity);
  return buf;
}

// The shells knob re-slices the scene's fur, it does not make another fur: gravity's bend
// (eq. 2, whose total grows with the square of the node count as printed) and the strand
// opacity are scaled to the authored 16 layers (FurParams::authored_shells), so 48 shells
// draw the same drooping fur more finely. Without the gravity scale the 48-shell fur hung
// straight down the box's sides and stood ten times as far from the 16-shell image (RMSE
// 0.046 against 0.0048 here).
TEST(Quality, TheShellsKnobKeepsTheGravityPose) {
  const io::Scene scene = io::parse_scene(drooping_knob_scene(), "knobs_gravity.json");
  const std::vector<float> authored = render_at(scene, io::Quality{}).color;
  io::Quality q;
  ASSERT_FALSE(io::set_knob(q, "shells", "48"));
  const double resliced = image_rmse(render_at(scene, q).color, authored);
  std::printf("RMSE between 48 and the scene's 16 shells, with gravity: %.5f\n", resliced);
  EXPECT_GT(resliced, 0.0);  // a finer slicing is a different image
  EXPECT_LT(resliced, 0.012);
}

TEST(Quality, ReferenceCompositesTranslucentLayersToTheClosedFormInAnyOrder) {
  const double rgb[4][3] = {{0.9, 0.2, 0.1}, {0.1, 0.8, 0.3}, {0.2, 0.3, 0.9}, {0.7, 0.7, 0.2}};
  const double opacity[4] = {0.35, 0.6, 0.25, 0.8};
  const double z[4] = {0.5, -0.25, -1.0, -1.75};  // layer 0 nearest the camera at z = 6
  const double bg[3] = {0.05, 0.1, 0.2};
  // Back to front: C = c a + C (1 - a), with c = AmbientCoeff x SkinColor x ambient colour.
  double expect[3] = {bg[0], bg[1], bg[2]};
  for (int k = 3; k >= 0; --k)
    for (int c = 0; c < 3; ++c) expect[c] = rgb[k][c] * opacity[k] + expect[c] * (1.0 - opacity[k]);

  int order[4] = {0, 1, 2, 3};
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    std::shuffle(order, order + 4, rng);
    std::string objects;
    for (int k : order) {
      if (!objects.empty()) objects += ',';
      objects += layer_object(z[k], rgb[k], opacity[k]);
    }
    const io::Scene scene = io::parse_scene(
        R"({"pelt": 1, "image": {"width": 32, "height": 24, "background": [0.05, 0.1, 0.2]},
        "camera": {"eye": [0, 0, 6], "target": [0, 0, 0], "fovy_deg": 30},
        "lights": [{"type": "ambient", "color": [1, 1, 1]}], "objects": [)" + objects + "]}",
        "layers.json");
    const FrameImage img = render_at(scene, reference_quality());
    for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(img.color[4 * p + c], expect[c], 2e-6) << "pixel " << p << " channel " << c << " trial " << trial;
  }
}

// A Lambert plane under a directional and an ambient light has one exact radiance,
// albedo (ambient + E cos theta), at every pixel; the reference hits it to float rounding.
TEST(Quality, ReferenceGivesAFlatLitPlaneItsExactRadiance) {
  const io::Scene scene = io::parse_scene(
      R"({"pelt": 1, "image": {"width": 40, "height": 30},
      "camera": {"eye": [0, 5, 0.001], "target": [0, 0, 0], "fovy_deg": 30},
      "lights": [{"type": "directional", "direction": [0.6, 0.8, 0], "color": [1, 0.9, 0.8], "intensity": 1.5},
                 {"type": "ambient", "color": [0.1, 0.2, 0.3]}],
      "objects": [{"mesh": "plane:3", "transform": {"scale": 10},
                   "material": {"type": "lambert", "color": [0.5, 0.4, 0.3]}}]})",
      "plane.json");
  const FrameImage img = render_at(scene, reference_quality());
  const double albedo[3] = {0.5, 0.4, 0.3}, e[3] = {1.5, 1.35, 1.2}, amb[3] = {0.1, 0.2, 0.3};
  const double cos_theta = 0.8;
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(img.color[4 * p + c], albedo[c] * (amb[c] + e[c] * cos_theta), 1e-6) << "pixel " << p;
}

// Skin on the same plane: the reference pixel is the mean of the double-precision shader over
// its 64 sub-samples, which for a shading function this smooth across a pixel is the value at
// the pixel centre to well under 1/255.
TEST(Quality, ReferenceSkinPlaneMatchesTheDoubleShaderAtPixelCentres) {
  const io::Scene scene = io::parse_scene(
      R"({"pelt": 1, "image": {"width": 40, "height": 30},
      "camera": {"eye": [0, 5, 2], "target": [0, 0, 0], "fovy_deg": 30},
      "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.2]}],
      "objects": [{"mesh": "plane:3", "transform": {"scale": 10}, "material": {"type": "skin"}}]})",
      "skin_plane.json");
  const io::Quality q = reference_quality();
  const FrameImage img = render_at(scene, q);
  const io::Scene applied = apply_quality(scene, q);
  const shading::SkinParams& params = applied.objects[0].material.skin;
  const io::Camera& cam = scene.camera;
  const glm::mat4 inv = glm::inverse(cam.projection(40.0f / 30.0f) * cam.view());
  shading::Light light{};
  light.type = shading::Light::Type::Directional;
  const glm::vec3 l = glm::normalize(glm::vec3(0.3f, 0.8f, 0.2f));
  light.vec[0] = l.x, light.vec[1] = l.y, light.vec[2] = l.z;
  light.color[0] = light.color[1] = light.color[2] = 1.0f;
  const double eye[3] = {0, 5, 2};
  double worst = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      // The pixel centre's ray, intersected with the plane y = 0.
      const glm::vec4 ndc(2.0f * (x + 0.5f) / img.width - 1.0f, 1.0f - 2.0f * (y + 0.5f) / img.height, 0.5f, 1.0f);
      glm::vec4 w = inv * ndc;
      const glm::dvec3 p = glm::dvec3(w) / double(w.w);
      const glm::dvec3 o(eye[0], eye[1], eye[2]);
      const double t = o.y / (o.y - p.y);
      const glm::dvec3 hit = o + t * (p - o);
      shading::ref::Sample s{};
      s.pos[0] = hit.x, s.pos[1] = hit.y, s.pos[2] = hit.z;
      s.normal[1] = 1.0;
      s.albedo[0] = s.albedo[1] = s.albedo[2] = 1.0;
      const shading::ref::Shaded want = shading::ref::shade_skin_pixel(params, &light, 1, eye, s);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(double(img.color[4 * (size_t(y) * img.width + x) + c]) - want.rgb[c]));
    }
  std::printf("skin plane: largest |reference - double shader at the centre| = %.2e\n", worst);
  EXPECT_LT(worst, 1e-3);
}

TEST(Quality, SupersampledDepthIdOrOverdrawIsABadRequest) {
  const io::Scene scene = io::parse_scene(bare_box_scene(1), "box.json");
  RenderSettings rs;
  io::Quality q;
  q.spp = 4;
  rs.quality = q;
  rs.aov = Aov::depth;
  EXPECT_THROW(SceneRenderer(scene, rs), io::InputError);
  rs.aov = Aov::id;
  EXPECT_THROW(SceneRenderer(scene, rs), io::InputError);
  rs.aov = Aov::overdraw;
  EXPECT_THROW(SceneRenderer(scene, rs), io::InputError);
  rs.aov = Aov::color;
  EXPECT_NO_THROW(SceneRenderer(scene, rs));
}

TEST(Quality, SampleOffsetsAreStratumCentres) {
  for (int n = 1; n <= 8; ++n) {
    const std::vector<glm::vec2> o = sample_offsets(n * n);
    ASSERT_EQ(o.size(), size_t(n * n));
    glm::dvec2 mean(0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const glm::vec2 s = o[size_t(j * n + i)];
        // One sample in each of the n x n strata of the pixel, at its centre.
        EXPECT_EQ(int(std::floor((s.x + 0.5f) * n)), i);
        EXPECT_EQ(int(std::floor((s.y + 0.5f) * n)), j);
        mean += glm::dvec2(s);
      }
    EXPECT_NEAR(mean.x, 0.0, 1e-5);
    EXPECT_NEAR(mean.y, 0.0, 1e-5);
  }
  EXPECT_THROW(sample_offsets(3), std::invalid_argument);
}

}  // namespace
}  // namespace pelt::render::test
