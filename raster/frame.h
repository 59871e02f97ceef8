// Internal plain data shared by the front end (renderer.cpp) and the tile kernels
// (tile_kernels.cc): binned triangles per chunk and per-worker tile scratch.
#pragma once

#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "raster/clip.h"
#include "raster/config.h"
#include "raster/renderer.h"
#include "raster/setup.h"

namespace pelt::raster {

// Triangles per front-end chunk: large enough to amortise a chunk's per-tile offsets,
// small enough to balance two workers on a 36k-triangle fur frame.
inline constexpr uint32_t kChunkTriangles = 1024;

// A set-up triangle's frame-wide id, as stored in the visibility buffer (and increasing in
// submission order): its chunk in the high bits and its index among the chunk's set-ups (clipping fans a triangle into at most
// kMaxClipVertices - 2) in the low ones, so a pixel finds its triangle with two loads.
inline constexpr uint32_t kSetupIndexBits = 13;
static_assert(kChunkTriangles * (kMaxClipVertices - 2) <= (1u << kSetupIndexBits));
inline constexpr size_t kMaxChunks = (kNoPrimitive >> kSetupIndexBits);  // kNoPrimitive stays free
inline uint32_t setup_id(size_t chunk, uint32_t local) {
  return static_cast<uint32_t>(chunk << kSetupIndexBits) | local;
}

// A vector whose resize() leaves new trivially constructible elements uninitialised: the
// front end grows its set-up list by a batch, lets the set-up kernel write the survivors
// and shrinks it again; value-initialising each batch was a tenth of the front end.
template <class T>
struct UninitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitAllocator<U>;
  };
  UninitAllocator() = default;
  template <class U>
  UninitAllocator(const UninitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// Triangles of consecutive submission order, set up and binned by one worker. Aligned so
// that two workers binning neighbouring chunks never write the same cache line pair (the
// vectors' end pointers and the counters change per triangle: sharing a line made two
// threads barely faster than one).
struct alignas(128) BinChunk {
  uint32_t draw = 0, first = 0, count = 0;  // triangles [first, first+count) of draw
  std::vector<TriSetup, UninitAllocator<TriSetup>> setups;
  std::vector<uint32_t> tile_offsets;       // tiles + 1
  std::vector<uint32_t> items;              // setup index within the chunk, by tile
  std::vector<uint64_t> pairs;              // scratch: (tile << 32) | item
  std::vector<uint32_t> tile_cursor;        // scratch: per tile, the next item's position
  SnappedBatch batch;                       // scratch: unclipped triangles awaiting set-up
  uint32_t batch_primitive[kSetupBatch];    //   and their triangle indices
  float batch_key[kSetupBatch];             //   and sort keys
  uint64_t culled = 0, clipped = 0;
};

struct FrameView {
  Viewport vp;
  int tiles_x = 0, tiles_y = 0;
  const DrawCall* draws = nullptr;
  const BinChunk* chunks = nullptr;
  size_t chunk_count = 0;
  const uint32_t* tile_load = nullptr;  // per tile: its bin items over every chunk
  RenderOptions options;
  RenderTarget target;
  // With target.color8: one tile row of the background as RGBA8 bytes (unorm8), made once a
  // frame and copied into each row of an empty tile.
  uint8_t background8[4 * kTileSize];
};

inline constexpr uint32_t kBatchBlocks = kMaxBatchBlocks;
inline constexpr uint32_t kBatchLanes = kMaxBatchLanes;

struct TranslucentRef {
  const TriSetup* tri;
  uint32_t id;     // setup_id
  float sort_key;  // tri->sort_key, copied so the tile sort compares without chasing pointers
};

// True when triangles a and b (three vertex indices each) share an edge: two indices. Such
// triangles interpolate one continuous field of varyings across that edge.
inline bool triangles_share_edge(const uint32_t* a, const uint32_t* b) {
  int shared = 0;
  for (int i = 0; i < 3; ++i) shared += int(a[i] == b[0]) + int(a[i] == b[1]) + int(a[i] == b[2]);
  return shared >= 2;
}

// Per-worker state, reused for every tile the worker takes. Tile planes are stored
// block-major: block (bx, by) of the tile at [(by * 16 + bx) * 16], lane l = pixel
// (l % 4, l / 4) of the block, so 16 lanes are one contiguous load.
struct alignas(64) TileScratch {
  alignas(64) float color[4][kTilePixels];
  alignas(64) float depth[kTilePixels];
  alignas(64) uint32_t vis[kTilePixels];  // setup_id of the visible triangle
  alignas(64) uint16_t block_valid[kBlocksPerTile];  // lanes inside the viewport
  alignas(64) uint32_t overdraw[kTilePixels];        // RenderTarget::overdraw's counts, when wanted

  // The batch being assembled for the shader: blocks of one draw.
  uint32_t batch_blocks = 0;
  uint32_t batch_draw = 0;
  alignas(64) uint16_t batch_mask[kBatchBlocks];
  alignas(64) int32_t batch_x[kBatchBlocks];
  alignas(64) int32_t batch_y[kBatchBlocks];
  alignas(64) uint16_t batch_offset[kBatchBlocks];  // block offset within the tile planes
  // Per slot, bit g: lanes [g N, g N + N) of the slot hold values (N = the target's lanes).
  // Packed opaque slots fill only the vector groups their triangles cover; the others are
  // copied from a filled one before shading, so every lane a shader sees is finite.
  alignas(64) uint16_t batch_groups[kBatchBlocks];
  // Pass 3 packs a translucent triangle into its block's latest slot when their lanes are
  // disjoint (and, for a shader that differentiates, the triangles share an edge). The
  // block's latest slot, if it is in the current batch: block_slot[blk] is that slot exactly
  // when it is below batch_blocks and its batch_offset is blk (every slot of a pass-3 batch
  // is opened by AppendTranslucent, which records it here). Then the slot's latest triangle.
  alignas(64) uint8_t block_slot[kBlocksPerTile] = {};
  // Alpha-tested batches (pass 1) hold one triangle a slot: batch_tri is that triangle and
  // batch_id its setup_id, which the kept lanes write into vis.
  alignas(64) const TriSetup* batch_tri[kBatchBlocks];
  alignas(64) uint32_t batch_id[kBatchBlocks];
  alignas(64) uint32_t lane_prim[kBatchLanes];
  alignas(64) float lane_depth[kBatchLanes];
  alignas(64) float varyings[kMaxVaryings][kBatchLanes];
  alignas(64) float out[4][kBatchLanes];

  std::vector<TranslucentRef> translucent;
  std::vector<TranslucentRef> translucent_scratch;  // the tile sort's second buffer
  std::vector<TranslucentRef> alpha_tested;         // opaque items of alpha-tested draws, in order

  // Pass 2: the visible triangles of each block, with their lanes.
  struct Visible {
    const TriSetup* tri;
    uint32_t draw;  // tri->draw, from its chunk: the sort and batching read no set-up
    uint32_t block;
    uint32_t bits;
  };
  std::vector<Visible> visible;

  // SortMode::Exact: the tile's src-over fragments, composited per pixel at the end.
  struct Fragment {
    float depth;
    float rgba[4];
    uint32_t pixel;  // block-major index in the tile planes
  };
  std::vector<Fragment> fragments;
  std::vector<Fragment> by_pixel;        // scratch: the fragments grouped by pixel, submission order within
  std::vector<uint32_t> fragment_order;  // scratch: one long pixel's sorted order
  std::vector<uint32_t> pixel_start;     // kTilePixels + 1
  std::vector<uint32_t> pixel_next;      // scratch: per pixel, where its next fragment goes

  uint64_t fragments_visible = 0, pixels_shaded = 0, fragments_blended = 0, lanes_shaded = 0;
  uint64_t exact_passes = 0, exact_fragments_peak = 0;  // RasterStats'
};

// Rasterizes, shades, blends and resolves tile `tile` (dispatched once per tile).
void raster_tile(const FrameView& frame, uint32_t tile, TileScratch& scratch);

}  // namespace pelt::raster

