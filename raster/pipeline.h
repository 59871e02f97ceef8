// What a caller hands the rasterizer: draw calls (indexed triangles, per-vertex
// varyings, a clip-space transform, fixed-function state) and the Shader interface that
// turns interpolated fragments into colour. The rasterizer knows nothing of what the
// varyings mean.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "raster/config.h"

namespace pelt::raster {

enum class DepthFunc : uint8_t { Less, LessEqual, Always };
enum class CullMode : uint8_t { None, Back, Front };  // front = counter-clockwise in NDC (OpenGL)
enum class BlendMode : uint8_t {
  Opaque,
  // src-over of a shader's straight colour onto premultiplied planes: C = Cs a + Cd (1 - a),
  // A = a + Ad (1 - a); the planes stay premultiplied (associated) when they start so
  // (RenderOptions::background), which is what lets samples average and images composite.
  AlphaOver,
  Additive,   // C = Cd + Cs a, A = Ad: counts overdraw, glows
};

// Opaque draws fill a visibility buffer (depth + primitive) and are shaded once per
// visible pixel after all opaque geometry of a tile is known. AlphaOver draws come after,
// depth-tested against the opaque depth, shaded per fragment and blended src-over
// (straight alpha; or added) in their order: submission order, or back to front per tile.
struct PipelineState {
  DepthFunc depth_func = DepthFunc::Less;
  bool depth_write = true;
  CullMode cull = CullMode::None;
  BlendMode blend = BlendMode::Opaque;
  // Opaque draws: a fragment whose shaded alpha is below alpha_cutoff (or NaN) is discarded
  // before the depth test writes, so a cut-out (a leaf, an eyelash card) hides what lies
  // behind it only where it is drawn; a kept fragment is stored opaque (alpha 1). Such a
  // draw is shaded twice: for its alpha where it passes the depth test, and again, as every
  // opaque draw, where it is visible. After every draw without it (the tile's opaque
  // triangles first, then the alpha-tested ones in submission order): under DepthFunc::Less
  // two surfaces at one depth keep the plain opaque one (under LessEqual or Always, the
  // alpha-tested one). Opaque draws only: refused on a blended one.
  bool alpha_test = false;
  float alpha_cutoff = 0.5f;
};

// A batch of fragments of ONE draw, in whole 4x4 blocks. Lane l of a block is pixel
// (block_x + l % 4, block_y + l / 4). Lanes outside `mask` hold the block's first
// triangle's planes extrapolated (finite, usable for derivatives) and their outputs are
// ignored; for a shader that uses no derivatives they hold finite values of some triangle
// of the draw. A block's covered lanes come from one triangle, or (translucent draws) from
// triangles each sharing an edge, i.e. two vertex indices, with the one before it, so
// varyings are one continuous field across the block; a shader without derivatives may see
// any triangles of the draw in one block. A block holds at most one fragment per pixel.
// All per-lane arrays hold 16 * blocks floats, 64-byte aligned.
struct FragmentBatch {
  uint32_t blocks = 0;
  const uint16_t* mask = nullptr;     // per block: bit l = lane l covered
  const int32_t* block_x = nullptr;   // per block: pixel x of lane 0
  const int32_t* block_y = nullptr;   // per block: pixel y of lane 0
  const uint32_t* primitive = nullptr;  // per lane: triangle index within the draw
  const float* varying[kMaxVaryings] = {};  // per lane, perspective-correct
  const float* depth = nullptr;       // per lane, window depth in [0, 1]
  float* out[4] = {};                 // per lane: the shader writes linear r, g, b, a
};

class Shader {
 public:
  virtual ~Shader() = default;
  // Called per worker thread, per batch, possibly concurrently from several threads:
  // must not modify shared state. Writes out[0..3] for all 16 * blocks lanes.
  virtual void shade(const FragmentBatch& batch) const = 0;
  // True when the shader differentiates varyings across a block (texture LOD): then the
  // lanes of a block come from its one triangle (extrapolated where uncovered), or from
  // triangles joined by shared edges (translucent draws, see FragmentBatch). Otherwise
  // the visible pixels of any triangles of the draw may share a block, which shades fewer
  // lanes.
  virtual bool uses_derivatives() const { return true; }
};

struct DrawCall {
  const glm::vec3* positions = nullptr;  // object space
  uint32_t vertex_count = 0;
  const uint32_t* indices = nullptr;     // 3 per triangle
  uint32_t triangle_count = 0;
  const float* varyings = nullptr;       // varying_count floats per vertex, interleaved
  uint32_t varying_count = 0;
  glm::mat4 clip_from_object{1.0f};
  PipelineState state;
  const Shader* shader = nullptr;
  // The id AOV of a pixel shows id_base + triangle index + 1 of its visible opaque triangle,
  // or id_base + triangle_ids[triangle index] + 1 where the caller numbers the triangles (a
  // draw of some of a mesh's triangles, numbered as in the whole mesh).
  uint32_t id_base = 0;
  const uint32_t* triangle_ids = nullptr;
  // Translucent draws: the tile sort keys each run of sort_group consecutive triangles (0 ..
  // sort_group - 1, then the next run) by the run's mean view depth, so the run sorts as one
  // primitive and the tiles pack its triangles into shared blocks; quads (2, the default) and
  // strips of quads. A run keeps the shared key only when all its triangles are valid and each
  // shares an edge with the one before; otherwise each triangle sorts by its own mean depth, as
  // every triangle does with 1 (or 0). Blend order within a run is submission order.
  uint32_t sort_group = 2;
  // Translucent draws: the caller's own tile-sort key for every triangle (triangle_count of
  // them, larger = drawn earlier), in place of the mean view depth and sort_group's shared
  // keys; for orders that depth alone does not give (fur's `surface` sort keeps each layer
  // after the layers below it that it leans over). Triangles with equal keys keep submission
  // order. Opaque draws ignore it.
  const float* sort_keys = nullptr;
};

}  // namespace pelt::raster
