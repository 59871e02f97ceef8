// Fur on a mesh split at a texture seam, as exporters split them: the seam's two copies of each
// vertex grow one strand, so the fur looks as it does on the same mesh welded. Before, each side's
// boundary edge grew its own fin, and the two coincident fins blended the seam twice; a file
// without normals got a different normal on each side, and the shells cracked open along it.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "tests/tools/render/render_test_scenes.h"

namespace pelt::render::test {
namespace fur_seams_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// An OBJ of the sheet y = 0.4 x^2 + 0.3 x z over [-1, 1]^2 in 4 x 4 quads, bent across the seam
// (x = 0) so that normals, or directions along it, computed from one side's triangles alone
// would tilt away from the other side's. `split`:
// the column x = 0 is written twice, one copy for each side, as a texture seam is; the texture
// coordinates are the same either way, so only the vertex count tells the two files apart.
std::string plane_obj(bool split, bool with_normals) {
  const int n = 4;
  std::string v, vt, f;
  int count = 0;
  int index[n + 1][n + 1][2];
  for (int side = 0; side < (split ? 2 : 1); ++side)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        if (split && side == 1 && i != n / 2) continue;  // only the seam column is copied
        const float x = -1.0f + 2.0f * float(i) / n, z = -1.0f + 2.0f * float(j) / n;
        v += "v " + std::to_string(x) + " " + std::to_string(0.4f * x * x + 0.3f * x * z) + " " + std::to_string(z) + "\n";
        vt += "vt " + std::to_string((x + 1) / 2) + " " + std::to_string((z + 1) / 2) + "\n";
        index[i][j][side] = ++count;
        if (!split || i != n / 2) index[i][j][1] = count;
      }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int side = i < n / 2 ? 0 : 1;  // the right half uses the seam's second copy
      f += "f";
      for (const auto& [a, b] : {std::pair{i, j}, {i, j + 1}, {i + 1, j + 1}, {i + 1, j}}) {
        const std::string k = std::to_string(index[a][b][a == n / 2 ? side : 0]);
        f.append(" ").append(k).append("/").append(k).append(with_normals ? "/1" : "");
      }
      f += "\n";
    }
  return v + vt + (with_normals ? "vn 0 1 0\n" : "") + f;
}

std::string plane_scene(const std::string& mesh, const std::string& fins, const std::string& fur_extra) {
  return R"({"pelt": 1, "image": {"width": 160, "height": 120},
  "camera": {"eye": [0.3, 1.2, 2.6], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "intensity": 0.3}],
  "objects": [{"mesh": ")" +
         mesh + R"(", "material": {"type": "lambert"},
    "fur": {"shells": 16, "length": 0.15, "texture_size": 64, "fins": ")" + fins + "\"" +
         fur_extra + "}}]}";
}

// Bit for bit, in the tile, surface and exact sorts, sampled bilinear and trilinear. A second fin
// or an open seam is 0.03 to 0.07. Under trilinear filtering a block's level of detail comes from
// the triangles whose lanes the rasterizer packs into it, which must share an edge by index: the
// shells name one index for the seam's copies (0.003 to 0.009 apart when they named two).
void expect_seam_invisible(bool with_normals, const std::string& fur_extra) {
  SceneDir dir;
  dir.write("welded.obj", plane_obj(false, with_normals));
  dir.write("split.obj", plane_obj(true, with_normals));
  for (const auto& [sort, filter] : {std::pair{io::SortQuality::tile, raster::Filter::Bilinear},
                                     {io::SortQuality::tile, raster::Filter::Trilinear},
                                     {io::SortQuality::surface, raster::Filter::Trilinear},
                                     {io::SortQuality::exact, raster::Filter::Trilinear}}) {
    io::Quality q;
    q.filter = filter;
    q.sort = sort;
    const FrameImage welded = render_at(dir.scene(plane_scene("welded.obj", "all", fur_extra)), q);
    const FrameImage split = render_at(dir.scene(plane_scene("split.obj", "all", fur_extra)), q);
    ASSERT_EQ(welded.color.size(), split.color.size());
    size_t differ = 0;
    for (size_t i = 0; i < welded.color.size(); ++i) differ += welded.color[i] != split.color[i];
    EXPECT_EQ(differ, 0u) << "of " << welded.color.size() << " channel values, sort " << int(sort) << ", filter "
                          << int(filter);
    // The scene shows fins: with them off, the image changes (the test would not see a second fin
    // in a frame that draws none).
    const FrameImage no_fins = render_at(dir.scene(plane_scene("split.obj", "off", fur_extra)), q);
    EXPECT_NE(no_fins.color, split.color);
  }
}

TEST(FurSeams, ASplitSeamLooksLikeTheWeldedMesh) { expect_seam_invisible(true, ""); }

TEST(FurSeams, ASplitSeamLooksLikeTheWeldedMeshUnderGravityAndWind) {
  expect_seam_invisible(true, R"(, "gravity": {"strength": 2},
    "wind": {"direction": [1, 0, 0.3], "strength": 2, "gust_frequency": 0.5, "gust_scale": 0.5})");
}

// Combing along the texture's u: each copy of a seam vertex sees only its side's triangles, so
// alone they would comb apart (by half the sheet's turn between columns); they take their joined
// direction instead, as the welded vertex does. (Normals computed: under the file's normals, all
// +y, the one-sided tilt would lie along the normal and vanish in the projection.)
TEST(FurSeams, ASplitSeamCombsLikeTheWeldedMesh) {
  expect_seam_invisible(false, R"(, "comb": {"field": "uv", "weight": 0.8})");
}

// Normals computed from the triangles sum over both copies of a seam vertex (the OBJ loader's
// NormalSharing::per_position): the shells stay closed along the seam.
TEST(FurSeams, ComputedNormalsDoNotOpenTheSeam) { expect_seam_invisible(false, ""); }

}  // namespace fur_seams_test
}  // namespace pelt::render::test
