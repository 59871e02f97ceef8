#include "fur/strand_textures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace pelt::fur {
namespace {

StrandTextures grow(const FurParams& p) {
  StrandTextures t;
  auto e = generate_strand_textures(p, t);
  EXPECT_FALSE(e.has_value()) << e->field << ": " << e->reason;
  return t;
}

size_t covered(const LayerTextures& t, int s) {
  size_t n = 0;
  const uint8_t* p = t.layer(s);
  for (size_t k = 0; k < size_t(t.size) * t.size; ++k) n += p[4 * k + 3] > 0;
  return n;
}

uint8_t to8(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

TEST(StrandTextures, LayoutAndFormat) {
  FurParams p;
  p.shells = 5;
  p.texture_size = 64;
  const StrandTextures t = grow(p);
  EXPECT_EQ(t.shells.size, 64);
  EXPECT_EQ(t.shells.layers, 5);
  EXPECT_EQ(t.shells.rgba.size(), 5u * 64 * 64 * 4);
  EXPECT_EQ(t.fin.size, 64);
  EXPECT_EQ(t.fin.layers, 1);
  EXPECT_EQ(t.fin.rgba.size(), 64u * 64 * 4);
}

// One luminance-alpha layer against its RGBA twin (n x n texels): equal alpha bytes, and
// min(1, tint(y) L) per channel within the rounding of L, scaled by the tint (<= 1.25 * 0.5 /
// 255), plus the RGBA byte's own. Returns the number of strand texels (alpha > 0), stopping
// at the first colour that is not near.
size_t expect_la_layer_matches_rgba(const uint8_t* la, const uint8_t* rgba, int n,
                                    const std::function<glm::vec3(int)>& tint, const std::string& what) {
  size_t strands = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t t = size_t(y) * size_t(n) + size_t(x);
      EXPECT_EQ(la[2 * t + 1], rgba[4 * t + 3]) << what << " texel " << x << "," << y;
      strands += la[2 * t + 1] > 0;
      for (int c = 0; c < 3; ++c) {
        const double colour = std::min(1.0, double(tint(y)[c]) * la[2 * t] / 255.0);
        const bool near = std::abs(colour - rgba[4 * t + c] / 255.0) <= (1.25 * 0.5 + 0.5) / 255.0 + 1e-6;
        EXPECT_TRUE(near) << what << " texel " << x << "," << y << " channel " << c << ": " << colour << " against "
                          << rgba[4 * t + c] / 255.0;
        if (!near) return strands;
      }
    }
  return strands;
}

// The luminance form of the shells holds the same strands and colours (as min(1, tint L)).
size_t expect_luminance_matches_rgba(const StrandTextures& t) {
  const ShellLuminance& lum = t.shell_luminance;
  const int n = t.shells.size, layers = t.shells.layers;
  EXPECT_EQ(lum.size, n);
  EXPECT_EQ(lum.layers, layers);
  EXPECT_EQ(lum.la.size(), size_t(layers) * size_t(n) * size_t(n) * 2);
  EXPECT_EQ(lum.tint.size(), size_t(layers));
  if (lum.la.size() != size_t(layers) * size_t(n) * size_t(n) * 2 || lum.tint.size() != size_t(layers)) return 0;
  size_t strands = 0;
  for (int s = 0; s < layers; ++s)
    strands += expect_la_layer_matches_rgba(lum.la.data() + size_t(s) * size_t(n) * size_t(n) * 2, t.shells.layer(s), n,
                                            [&](int) { return lum.tint[size_t(s)]; }, "layer " + std::to_string(s));
  return strands;
}

TEST(StrandTextures, LuminanceShellsMatchTheRgbaShells) {
  for (glm::vec3 tip : {glm::vec3(0.8f, 0.58f, 0.36f), glm::vec3(0.95f, 0.9f, 0.1f)}) {
    FurParams p;
    p.shells = 6;
    p.texture_size = 64;
    p.tip_color = tip;  // 0.95 * 1.25 saturates in both forms
    p.seed = 11;
    EXPECT_GT(expect_luminance_matches_rgba(grow(p)), 1000u);
  }
}

// The fin's luminance form holds the same strands and, as min(1, (tint_root + tint_slope v) L)
// at the row's height v, the same colours.
size_t expect_fin_luminance_matches_rgba(const StrandTextures& t) {
  const FinLuminance& lum = t.fin_luminance;
  const int n = t.fin.size;
  EXPECT_EQ(lum.size, n);
  EXPECT_EQ(lum.la.size(), size_t(n) * size_t(n) * 2);
  if (lum.la.size() != size_t(n) * size_t(n) * 2) return 0;
  return expect_la_layer_matches_rgba(
      lum.la.data(), t.fin.layer(0), n,
      [&](int y) { return lum.tint_root + lum.tint_slope * ((float(y) + 0.5f) / float(n)); }, "fin");
}

TEST(StrandTextures, LuminanceFinMatchesTheRgbaFin) {
  for (glm::vec3 tip : {glm::vec3(0.8f, 0.58f, 0.36f), glm::vec3(0.95f, 0.9f, 0.1f)}) {
    FurParams p;
    p.shells = 6;
    p.texture_size = 64;
    p.root_color = glm::vec3(0.2f, 0.1f, 0.05f);
    p.tip_color = tip;
    p.seed = 12;
    EXPECT_GT(expect_fin_luminance_matches_rgba(grow(p)), 100u);
  }
  // The harness's fin: fur colour times (0.45 + 0.55 v) times the brightness.
  EXPECT_GT(expect_fin_luminance_matches_rgba(match_llvmpipe_textures()), 256u * 256 / 8);
}

// The harness's shells too: pelt samples their luminance form (--match-llvmpipe).
TEST(StrandTextures, MatchLlvmpipeLuminanceShellsMatchTheHarnessBytes) {
  EXPECT_GT(expect_luminance_matches_rgba(match_llvmpipe_textures()), 16u * 256 * 256 / 4);
}

TEST(StrandTextures, DensityIsWithinTwoPercentOfTheRequest) {
  for (float density : {15.0f, 30.0f, 2.5f}) {
    for (int size : {64, 256}) {
      FurParams p;
      p.density = density;
      p.texture_size = size;
      p.seed = 77;
      const StrandTextures t = grow(p);
      const double area = double(size) * size;
      const double want = density / 100.0;
      const double roots = double(t.strands.size()) / area;
      const double measured = double(covered(t.shells, 0)) / area;  // root texels
      EXPECT_NEAR(roots / want, 1.0, 0.02) << "density " << density << " size " << size;
      EXPECT_NEAR(measured / want, 1.0, 0.02) << "density " << density << " size " << size;
    }
  }
}

TEST(StrandTextures, SameSeedSameTexturesOtherSeedDifferent) {
  FurParams p;
  p.texture_size = 128;
  p.seed = 1234;
  const StrandTextures a = grow(p), b = grow(p);
  EXPECT_EQ(a.shells.rgba, b.shells.rgba);
  EXPECT_EQ(a.fin.rgba, b.fin.rgba);
  EXPECT_EQ(a.fin_luminance.la, b.fin_luminance.la);
  p.seed = 1235;
  const StrandTextures c = grow(p);
  EXPECT_NE(a.shells.rgba, c.shells.rgba);
  EXPECT_NE(a.fin.rgba, c.fin.rgba);
  EXPECT_NE(a.fin_luminance.la, c.fin_luminance.la);
}

// The renderer grows only the luminance form: everything else must be what the full
// generation gives, for pelt's own fur and for the harness's.
TEST(StrandTextures, LuminanceOnlyLeavesOutJustTheRgbaShells) {
  FurParams p;
  p.texture_size = 64;
  p.shells = 6;
  p.seed = 77;
  const StrandTextures full = grow(p);
  StrandTextures lum;
  ASSERT_FALSE(generate_strand_textures(p, lum, ShellForms::LuminanceOnly).has_value());
  EXPECT_TRUE(lum.shells.rgba.empty());
  EXPECT_EQ(lum.shells.size, full.shells.size);
  EXPECT_EQ(lum.shells.layers, full.shells.layers);
  EXPECT_EQ(lum.shell_luminance.la, full.shell_luminance.la);
  EXPECT_EQ(lum.shell_luminance.tint, full.shell_luminance.tint);
  EXPECT_EQ(lum.fin.rgba, full.fin.rgba);
  EXPECT_EQ(lum.fin_luminance.la, full.fin_luminance.la);
  EXPECT_EQ(lum.fin_luminance.tint_root, full.fin_luminance.tint_root);
  EXPECT_EQ(lum.fin_luminance.tint_slope, full.fin_luminance.tint_slope);
  ASSERT_EQ(lum.strands.size(), full.strands.size());
  for (size_t k = 0; k < lum.strands.size(); ++k) {
    EXPECT_EQ(lum.strands[k].root_x, full.strands[k].root_x);
    EXPECT_EQ(lum.strands[k].root_y, full.strands[k].root_y);
    EXPECT_EQ(lum.strands[k].brightness, full.strands[k].brightness);
  }
  const StrandTextures harness = match_llvmpipe_textures(), harness_lum = match_llvmpipe_textures(ShellForms::LuminanceOnly);
  EXPECT_TRUE(harness_lum.shells.rgba.empty());
  EXPECT_EQ(harness_lum.shell_luminance.la, harness.shell_luminance.la);
  EXPECT_EQ(harness_lum.shell_luminance.tint, harness.shell_luminance.tint);
  EXPECT_EQ(harness_lum.fin.rgba, harness.fin.rgba);
  EXPECT_EQ(harness_lum.fin_luminance.la, harness.fin_luminance.la);
}

TEST(StrandTextures, AlphaFallsFromRootToTipAlongEachStrand) {
  FurParams p;
  p.texture_size = 256;
  p.density = 3.0f;  // sparse, so most strands are alone
  p.seed = 9;
  const StrandTextures t = grow(p);
  const int S = p.shells, N = p.texture_size;
  size_t exact = 0, total = 0, slanted = 0;
  for (const ShellStrand& st : t.strands) {
    EXPECT_GE(st.seed.y, 2.0f);  // large up component
    float prev_alpha = 2.0f;
    int x0, y0, xs, ys;
    strand_texel(st, 0, S, N, x0, y0);
    EXPECT_EQ(x0, st.root_x);
    EXPECT_EQ(y0, st.root_y);
    for (int s = 0; s < S; ++s) {
      const float h = float(s) / float(S - 1);
      const float a = strand_alpha(st, h);
      if (a <= 0.0f) {
        EXPECT_GT(h, st.length);
        continue;
      }
      EXPECT_LT(a, prev_alpha);
      prev_alpha = a;
      int x, y;
      strand_texel(st, s, S, N, x, y);
      const uint8_t tex_a = t.shells.texel(s, x, y)[3];
      EXPECT_GE(tex_a, to8(a));  // the largest alpha wins where strands meet
      exact += tex_a == to8(a);
      ++total;
    }
    strand_texel(st, S - 1, S, N, xs, ys);
    slanted += (xs != x0 || ys != y0);
  }
  EXPECT_GT(double(exact) / double(total), 0.9);
  EXPECT_GT(slanted, t.strands.size() / 2);  // strands slant with their seed vectors
  // Over the whole texture: mean strand alpha per layer falls from root to tip, and fewer
  // strands reach the upper layers.
  double prev_mean = 256.0;
  size_t first_count = 0;
  for (int s = 0; s < S; ++s) {
    double sum = 0;
    size_t n = 0;
    const uint8_t* l = t.shells.layer(s);
    for (size_t k = 0; k < size_t(N) * N; ++k)
      if (l[4 * k + 3]) sum += l[4 * k + 3], ++n;
    ASSERT_GT(n, 0u);
    EXPECT_LT(sum / n, prev_mean) << "layer " << s;
    prev_mean = sum / n;
    if (s == 0) first_count = n;
    if (s == S - 1) {
      EXPECT_LT(n, first_count / 3);  // lengths in [0.6, 1]: a fifth of the strands reach the top
    }
  }
}

// Re-slicing the same fur into more layers (quality `shells` over a scene's count) keeps each
// strand's optical depth, the sum of -ln(1 - alpha) over the layers it crosses; without the
// rescale, 64 layers would stack about four times the opacity of 16.
TEST(StrandTextures, ResliceKeepsEachStrandsOpticalDepth) {
  auto depth_per_strand = [](const FurParams& p) {
    const StrandTextures t = grow(p);
    const int S = p.shells, N = p.texture_size;
    double sum = 0.0;
    for (const ShellStrand& st : t.strands)
      for (int s = 1; s < S; ++s) {  // layer 0 is opaque at every count (alpha 1 at the root)
        int x, y;
        strand_texel(st, s, S, N, x, y);
        const double a = t.shells.texel(s, x, y)[3] / 255.0;
        sum += -std::log(1.0 - a);  // transmittance multiplies, optical depth adds
      }
    return sum / double(t.strands.size());
  };
  FurParams p;
  p.texture_size = 128;
  p.density = 2.0f;  // sparse: strands rarely share a texel
  p.seed = 4;
  const double authored = depth_per_strand(p);
  FurParams fine = p;
  fine.shells = 64;
  const double stacked = depth_per_strand(fine);
  fine.authored_shells = p.shells;
  const double resliced = depth_per_strand(fine);
  FurParams coarse = p;
  coarse.shells = 8;
  coarse.authored_shells = p.shells;
  const double coarser = depth_per_strand(coarse);
  std::printf("optical depth per strand: 16 layers %.4f, 64 resliced %.4f, 8 resliced %.4f, "
              "64 stacked %.4f\n", authored, resliced, coarser, stacked);
  // The layer sums are Riemann sums of -ln(1 - a(h)) with a(h) = 1 - 0.8 h / length, whose log
  // singularity at the root makes them converge slowly (measured: 8 layers -13 %, 64 layers
  // +12 % against 16); stacking without the rescale is off by 4.7x.
  EXPECT_NEAR(resliced / authored, 1.0, 0.15);
  EXPECT_NEAR(coarser / authored, 1.0, 0.15);
  EXPECT_LT(coarser, authored);
  EXPECT_LT(authored, resliced);
  EXPECT_GT(stacked / authored, 3.0);
  // The authored count itself is untouched, byte for byte.
  FurParams same = p;
  same.authored_shells = p.shells;
  EXPECT_EQ(grow(same).shells.rgba, grow(p).shells.rgba);
}

TEST(StrandTextures, ColourRunsFromRootToTip) {
  FurParams p;
  p.texture_size = 64;
  p.root_color = {0.0f, 0.0f, 1.0f};
  p.tip_color = {1.0f, 0.0f, 0.0f};
  const StrandTextures t = grow(p);
  // Empty texels carry the layer colour (brightness 1) so filtering stays in colour.
  const uint8_t* bottom = t.shells.layer(0);
  const uint8_t* top = t.shells.layer(p.shells - 1);
  for (size_t k = 0; k < 64 * 64; ++k) {
    if (bottom[4 * k + 3] == 0) {
      EXPECT_EQ(bottom[4 * k + 0], 0);
      EXPECT_EQ(bottom[4 * k + 2], 255);
    }
    if (top[4 * k + 3] == 0) {
      EXPECT_EQ(top[4 * k + 0], 255);
      EXPECT_EQ(top[4 * k + 2], 0);
    }
  }
}

TEST(StrandTextures, FinShowsStrandsFromTheSide) {
  FurParams p;
  p.texture_size = 128;
  p.density = 30.0f;
  const StrandTextures t = grow(p);
  const int N = 128;
  auto row_stats = [&](int y, double& mean, size_t& count) {
    double sum = 0;
    count = 0;
    for (int x = 0; x < N; ++x) {
      const uint8_t a = t.fin.texel(0, x, y)[3];
      if (a) sum += a, ++count;
    }
    mean = count ? sum / count : 0.0;
  };
  double m0, m_mid, m_top;
  size_t c0, c_mid, c_top;
  row_stats(0, m0, c0);
  row_stats(N / 2, m_mid, c_mid);
  row_stats(N - 1, m_top, c_top);
  EXPECT_GT(c0, size_t(N / 4));  // roots along the bottom row
  EXPECT_GT(m0, m_mid);          // alpha fades toward the tip
  // A fifth of the strands reach the top row.
  EXPECT_GT(c_top, 0u);
  EXPECT_LT(c_top, c0 / 2);
  EXPECT_GT(c_mid, c_top);
}

// strand_textures.h: a fin strand is a line from its root column leaning by up to 0.1 * size
// over the fin height. With one fin strand per texture (density 0.4 at size 64) each row holds
// one texel of it, moving at most a column a row; over a few seeds some strand must lean
// (a uniform lean of several columns is rarely near zero). Kills the lean dropped (vertical strands).
TEST(StrandTextures, FinStrandsLeanWithinATenthOfTheSize) {
  const int N = 64;
  int widest = 0;
  for (uint32_t seed = 1; seed <= 8; ++seed) {
    FurParams p;
    p.texture_size = N;
    p.density = 0.4f;  // round(0.004 * 64 * kFinDepthTexels) = 1 fin strand
    p.seed = seed;
    const StrandTextures t = grow(p);
    std::vector<int> column;
    for (int y = 0; y < N; ++y) {
      std::vector<int> xs;
      for (int x = 0; x < N; ++x)
        if (t.fin.texel(0, x, y)[3] > 0) xs.push_back(x);
      if (xs.empty()) break;  // above the strand's tip
      ASSERT_EQ(xs.size(), 1u) << "seed " << seed << " row " << y;
      column.push_back(xs[0]);
    }
    ASSERT_GE(column.size(), size_t(0.6 * N) - 1) << "seed " << seed;  // length >= 0.6
    auto step = [&](int from, int to) {  // signed column change, wrapped (u repeats)
      int d = (to - from) % N;
      if (d > N / 2) d -= N;
      if (d < -N / 2) d += N;
      return d;
    };
    for (size_t y = 1; y < column.size(); ++y) EXPECT_LE(std::abs(step(column[y - 1], column[y])), 1) << "seed " << seed;
    const int shift = step(column.front(), column.back());
    EXPECT_LE(std::abs(shift), int(std::ceil(0.1 * N)) + 1) << "seed " << seed;
    widest = std::max(widest, std::abs(shift));
  }
  EXPECT_GE(widest, 2);
}

// strand_textures.h: at height h a strand's texel is offset from its root by
// (seed.x, seed.z) / seed.y * h * shell_volume_height, x and z independently (a strand leans
// along its own direction; y being Y-up height). Kills x/z mixed up and * seed.y for / seed.y.
TEST(StrandTextures, AStrandLeansByItsSeedOverItsHeight) {
  ShellStrand st;
  st.root_x = 10;
  st.root_y = 20;
  st.seed = {0.5f, 2.0f, -1.0f};
  const int size = 256, layers = 5;
  ASSERT_EQ(shell_volume_height(size), 16);
  struct Want {
    int s, x, y;
  };
  // h = s / 4; offset = (0.25, -0.5) * h * 16 = (4 h, -8 h).
  for (const Want w : {Want{0, 10, 20}, Want{1, 11, 18}, Want{2, 12, 16}, Want{4, 14, 12}}) {
    int x = -1, y = -1;
    strand_texel(st, w.s, layers, size, x, y);
    EXPECT_EQ(x, w.x) << "layer " << w.s;
    EXPECT_EQ(y, w.y) << "layer " << w.s;
  }
  // The offset wraps around the texture, as the texture repeats over the surface.
  st.root_x = 254;
  st.root_y = 3;
  int x = -1, y = -1;
  strand_texel(st, 4, layers, size, x, y);
  EXPECT_EQ(x, 2);    // 254 + 4
  EXPECT_EQ(y, 251);  // 3 - 8
}

TEST(StrandTextures, RejectsBadParams) {
  FurParams p;
  p.texture_size = 300;
  StrandTextures t;
  auto e = generate_strand_textures(p, t);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "texture_size");
}

