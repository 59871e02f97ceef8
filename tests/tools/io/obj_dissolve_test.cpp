// An MTL material's `map_d` (its dissolve map) blends its faces as its colour map's alpha
// (io/dissolve_map.h): the loader hands on one image, map_Kd's colour with map_d's dissolve.
// Until 2026-11-28 map_d was warned of and not drawn.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/temp_dir.h"
#include "tools/io/budget.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"
#include "tools/io/srgb.h"

namespace pelt::io {
namespace {

const std::string kQuadObj =
    "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";

LoadedMesh quad_with(const TempDir& dir, const std::string& mtl) {
  dir.write("q.mtl", mtl);
  return load_mesh_file(dir.write("q.obj", kQuadObj));
}

// A one-texel grey colour map c.ppm and a dissolve of 7/255, d.pgm, under material m's statements.
LoadedMesh one_texel_maps(const TempDir& dir, const std::string& statements) {
  dir.write("c.ppm", "P3\n1 1\n255\n9 9 9\n");
  dir.write("d.pgm", "P2\n1 1\n255\n7\n");
  return quad_with(dir, "newmtl m\n" + statements);
}

void expect_only_warning(const LoadedMesh& l, const std::string& warning) {
  ASSERT_EQ(l.warnings.size(), 1u) << ::testing::PrintToString(l.warnings);
  EXPECT_EQ(l.warnings[0], warning);
}

// Texel (x, y)'s channel c of the set's combined map.
float texel(const LoadedMesh& l, int x, int y, int c) {
  const ImageRGBA& img = *l.set(0).color_map.pixels;
  return img.pixel(x, y)[c];
}

// A grey map_d beside an RGB map_Kd: the colour's texels, sRGB-decoded as a colour map is, with the
// grey level as their alpha, read linear (data, not colour); the set blends by it, and names both
// files as its inputs.
TEST(ObjDissolve, AGreyDissolveMapIsTheColourMapsAlpha) {
  TempDir dir;
  dir.write("c.ppm", "P3\n2 1\n255\n255 0 0  0 128 0\n");
  dir.write("d.pgm", "P2\n2 1\n255\n0 51\n");
  const LoadedMesh l = quad_with(dir, "newmtl m\nmap_Kd c.ppm\nmap_d d.pgm\n");
  ASSERT_EQ(l.maps.size(), 1u);
  const MeshMaps& set = l.set(0);
  EXPECT_EQ(set.alpha_mode, AlphaMode::blend);
  EXPECT_EQ(set.alpha_factor, 1.0f);
  ASSERT_TRUE(set.color_map.pixels);
  EXPECT_TRUE(set.color_map.path.empty());
  EXPECT_EQ(set.color_map.files, (std::vector{dir.path() / "c.ppm", dir.path() / "d.pgm"}));
  EXPECT_EQ(texel(l, 0, 0, 0), 1.0f);
  EXPECT_NEAR(texel(l, 1, 0, 1), srgb8_to_linear(128), 1e-6f);
  EXPECT_EQ(texel(l, 0, 0, 3), 0.0f);
  EXPECT_NEAR(texel(l, 1, 0, 3), 0.2f, 1e-6f);
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
}

// An RGBA map_d (often the colour map's own file) gives its alpha; -imfchan picks a channel
// (m: the alpha, l: the luminance); without map_Kd the colour is white at the dissolve's size; `d`
// below 1 multiplies, as the factor.
TEST(ObjDissolve, TheChannelIsTheAlphaOrTheOneNamed) {
  TempDir dir;
  const uint8_t rgba[2 * 4] = {255, 0, 0, 102, 0, 0, 255, 204};
  write_image_atomic(dir.path() / "d.png", 2, 1, 4, PixelType::u8, rgba);
  const LoadedMesh alpha = quad_with(dir, "newmtl m\nd 0.5\nmap_d d.png\n");
  EXPECT_NEAR(texel(alpha, 0, 0, 3), 0.4f, 1e-6f);
  EXPECT_NEAR(texel(alpha, 1, 0, 3), 0.8f, 1e-6f);
  EXPECT_EQ(texel(alpha, 1, 0, 0), 1.0f);  // white
  EXPECT_EQ(alpha.set(0).alpha_factor, 0.5f);
  const LoadedMesh red = quad_with(dir, "newmtl m\nmap_d -imfchan r d.png\n");
  EXPECT_EQ(texel(red, 0, 0, 3), 1.0f);
  EXPECT_EQ(texel(red, 1, 0, 3), 0.0f);
  const LoadedMesh lum = quad_with(dir, "newmtl m\nmap_d -imfchan l d.png\n");
  EXPECT_NEAR(texel(lum, 0, 0, 3), 0.2126f, 1e-6f);
  EXPECT_NEAR(texel(lum, 1, 0, 3), 0.0722f, 1e-6f);
  try {
    quad_with(dir, "newmtl m\nmap_d -imfchan z d.png\n");
    ADD_FAILURE() << "-imfchan z was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, (dir.path() / "q.mtl").string());
    EXPECT_EQ(e.field, "line 2 `map_d` -imfchan");
    EXPECT_EQ(e.reason, "`z` is no channel pelt reads a dissolve from: r, g, b, m (the alpha) or l (the luminance)");
  }
}

// `-imfchan m` of a file without alpha reads 1 (opaque): said so. A dissolve map is decoded as the
// mesh loads, before the render's memory estimate: a large one beside a small colour map is refused
// there under a small --max-memory, naming it and the flag (a hunt found a 8192 x 8192 map_d
// shrunk to a 64 x 64 map_Kd passing a 300 MiB budget, at 1.4 GB).
TEST(ObjDissolve, AMissingAlphaIsNamedAndTheDecodingIsBudgeted) {
  TempDir dir;
  const LoadedMesh l = one_texel_maps(dir, "map_Kd c.ppm\nmap_d -imfchan m d.pgm\n");
  expect_only_warning(l, "`map_d -imfchan m` reads the alpha of d.pgm, which has none (its alpha reads 1): the faces "
                         "are drawn opaque");
  EXPECT_EQ(texel(l, 0, 0, 3), 1.0f);
  dir.write("big.pgm", "P5\n2048 2048\n255\n" + std::string(size_t(2048) * 2048, '\x80'));
  dir.write("q.mtl", "newmtl m\nmap_Kd c.ppm\nmap_d big.pgm\n");
  Budget small;
  small.max_memory_bytes = uint64_t{150} << 20;  // the process's 136 MiB and 64 MiB of floats do not fit
  try {
    load_mesh_file(dir.path() / "q.obj", small);
    ADD_FAILURE() << "a 2048 x 2048 dissolve map fit 150 MiB";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, (dir.path() / "big.pgm").string());
    EXPECT_NE(e.reason.find("reading it as a dissolve map beside its colour map c.ppm holds about"), std::string::npos)
        << e.what();
    EXPECT_NE(e.reason.find("(raise it with --max-memory)"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(load_mesh_file(dir.path() / "q.obj"));
}

// The dissolve multiplies the colour map's own alpha (three.js's alphaMap), but one RGBA file named
// as both gives its alpha once, not squared (a review found the colour map's holes dropped).
TEST(ObjDissolve, TheDissolveMultipliesTheColourMapsAlphaOnce) {
  TempDir dir;
  const uint8_t rgba[2 * 4] = {9, 9, 9, 255, 9, 9, 9, 102};
  write_image_atomic(dir.path() / "c.png", 2, 1, 4, PixelType::u8, rgba);
  dir.write("d.pgm", "P2\n2 1\n255\n255 51\n");
  const LoadedMesh two = quad_with(dir, "newmtl m\nmap_Kd c.png\nmap_d d.pgm\n");
  EXPECT_EQ(texel(two, 0, 0, 3), 1.0f);
  EXPECT_NEAR(texel(two, 1, 0, 3), 0.4f * 0.2f, 1e-6f);
  const LoadedMesh one = quad_with(dir, "newmtl m\nmap_Kd c.png\nmap_d ./c.png\n");
  EXPECT_NEAR(texel(one, 1, 0, 3), 0.4f, 1e-6f);
}

// The pairs of a file's materials are held together as the mesh loads: each is checked beside those
// read before it (a review found ten pairs each within the budget holding more than it together).
TEST(ObjDissolve, ThePairsOfAFileAreBudgetedTogether) {
  TempDir dir;
  // Appended, not `"header" + std::string(...)`: GCC 12 warns of that (a false -Warray-bounds).
  std::string pgm = "P5\n1024 1024\n255\n";
  pgm.append(size_t(1024) * 1024, '\x40');
  for (const char* name : {"a.pgm", "b.pgm"}) dir.write(name, pgm);
  dir.write("q.mtl", "newmtl m1\nmap_d a.pgm\nnewmtl m2\nmap_d b.pgm\n");
  const auto obj = dir.write("q.obj", "mtllib q.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                      "usemtl m1\nf 1/1 2/2 3/3\nusemtl m2\nf 1/1 3/3 2/2\n");
  // Each pair alone: the process (136 MiB), the dissolve map decoded (17 MiB) and its white image
  // (16 MiB) fit 180 MiB; the second beside the first's 16 MiB does not.
  Budget budget;
  budget.max_memory_bytes = uint64_t{180} << 20;
  try {
    load_mesh_file(obj, budget);
    ADD_FAILURE() << "two pairs fit 180 MiB";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, (dir.path() / "b.pgm").string()) << e.what();
  }
  budget.max_memory_bytes = uint64_t{200} << 20;
  EXPECT_EQ(load_mesh_file(obj, budget).maps.size(), 2u);
}

// A dissolve of another size is read bilinearly at the colour texels' centres: a 1 x 2 map of 0
// over 1 under a 1 x 4 colour map gives its rows 0, 0.25, 0.75 and 1 (clamped at the edges).
TEST(ObjDissolve, ADissolveOfAnotherSizeIsResampled) {
  TempDir dir;
  dir.write("c.ppm", "P3\n1 4\n255\n9 9 9\n9 9 9\n9 9 9\n9 9 9\n");
  dir.write("d.pgm", "P2\n1 2\n255\n0\n255\n");
  const LoadedMesh l = quad_with(dir, "newmtl m\nmap_Kd c.ppm\nmap_d d.pgm\n");
  const float want[4] = {0.0f, 0.25f, 0.75f, 1.0f};
  for (int y = 0; y < 4; ++y) EXPECT_NEAR(texel(l, 0, y, 3), want[y], 1e-6f) << y;
}

// map_d placed otherwise than map_Kd: one image cannot lie two ways, so the dissolve follows the
// colour map, with a warning; a missing dissolve file is an error naming it.
TEST(ObjDissolve, ADissolvePlacedApartIsNamedAndAMissingOneRefused) {
  TempDir dir;
  const LoadedMesh l = one_texel_maps(dir, "map_Kd -s 2 2 c.ppm\nmap_d d.pgm\n");
  expect_only_warning(l, "material `m` places `map_d d.pgm` otherwise than its `map_Kd` (-s, -o, -clamp): the "
                         "dissolve is read where the colour map lies");
  EXPECT_EQ(l.set(0).color_map.placement.m[0], 2.0f);
  dir.write("q.mtl", "newmtl m\nmap_d gone.png\n");
  EXPECT_THROW(load_mesh_file(dir.path() / "q.obj"), InputError);
  try {
    load_mesh_file(dir.path() / "q.obj");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gone.png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pelt::io
