// The translucent pass packs the lanes of several triangles of one draw into one block:
// triangles sharing an edge for a shader with derivatives, any disjoint ones otherwise. Packing
// must not change a pixel's blend order or any lane's values, and the tile sort must keep a
// quad's two triangles together so that it can pack them at all.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/frame.h"
#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace translucent_packing_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

constexpr int kSize = 160;
constexpr int kCells = 5;
constexpr int kLayers = 4;
constexpr float kAlpha = 0.5f;
const glm::vec4 kBackground(0.05f, 0.1f, 0.2f, 1.0f);

// A translucent (src-over, no depth write) draw of indexed triangles with 3 varyings a vertex.
DrawCall translucent_draw(const std::vector<glm::vec3>& pos, const std::vector<uint32_t>& idx,
                          const std::vector<float>& var, uint32_t varying_count, const glm::mat4& clip,
                          const Shader& sh) {
  DrawCall d;
  d.positions = pos.data();
  d.vertex_count = uint32_t(pos.size());
  d.indices = idx.data();
  d.triangle_count = uint32_t(idx.size() / 3);
  d.varyings = var.empty() ? nullptr : var.data();
  d.varying_count = varying_count;
  d.clip_from_object = clip;
  d.state.blend = BlendMode::AlphaOver;
  d.state.depth_write = false;
  d.shader = &sh;
  return d;
}

glm::vec3 layer_colour(int layer) { return {0.2f + 0.2f * layer, 0.9f - 0.15f * layer, 0.3f + 0.1f * (layer % 2)}; }

// kLayers parallel tilted grids of jittered quads, farthest first, in one draw like fur
// shells: cell (i, j) of layer L is the triangles (v00, v10, v11) and (v00, v11, v01), which
// share their diagonal. The tilt spans more depth within a quad than the layer spacing, so
// per-triangle depths of neighbouring layers interleave. `shared`: the quads' triangles
// share vertex indices; otherwise every triangle has its own copies (same positions).
// `strips`: each row of cells is a strip instead, (v00, v10, v01) and (v10, v11, v01), so that
// every triangle shares an edge with the one before it along the row (like a fur fin's quads).
struct Grid {
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  std::vector<glm::vec3> centroid;  // per triangle, for picking interior pixels
  std::vector<int> layer;           // per triangle

  explicit Grid(bool shared, bool strips = false) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
    glm::vec2 xy[kCells + 1][kCells + 1];
    for (int j = 0; j <= kCells; ++j)
      for (int i = 0; i <= kCells; ++i) {
        const bool inner = i > 0 && j > 0 && i < kCells && j < kCells;
        xy[j][i] = glm::vec2(-2.0f + 0.8f * i + (inner ? jitter(rng) : 0.0f), -2.0f + 0.8f * j + (inner ? jitter(rng) : 0.0f));
      }
    for (int L = kLayers - 1; L >= 0; --L) {
      auto vertex = [&](int i, int j) {
        const glm::vec2 p = xy[j][i];
        pos.push_back({p.x, p.y, -6.0f - 0.05f * L + 0.4f * p.x + 0.25f * p.y});
        const glm::vec3 c = layer_colour(L);
        var.insert(var.end(), {c.r, c.g, c.b});
        return uint32_t(pos.size() - 1);
      };
      uint32_t grid[kCells + 1][kCells + 1];
      if (shared)
        for (int j = 0; j <= kCells; ++j)
          for (int i = 0; i <= kCells; ++i) grid[j][i] = vertex(i, j);
      for (int j = 0; j < kCells; ++j)
        for (int i = 0; i < kCells; ++i) {
          const int quad[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
          const int strip[2][3][2] = {{{0, 0}, {1, 0}, {0, 1}}, {{1, 0}, {1, 1}, {0, 1}}};
          for (const auto& tri : strips ? strip : quad) {
            glm::vec3 c(0.0f);
            for (const auto& k : tri) {
              const uint32_t v = shared ? grid[j + k[1]][i + k[0]] : vertex(i + k[0], j + k[1]);
              idx.push_back(v);
              c += pos[v] / 3.0f;
            }
            centroid.push_back(c);
            layer.push_back(L);
          }
        }
    }
  }