// Spot checks against the llvmpipe README's formulas, recomputed here from its words.
TEST(StrandTextures, MatchLlvmpipeReproducesTheHarnessFormulas) {
  const StrandTextures t = match_llvmpipe_textures();
  ASSERT_EQ(t.shells.size, 256);
  ASSERT_EQ(t.shells.layers, 16);
  ASSERT_EQ(t.fin.size, 256);
  const float fur[3] = {0.80f, 0.58f, 0.36f};
  std::mt19937 gen(2008);
  auto next = [&] { return double(gen()) / 4294967296.0; };
  // Texels are generated row by row; check the first 300 texels of row 0 and 1 fully.
  size_t strands = 0;
  for (int k = 0; k < 300; ++k) {
    const int x = k % 256, y = k / 256;
    const bool strand = next() < 0.30;
    const float bright = float(0.75 + 0.5 * next());
    strands += strand;
    for (int s : {0, 7, 15}) {
      const float f = float(s) / 15.0f;
      const uint8_t* p = t.shells.texel(s, x, y);
      const float shade = (0.45f + 0.55f * f) * (strand ? bright : 1.0f);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], to8(fur[c] * shade)) << k << " " << s;
      EXPECT_EQ(p[3], strand ? to8(1.0f - 0.8f * f) : 0) << k << " " << s;
    }
  }
  EXPECT_GT(strands, 60u);
  EXPECT_LT(strands, 120u);
  // About 30% strand roots overall; alpha 1.0 -> 0.2 from layer 0 to 15.
  const double frac = double(covered(t.shells, 0)) / (256.0 * 256.0);
  EXPECT_NEAR(frac, 0.30, 0.01);
  EXPECT_EQ(covered(t.shells, 0), covered(t.shells, 15));
  std::mt19937 fgen(7600);
  auto fnext = [&] { return double(fgen()) / 4294967296.0; };
  for (int x = 0; x < 20; ++x) {
    const bool strand = fnext() < 0.30;
    const float bright = float(0.75 + 0.5 * fnext());
    const float len = float(0.6 + 0.4 * fnext());
    for (int y : {0, 100, 160, 200, 255}) {
      const float v = (y + 0.5f) / 256.0f;
      const uint8_t* p = t.fin.texel(0, x, y);
      const float shade = (0.45f + 0.55f * v) * (strand ? bright : 1.0f);
      EXPECT_EQ(p[0], to8(fur[0] * shade));
      EXPECT_EQ(p[3], (strand && v <= len) ? to8(1.0f - 0.8f * v) : 0) << x << " " << y;
    }
  }
}

}  // namespace
}  // namespace pelt::fur
