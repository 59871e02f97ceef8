// The rasterizer's public API: one call renders a list of draws into caller-owned planes.
//
// Stages, each handing plain data to the next:
//   transform (vertices to clip space, per draw)
//   -> clip + set-up + bin (per chunk of triangles, in parallel; per-chunk tile lists
//      keep submission order without atomics)
//   -> tiles (in parallel, a worker owns a 64x64 tile): opaque visibility (depth + id),
//      shading of each visible pixel once, translucent fragments shaded and blended in
//      order, resolve into the caller's planes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec4.hpp>

#include "raster/config.h"
#include "raster/parallel.h"
#include "raster/pipeline.h"

namespace pelt::raster {

enum class SortMode : uint8_t {
  None,  // translucent triangles blend in submission order
  Tile,  // per tile, back to front by view depth (stable); a quad, triangles 2k and 2k + 1
         // sharing an edge, sorts as one primitive at its mean depth
  Exact, // per pixel: every src-over fragment kept, sorted by depth, composited far to near
};

struct RenderTarget {
  int width = 0, height = 0;
  float* color = nullptr;  // width*height*4 linear RGBA, row 0 at the top; null: not wanted
  float* depth = nullptr;  // width*height window depth z/w*0.5+0.5; 1 where empty
  uint32_t* id = nullptr;  // width*height id_base + triangle + 1 of the visible opaque triangle; 0 empty
  // width*height*4 bytes, R, G, B, A: the linear colour as an RGBA8 UNORM framebuffer holds it
  // (unorm8 of each channel, no sRGB encoding), row 0 at the top; null: not wanted. A quarter of
  // the float plane's bytes: where the frame only has to reach memory (bench fps, as the GPU and
  // llvmpipe draw into RGBA8), writing it is that much cheaper.
  uint8_t* color8 = nullptr;
  // width*height: per pixel, the translucent fragments that passed the depth test (each blended
  // once, or kept for the exact sort), row 0 at the top; null: not counted. Where a frame's
  // translucent work lies: a fur frame's shells and fins pile up at silhouettes.
  uint32_t* overdraw = nullptr;
};

// An RGBA8 UNORM channel: round-half-up(255 c) of c clamped to [0, 1] (a product, then a sum, in
// float); NaN gives 0. The tile resolve computes exactly this.
inline uint8_t unorm8(float c) {
  if (!(c > 0.0f)) return 0;
  if (!(c < 1.0f)) return 255;
  return static_cast<uint8_t>(static_cast<int>(c * 255.0f + 0.5f));
}

struct RenderOptions {
  // The planes' first value, as they hold colour: premultiplied by alpha for AlphaOver's
  // result to be premultiplied too (pelt's renders pass the scene's background so).
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
  SortMode sort = SortMode::None;
  // SortMode::Exact: the most fragments a tile holds at once. A tile whose src-over fragments,
  // counted by coverage and depth before shading, pass it draws its translucent pass in bands of
  // blocks, one after another, each within it, so a worker's fragment lists stay bounded (a pile
  // of full-screen layers held them all, 631 MB at 512 x 512 for a thousand blended quads). Each
  // pixel blends the same fragments in the same order; a batch may pack a banded tile's blocks
  // otherwise, which can move a derivative shader's level of detail. A single 4 x 4 block over
  // the cap is drawn alone and may exceed it.
  uint32_t exact_fragment_cap = kExactFragmentCap;
};

struct RasterStats {
  uint64_t triangles_submitted = 0;
  uint64_t triangles_culled = 0;   // outside the frustum, back-facing, zero area or no pixel
  uint64_t triangles_clipped = 0;  // needed near/far/guard-band clipping
  uint64_t triangles_setup = 0;    // set up (after clipping's fans)
  uint64_t bin_items = 0;          // (tile, triangle) pairs
  uint64_t fragments_visible = 0;  // opaque fragments that passed the depth test
  uint64_t pixels_shaded = 0;      // opaque pixels shaded (once each)
  uint64_t fragments_blended = 0;  // translucent fragments that passed the depth test
  uint64_t lanes_shaded = 0;       // lanes handed to shaders (whole 4x4 blocks): the shading
                                   // work, of which pixels_shaded + fragments_blended were used
                                   // (and, for alpha-tested draws, the lanes shaded for their
                                   // alpha before the depth was written)
  uint64_t exact_passes = 0;       // SortMode::Exact: translucent passes of tiles (one a tile,
                                   // more where a tile is drawn in bands)
  uint64_t exact_fragments_peak = 0;  // SortMode::Exact: the most fragments a tile held at once
  double ms_front = 0.0;           // transform, clip, set-up and binning
  double ms_tiles = 0.0;           // rasterization, shading, blending, resolve

  // Sums every counter and time (e.g. over the passes of one supersampled frame).
  RasterStats& operator+=(const RasterStats& o) {
    triangles_submitted += o.triangles_submitted;
    triangles_culled += o.triangles_culled;
    triangles_clipped += o.triangles_clipped;
    triangles_setup += o.triangles_setup;
    bin_items += o.bin_items;
    fragments_visible += o.fragments_visible;
    pixels_shaded += o.pixels_shaded;
    fragments_blended += o.fragments_blended;
    lanes_shaded += o.lanes_shaded;
    exact_passes += o.exact_passes;
    exact_fragments_peak = std::max(exact_fragments_peak, o.exact_fragments_peak);  // a peak, not a sum
    ms_front += o.ms_front;
    ms_tiles += o.ms_tiles;
    return *this;
  }
};

class Renderer {
 public:
  // threads: see ThreadPool (0 = inline on the calling thread).
  explicit Renderer(int threads);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int threads() const;
  // The renderer's threads for other independent work of its caller (set-up passes): calls
  // fn(item, slot) for item in [0, count) as ThreadPool::parallel_for does.
  void parallel_for(size_t count, ItemFn fn);
  // Bytes each worker keeps for the tile it works on (its planes and shading batch).
  static size_t worker_scratch_bytes();
  // What a worker's fragment lists hold at most under SortMode::Exact with `cap`
  // (RenderOptions::exact_fragment_cap), unless a single block leaves more.
  static size_t exact_sort_bytes(uint32_t cap);

  // Renders `draws` in order. The images are bit-identical for any thread count.
  // Buffers are kept between calls: rendering the same-sized frame again allocates nothing.
  void render(std::span<const DrawCall> draws, const RenderOptions& options,
              const RenderTarget& target, RasterStats* stats = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pelt::raster