  DrawCall draw(const Shader& sh) const {
    return translucent_draw(pos, idx, var, 3,
                            glm::perspective(glm::radians(45.0f), 1.0f, 1.0f, 20.0f) *
                                glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -1.2f)),
                            sh);
  }
};

RenderOptions options(SortMode sort) {
  RenderOptions o;
  o.background = kBackground;
  o.sort = sort;
  return o;
}

// The pixel under a world point.
glm::ivec2 pixel_of(const DrawCall& d, glm::vec3 p) {
  const glm::vec4 c = d.clip_from_object * glm::vec4(p, 1.0f);
  return {int((c.x / c.w * 0.5f + 0.5f) * kSize), int((0.5f - 0.5f * c.y / c.w) * kSize)};
}

// Every layer composited back to front over the background, in double.
glm::dvec4 expected_colour() {
  glm::dvec4 e(kBackground);
  for (int L = kLayers - 1; L >= 0; --L)
    e = glm::dvec4(glm::dvec3(layer_colour(L)) * double(kAlpha) + glm::dvec3(e) * (1.0 - kAlpha),
                   kAlpha + e.a * (1.0 - kAlpha));
  return e;
}

TEST(TranslucentPacking, AQuadsTrianglesShareBlocksWithoutChangingAPixel) {
  const VaryingShader sh(kAlpha, /*derivatives=*/true);
  const Grid shared(true), separate(false);
  const DrawCall ds = shared.draw(sh), dp = separate.draw(sh);
  const glm::dvec4 expect = expected_colour();
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
      const std::string what = target + " sort " + std::to_string(int(sort));
      const Image packed = render({&ds, 1}, kSize, kSize, 2, options(sort));
      const Image apart = render({&dp, 1}, kSize, kSize, 2, options(sort));
      EXPECT_EQ(packed.stats.fragments_blended, apart.stats.fragments_blended) << what;
      // Every lane is still computed from its own triangle's planes, and no pixel blends
      // twice or out of order.
      if (sort != SortMode::Tile) {
        EXPECT_EQ(0, std::memcmp(packed.color.data(), apart.color.data(), packed.color.size() * 4)) << what;
      }
      // Interior pixels (each triangle's centroid, where all layers cover it with the same
      // cell) composite to the closed form in every mode, the tile sort included.
      for (size_t t = 0; t < shared.centroid.size(); ++t) {
        const glm::ivec2 p = pixel_of(ds, shared.centroid[t]);
        for (int c = 0; c < 4; ++c)
          ASSERT_NEAR(packed.color[(size_t(p.y) * kSize + size_t(p.x)) * 4 + c], expect[c], 1e-5)
              << what << " triangle " << t << " pixel " << p.x << "," << p.y;
      }
      // Shared edges let a quad's triangles fill a block together; without them every
      // triangle takes its own slot. In the tile sort this needs the two halves of a quad to
      // sort next to each other, although other layers' triangles lie between their depths.
      EXPECT_LT(double(packed.stats.lanes_shaded), 0.9 * double(apart.stats.lanes_shaded)) << what;
    }
  });
}