namespace pelt::raster {

// A triangle's edges restricted to the part of one tile its bounding box touches,
// widened to whole 4x4 blocks ("region", inclusive pixel bounds). Edges that accept the
// whole region are replaced by an always-positive constant, so the kernels only pay for
// edges that cross it, and those fit in int32 (config.h). Used at bin time to classify
// and by the tile kernels to rasterize; returns false if the region holds no pixel of
// the triangle.
struct TileEdges {
  int32_t a[3], b[3];
  int32_t e0[3];  // edge value at the region's first pixel (rx0, ry0)
  int32_t rx0, ry0, rx1, ry1;
  bool all_accepted;
};

// The 4x4 blocks of the tile at (tx0, ty0) that triangle t's bounding box meets: columns
// [c0, c1] and rows [r0, r1] of the tile's blocks. False when it meets none.
struct TileBlocks {
  int32_t c0, r0, c1, r1;
};
inline bool tile_blocks(const TriSetup& t, int32_t tx0, int32_t ty0, TileBlocks& b) {
  const int32_t x0 = t.x0 > tx0 ? t.x0 : tx0;
  const int32_t y0 = t.y0 > ty0 ? t.y0 : ty0;
  const int32_t x1 = t.xmax < tx0 + kTileSize - 1 ? t.xmax : tx0 + kTileSize - 1;
  const int32_t y1 = t.ymax < ty0 + kTileSize - 1 ? t.ymax : ty0 + kTileSize - 1;
  if (x0 > x1 || y0 > y1) return false;
  b = {(x0 - tx0) / kBlockSize, (y0 - ty0) / kBlockSize, (x1 - tx0) / kBlockSize, (y1 - ty0) / kBlockSize};
  return true;
}

inline bool tile_region_edges(const TriSetup& t, int32_t tx0, int32_t ty0, TileEdges& te) {
  TileBlocks b;
  if (!tile_blocks(t, tx0, ty0, b)) return false;
  te.rx0 = tx0 + b.c0 * kBlockSize;
  te.ry0 = ty0 + b.r0 * kBlockSize;
  te.rx1 = tx0 + b.c1 * kBlockSize + kBlockSize - 1;
  te.ry1 = ty0 + b.r1 * kBlockSize + kBlockSize - 1;
  te.all_accepted = true;
  for (int k = 0; k < 3; ++k) {
    const EdgeEq& e = t.edge[k];
    const int64_t lo = eval_edge(e, e.a > 0 ? te.rx0 : te.rx1, e.b > 0 ? te.ry0 : te.ry1);
    const int64_t hi = eval_edge(e, e.a > 0 ? te.rx1 : te.rx0, e.b > 0 ? te.ry1 : te.ry0);
    if (hi < 0) return false;
    if (lo >= 0) {
      te.a[k] = 0;
      te.b[k] = 0;
      te.e0[k] = 1 << 30;
    } else {
      te.a[k] = e.a;
      te.b[k] = e.b;
      te.e0[k] = static_cast<int32_t>(eval_edge(e, te.rx0, te.ry0));
      te.all_accepted = false;
    }
  }
  return true;
}

}  // namespace pelt::raster