// A strip keyed as one run (DrawCall::sort_group) sorts as one primitive: its quads follow each
// other in the tile sort, although other layers' quads lie between their depths, and pack
// into shared blocks; the layers still composite in order.
TEST(TranslucentPacking, AStripKeyedAsOneRunPacksAcrossItsQuads) {
  const VaryingShader sh(kAlpha, /*derivatives=*/true);
  const Grid strips(true, true);
  DrawCall quads = strips.draw(sh), rows = strips.draw(sh);
  rows.sort_group = 2 * kCells;
  const glm::dvec4 expect = expected_colour();
  for_each_target([&](const std::string& target) {
    const Image by_quad = render({&quads, 1}, kSize, kSize, 2, options(SortMode::Tile));
    const Image by_row = render({&rows, 1}, kSize, kSize, 2, options(SortMode::Tile));
    EXPECT_EQ(by_quad.stats.fragments_blended, by_row.stats.fragments_blended) << target;
    for (const Image* img : {&by_quad, &by_row})
      for (size_t t = 0; t < strips.centroid.size(); ++t) {
        const glm::ivec2 p = pixel_of(rows, strips.centroid[t]);
        for (int c = 0; c < 4; ++c)
          ASSERT_NEAR(img->color[(size_t(p.y) * kSize + size_t(p.x)) * 4 + c], expect[c], 1e-5)
              << target << " triangle " << t << " pixel " << p.x << "," << p.y;
      }
    EXPECT_LT(double(by_row.stats.lanes_shaded), 0.95 * double(by_quad.stats.lanes_shaded)) << target;
  });
}

// A run whose triangles do not share edges one after the other is no strip: each of its
// triangles sorts by its own depth. Triangles 0 and 1 (one run of 2) are a far green triangle
// over the centre and a near one off screen, whose mean depth lies in front of the red
// triangle 2 over the centre; by their own depths the green one lies behind the red.
// Sharing one vertex is not sharing an edge: a fan's triangles around a vertex are no strip
// (DrawCall::sort_group keys a run together only when each triangle shares an EDGE with the one
// before) and do not differentiate as one field. Kills shared >= 2 -> >= 1 (frame.h).
TEST(TranslucentPacking, TrianglesShareAnEdgeOnlyWithTwoVerticesInCommon) {
  const uint32_t t[3] = {0, 1, 2};
  const uint32_t edge[3] = {2, 1, 7}, edge_rotated[3] = {7, 0, 2}, vertex[3] = {2, 8, 9}, none[3] = {3, 4, 5};
  EXPECT_TRUE(triangles_share_edge(t, edge));
  EXPECT_TRUE(triangles_share_edge(t, edge_rotated));
  EXPECT_TRUE(triangles_share_edge(t, t));
  EXPECT_FALSE(triangles_share_edge(t, vertex));
  EXPECT_FALSE(triangles_share_edge(vertex, t));
  EXPECT_FALSE(triangles_share_edge(t, none));
}

TEST(TranslucentPacking, ARunThatIsNotAChainSortsItsTrianglesByTheirOwnDepths) {
  std::vector<glm::vec3> pos = {{-3, -3, -8}, {3, -3, -8}, {0, 3, -8},      {-60, 0, -2}, {-59, 0, -2},
                                {-60, 1, -2}, {-1, -1, -5.5f}, {1, -1, -5.5f}, {0, 1, -5.5f}};
  std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<float> var;  // green, then red
  for (size_t v = 0; v < pos.size(); ++v) var.insert(var.end(), {v >= 6 ? 1.0f : 0.0f, v < 6 ? 1.0f : 0.0f, 0.0f});
  const VaryingShader sh(0.5f);
  const DrawCall d = translucent_draw(pos, idx, var, 3, glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f), sh);
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, 64, 64, 1, options(SortMode::Tile));
    const size_t centre = (size_t(32) * 64 + 32) * 4;
    // Back to front: green first, then red over it.
    EXPECT_NEAR(img.color[centre], 0.5f + kBackground.r * 0.25f, 1e-5) << target;
    EXPECT_NEAR(img.color[centre + 1], 0.25f + kBackground.g * 0.25f, 1e-5) << target;
  });
}

// A draw's own keys (DrawCall::sort_keys) order the tile sort in place of depth: keyed the
// other way round, the near red triangle is drawn first and the far green one over it; no
// other order consults them.
TEST(TranslucentPacking, TheCallersKeysOrderTheTileSortInsteadOfDepth) {
  const std::vector<glm::vec3> pos = {{-3, -3, -8}, {3, -3, -8}, {0, 3, -8}, {-1, -1, -5.5f}, {1, -1, -5.5f}, {0, 1, -5.5f}};
  const std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5};
  std::vector<float> var;  // green, then red
  for (size_t v = 0; v < pos.size(); ++v) var.insert(var.end(), {v >= 3 ? 1.0f : 0.0f, v < 3 ? 1.0f : 0.0f, 0.0f});
  const VaryingShader sh(0.5f);
  DrawCall d = translucent_draw(pos, idx, var, 3, glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f), sh);
  const float keys[2] = {1.0f, 2.0f};  // red (triangle 1) farther
  d.sort_keys = keys;
  const size_t centre = (size_t(32) * 64 + 32) * 4;
  for_each_target([&](const std::string& target) {
    const Image tile = render({&d, 1}, 64, 64, 1, options(SortMode::Tile));
    EXPECT_NEAR(tile.color[centre], 0.25f + kBackground.r * 0.25f, 1e-5) << target;  // red, then green over it
    EXPECT_NEAR(tile.color[centre + 1], 0.5f + kBackground.g * 0.25f, 1e-5) << target;
    const Image none = render({&d, 1}, 64, 64, 1, options(SortMode::None));  // submission order
    EXPECT_NEAR(none.color[centre], 0.5f + kBackground.r * 0.25f, 1e-5) << target;
    EXPECT_NEAR(none.color[centre + 1], 0.25f + kBackground.g * 0.25f, 1e-5) << target;
  });
}

// Without derivatives any triangles of the draw whose lanes are disjoint share a block:
// overlapping translucent triangles in a random soup must still blend each pixel in
// submission (or sorted) order, exactly as one slot per triangle does.
TEST(TranslucentPacking, PackedAndPerTriangleBlendingAgree) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 c(u(rng) * 3.0f, u(rng) * 3.0f, -5.0f + u(rng) * 2.0f);
    const glm::vec3 colour(0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng), 0.5f + 0.5f * u(rng));
    for (int k = 0; k < 3; ++k) {
      pos.push_back(c + 0.5f * glm::vec3(u(rng), u(rng), u(rng)));
      var.insert(var.end(), {colour.r, colour.g, colour.b});
      idx.push_back(uint32_t(pos.size() - 1));
    }
  }
  const VaryingShader packed(0.4f, false), per_triangle(0.4f, true);
  DrawCall d = translucent_draw(pos, idx, var, 3, glm::perspective(glm::radians(60.0f), 4.0f / 3.0f, 0.5f, 20.0f), packed);
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile, SortMode::Exact}) {
      const std::string what = target + " sort " + std::to_string(int(sort));
      d.shader = &packed;
      const Image p = render({&d, 1}, 200, 150, 2, options(sort));
      d.shader = &per_triangle;
      const Image q = render({&d, 1}, 200, 150, 2, options(sort));
      EXPECT_EQ(0, std::memcmp(p.color.data(), q.color.data(), p.color.size() * 4)) << what;
      EXPECT_EQ(p.stats.fragments_blended, q.stats.fragments_blended) << what;
      EXPECT_LT(p.stats.lanes_shaded, q.stats.lanes_shaded) << what;
    }
  });
}

// Writes, per lane, the mean horizontal difference of varying 0 along the lane's block row
// (what a texture LOD estimate reads) to red, and alpha 1.
class RowDifferenceShader final : public Shader {
 public:
  void shade(const FragmentBatch& b) const override {
    const size_t lanes = size_t{b.blocks} * kBlockLanes;
    for (size_t i = 0; i < lanes; ++i) {
      const size_t row = i / 4 * 4;
      b.out[0][i] = (b.varying[0][row + 3] - b.varying[0][row]) / 3.0f;
      b.out[1][i] = b.out[2][i] = 0.0f;
      b.out[3][i] = 1.0f;
    }
  }
};

// Small disjoint triangles, many to a block, each with its own gradient of varying 0: a shader
// with derivatives must see, in every block, lanes of one triangle only (they share no
// edge), exactly as when each triangle is its own draw.
TEST(TranslucentPacking, TrianglesWithoutASharedEdgeNeverShareADifferentiatedBlock) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> g(-4.0f, 4.0f), jitter(0.0f, 0.05f);
  std::vector<glm::vec3> pos;
  std::vector<float> var;
  std::vector<uint32_t> idx;
  const int n = 24;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = -1.0f + 2.0f * i / n, y = -1.0f + 2.0f * j / n, s = 2.0f / n;
      const float gradient = g(rng);
      for (glm::vec2 c : {glm::vec2(0.1f, 0.1f), glm::vec2(0.9f, 0.15f), glm::vec2(0.2f, 0.85f)}) {
        pos.push_back({x + (c.x + jitter(rng)) * s, y + (c.y + jitter(rng)) * s, -2.0f});
        var.push_back(gradient * pos.back().x);
        idx.push_back(uint32_t(pos.size() - 1));
      }
    }
  const RowDifferenceShader sh;
  const DrawCall d = translucent_draw(pos, idx, var, 1, glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.5f, 5.0f), sh);
  std::vector<DrawCall> each;
  for (uint32_t t = 0; t < d.triangle_count; ++t) {
    DrawCall e = d;
    e.indices = idx.data() + 3 * size_t{t};
    e.triangle_count = 1;
    each.push_back(e);
  }
  for_each_target([&](const std::string& target) {
    for (SortMode sort : {SortMode::None, SortMode::Tile}) {
      const Image one = render({&d, 1}, 128, 128, 2, options(sort));
      const Image apart = render(each, 128, 128, 2, options(sort));
      EXPECT_EQ(0, std::memcmp(one.color.data(), apart.color.data(), one.color.size() * 4))
          << target << " sort " << int(sort);
    }
  });
}

// A quad whose partner triangle has a NaN vertex: the partner is culled, the other half
// keeps its own sort key (no NaN reaches the sort) and is sorted behind the small triangle
// submitted before it. Triangle 1 lies off screen and pairs with nothing.
TEST(TranslucentPacking, QuadWithANonFinitePartnerSortsByItsOwnDepth) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<glm::vec3> pos = {{-2, -2, -5}, {2, -2, -5}, {2, 2, -5}, {-2, 2, nan}, {-1, -1, -4}, {1, -1, -4}, {0, 1, -4},
                                {-100, 0, -5}, {-99, 0, -5}, {-100, 1, -5}};
  std::vector<uint32_t> idx = {4, 5, 6, 7, 8, 9, 0, 1, 2, 0, 2, 3};
  std::vector<float> var;  // the quad green, the small triangle red
  for (size_t v = 0; v < pos.size(); ++v) var.insert(var.end(), {v >= 4 ? 1.0f : 0.0f, v < 4 ? 1.0f : 0.0f, 0.0f});
  const VaryingShader sh(0.5f);
  const DrawCall d = translucent_draw(pos, idx, var, 3, glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 20.0f), sh);
  DrawCall alone = d;
  alone.triangle_count = 1;
  for_each_target([&](const std::string& target) {
    const Image img = render({&d, 1}, 64, 64, 1, options(SortMode::Tile));
    const Image one = render({&alone, 1}, 64, 64, 1, options(SortMode::Tile));
    EXPECT_EQ(img.stats.triangles_culled, 2u) << target;
    // The valid half of the quad is drawn besides the small triangle.
    EXPECT_GT(img.stats.fragments_blended, one.stats.fragments_blended) << target;
    for (float c : img.color) ASSERT_TRUE(std::isfinite(c)) << target;
    const size_t centre = (size_t(40) * 64 + 36) * 4;  // inside the small triangle and the quad's half
    // Back to front: the quad's half (green) first, then the small triangle (red) over it.
    EXPECT_NEAR(img.color[centre], 0.5f + kBackground.r * 0.25f, 1e-5) << target;
    EXPECT_NEAR(img.color[centre + 1], 0.25f + kBackground.g * 0.25f, 1e-5) << target;
  });
}

}  // namespace translucent_packing_test
}  // namespace pelt::raster::test
