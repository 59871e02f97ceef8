// The back end: everything a worker does to one 64x64 tile, written once with Highway
// and compiled for every target; dispatched once per tile.
//
// Pass 1, opaque visibility: coverage (exact int32 edge equations, hierarchical 16x16
//   then 4x4 rejection) and the depth test; writes depth and the visible triangle.
//   Alpha-tested draws follow: fragments that pass the depth test are shaded in batches,
//   and those whose alpha reaches the cutoff are depth-tested again and written.
// Pass 2, opaque shading: each visible pixel is shaded once, by the triangle that owns it.
// Pass 3, translucent: fragments depth-tested against pass 1, shaded in batches and
//   blended src-over in order (submission order or back to front per tile).
// Resolve: the tile's planes into the caller's row-major images.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/tile_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "raster/block_mask-inl.h"
#include "raster/frame.h"
#include "raster/translucent_sort.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;

// Plane value at lanes g of the block whose lane 0 is pixel (ox, oy) relative to the
// triangle's reference pixel. Same expression as eval_plane in setup.h.
HWY_INLINE hn::Vec<DF> EvalPlane(const Plane& p, int32_t ox, int32_t oy, size_t g) {
  const DF df;
  const DI di;
  const size_t n = hn::Lanes(df);
  const auto fx = hn::ConvertTo(df, hn::Add(hn::Set(di, ox), hn::LoadU(di, kLaneX + g * n)));
  const auto fy = hn::ConvertTo(df, hn::Add(hn::Set(di, oy), hn::LoadU(di, kLaneY + g * n)));
  return hn::Add(hn::Set(df, p.ref),
                 hn::Add(hn::Mul(hn::Set(df, p.dx), fx), hn::Mul(hn::Set(df, p.dy), fy)));
}

// eval_depth in setup.h, for lanes g of a block.
HWY_INLINE hn::Vec<DF> EvalDepth(const TriSetup& t, int32_t ox, int32_t oy, size_t g) {
  const DF df;
  return hn::Min(hn::Max(EvalPlane(t.z, ox, oy, g), hn::Zero(df)), hn::Set(df, 1.0f));
}

inline uint32_t BlockIndex(int32_t px, int32_t py, int32_t tx0, int32_t ty0) {
  return static_cast<uint32_t>(((py - ty0) / kBlockSize) * kBlocksPerTileSide +
                               (px - tx0) / kBlockSize);
}

// Lanes of a block inside all three edges, from the edges' values e at its lane 0 and
// their per-lane offsets `step` (a x + b y of each lane).
HWY_INLINE uint32_t BlockCover(const int32_t (&step)[3][kBlockLanes], int32_t e0, int32_t e1, int32_t e2) {
  const DI di;
  const size_t n = hn::Lanes(di);
  const uint32_t group_bits = GroupBits();
  uint32_t cover = 0;
  for (size_t g = 0; g * n < kBlockLanes; ++g) {
    const auto v0 = hn::Add(hn::Set(di, e0), hn::Load(di, step[0] + g * n));
    const auto v1 = hn::Add(hn::Set(di, e1), hn::Load(di, step[1] + g * n));
    const auto v2 = hn::Add(hn::Set(di, e2), hn::Load(di, step[2] + g * n));
    // Inside all three edges <=> the OR of the values has no sign bit.
    const auto outside = hn::Lt(hn::Or(hn::Or(v0, v1), v2), hn::Zero(di));
    cover |= (~MaskToBits(di, outside) & group_bits) << (g * n);
  }
  return cover;
}

// Calls fn(px, py, block, bits) for every block of the region that holds a covered
// pixel; bits = covered lanes inside the viewport. Called per triangle per tile.
template <class Fn>
HWY_INLINE void ForEachCoveredBlock(const TileEdges& te, int32_t tx0, int32_t ty0,
                                    const uint16_t* valid, Fn&& fn) {
  if (te.all_accepted) {
    for (int32_t py = te.ry0; py <= te.ry1; py += kBlockSize)
      for (int32_t px = te.rx0; px <= te.rx1; px += kBlockSize) {
        const uint32_t b = BlockIndex(px, py, tx0, ty0);
        if (valid[b]) fn(px, py, b, uint32_t{valid[b]});
      }
    return;
  }
  const DI di;
  const size_t n = hn::Lanes(di);
  // Per-lane edge offsets within a block, a x + b y: at most 16 / N vectors per edge.
  alignas(64) int32_t step[3][kBlockLanes];
  for (int k = 0; k < 3; ++k)
    for (size_t g = 0; g * n < kBlockLanes; ++g)
      hn::Store(hn::Add(hn::Mul(hn::Set(di, te.a[k]), hn::Load(di, kLaneX + g * n)),
                        hn::Mul(hn::Set(di, te.b[k]), hn::Load(di, kLaneY + g * n))),
                di, step[k] + g * n);

  // A region of at most 2x2 blocks (most triangles of a dense mesh): the four blocks'
  // coverage without branches, then the blocks that hold covered pixels. The general loop
  // below spends most of a small triangle's time on mispredicted loop exits and tests.
  if (te.rx1 - te.rx0 < 2 * kBlockSize && te.ry1 - te.ry0 < 2 * kBlockSize) {
    const int32_t wide = te.rx1 - te.rx0 >= kBlockSize, tall = te.ry1 - te.ry0 >= kBlockSize;
    uint32_t block_bits[4];
    for (int q = 0; q < 4; ++q) {
      const int32_t qx = q & 1, qy = q >> 1;
      const bool inside = qx <= wide && qy <= tall;
      const int32_t dxp = qx * kBlockSize, dyp = qy * kBlockSize;
      const int32_t e0 = te.e0[0] + te.a[0] * dxp + te.b[0] * dyp;
      const int32_t e1 = te.e0[1] + te.a[1] * dxp + te.b[1] * dyp;
      const int32_t e2 = te.e0[2] + te.a[2] * dxp + te.b[2] * dyp;
      const uint32_t cover = BlockCover(step, e0, e1, e2);
      // Blocks outside the region may lie outside the tile: their index is never formed.
      const uint32_t blk = inside ? BlockIndex(te.rx0 + dxp, te.ry0 + dyp, tx0, ty0) : 0;
      block_bits[q] = inside ? (cover & valid[blk]) : 0u;
    }
    for (int q = 0; q < 4; ++q) {
      if (!block_bits[q]) continue;
      const int32_t px = te.rx0 + (q & 1) * kBlockSize, py = te.ry0 + (q >> 1) * kBlockSize;
      fn(px, py, BlockIndex(px, py, tx0, ty0), block_bits[q]);
    }
    return;
  }

  // Larger regions, per 16x16 sub-tile: its 4x4 blocks are classified at once, one block a
  // lane (the lane layout of a block, kLaneX/kLaneY, scaled by the block size), by each
  // edge's least and greatest value over the block's pixels: a block with a negative greatest
  // value lies outside, one whose least values are all non-negative inside, and only the
  // rest need their lanes tested (BlockCover). A fur shell's triangle spans tens of blocks,
  // most of them wholly inside or outside it; testing the lanes of every block of a sub-tile
  // the triangle crosses, as this loop did before, took about 13 % of a furry-box frame.
  // A sub-tile is laid out in blocks as a block is in lanes: kSide a side, row-major, which
  // the row and column masks below rely on.
  constexpr int32_t kSide = kBlockSize;
  constexpr int32_t kSub = kSide * kBlockSize;
  static_assert([] {
    for (int j = 0; j < kBlockLanes; ++j)
      if (kLaneX[j] != j % kSide || kLaneY[j] != j / kSide) return false;
    return true;
  }());
  constexpr uint32_t kRow = (1u << kSide) - 1;  // one row's blocks
  constexpr uint32_t kAll = (1u << kBlockLanes) - 1;
  constexpr uint32_t kColumn = kAll / kRow;  // one block of every row (0x1111)
  // Per edge: its offsets to each block of a sub-tile (a lane's offset within a block, `step`,
  // scaled by the block size), and the least and greatest of `step` (a block's pixels).
  alignas(64) int32_t block_step[3][kBlockLanes];
  int32_t lo_off[3], hi_off[3];
  for (int k = 0; k < 3; ++k) {
    const int32_t a = te.a[k], b = te.b[k];
    for (size_t g = 0; g * n < kBlockLanes; ++g)
      hn::Store(hn::Mul(hn::Set(di, kBlockSize), hn::Load(di, step[k] + g * n)), di, block_step[k] + g * n);
    lo_off[k] = (std::min(a, 0) + std::min(b, 0)) * (kBlockSize - 1);
    hi_off[k] = (std::max(a, 0) + std::max(b, 0)) * (kBlockSize - 1);
  }
  const int32_t sy0 = ty0 + ((te.ry0 - ty0) & ~(kSub - 1));
  const int32_t sx0 = tx0 + ((te.rx0 - tx0) & ~(kSub - 1));
  for (int32_t sy = sy0; sy <= te.ry1; sy += kSub) {
    // The sub-tile's rows of blocks inside the region, as block bits.
    const int32_t r0 = (std::max(sy, te.ry0) - sy) / kBlockSize;
    const int32_t r1 = (std::min(sy + kSub - 1, te.ry1) - sy) / kBlockSize;
    const uint32_t rows = (kAll << (kSide * r0)) & (kAll >> (kSide * (kSide - 1 - r1)));
    for (int32_t sx = sx0; sx <= te.rx1; sx += kSub) {
      const int32_t c0 = (std::max(sx, te.rx0) - sx) / kBlockSize;
      const int32_t c1 = (std::min(sx + kSub - 1, te.rx1) - sx) / kBlockSize;
      const uint32_t cols = ((kRow << c0) & (kRow >> (kSide - 1 - c1))) * kColumn;
      int32_t e_sub[3];
      for (int k = 0; k < 3; ++k) e_sub[k] = te.e0[k] + te.a[k] * (sx - te.rx0) + te.b[k] * (sy - te.ry0);
      uint32_t outside = 0, partial = 0;
      for (size_t g = 0; g * n < kBlockLanes; ++g) {
        auto extreme = [&](const int32_t (&off)[3]) {
          auto v = hn::Add(hn::Set(di, e_sub[0] + off[0]), hn::Load(di, block_step[0] + g * n));
          for (int k = 1; k < 3; ++k)
            v = hn::Or(v, hn::Add(hn::Set(di, e_sub[k] + off[k]), hn::Load(di, block_step[k] + g * n)));
          return v;
        };
        const auto hi_or = extreme(hi_off), lo_or = extreme(lo_off);
        // A value's sign bit is the OR's: some edge negative at every pixel of the block
        // (outside), or at some pixel (not wholly inside).
        outside |= MaskToBits(di, hn::Lt(hi_or, hn::Zero(di))) << (g * n);
        partial |= MaskToBits(di, hn::Lt(lo_or, hn::Zero(di))) << (g * n);
      }
      uint32_t left = rows & cols & ~outside;
      const uint32_t first_blk = BlockIndex(sx, sy, tx0, ty0);
      while (left) {
        const int j = std::countr_zero(left);
        left &= left - 1;
        const int32_t bx = kLaneX[j], by = kLaneY[j];
        const uint32_t blk = first_blk + uint32_t(by * kBlocksPerTileSide + bx);
        uint32_t bits = valid[blk];
        const int32_t px = sx + bx * kBlockSize, py = sy + by * kBlockSize;
        if (partial & (1u << j))
          bits &= BlockCover(step, e_sub[0] + block_step[0][j], e_sub[1] + block_step[1][j],
                             e_sub[2] + block_step[2][j]);
        if (bits) fn(px, py, blk, bits);
      }
    }
  }
}

template <DepthFunc kFunc>
HWY_INLINE hn::Mask<DF> DepthPass(hn::Vec<DF> z, hn::Vec<DF> stored) {
  if constexpr (kFunc == DepthFunc::Less) return hn::Lt(z, stored);
  if constexpr (kFunc == DepthFunc::LessEqual) return hn::Le(z, stored);
  (void)stored;
  return hn::Eq(z, z);  // Always: true for the finite depths set-up produces
}

// Depth-tests the covered lanes of one block; writes depth (and vis) when asked.
// Returns the lanes that passed.
template <DepthFunc kFunc, bool kWrite, bool kWriteVis>
HWY_INLINE uint32_t DepthTestBlock(const TriSetup& t, int32_t px, int32_t py, uint32_t blk,
                                   uint32_t bits, uint32_t vis_id, TileScratch& s) {
  const DF df;
  const DU du;
  const size_t n = hn::Lanes(df);
  const uint32_t off = blk * kBlockLanes;
  uint32_t passed = 0;
  for (size_t g = 0; g * n < kBlockLanes; ++g) {
    const auto z = EvalDepth(t, px - t.x0, py - t.y0, g);
    const auto zb = hn::Load(df, s.depth + off + g * n);
    const auto pass = hn::And(BitsToMask(bits, g), DepthPass<kFunc>(z, zb));
    if constexpr (kWrite) {
      hn::Store(hn::IfThenElse(pass, z, zb), df, s.depth + off + g * n);
      if constexpr (kWriteVis) {
        const auto vb = hn::Load(du, s.vis + off + g * n);
        hn::Store(hn::IfThenElse(hn::RebindMask(du, pass), hn::Set(du, vis_id), vb), du,
                  s.vis + off + g * n);
      }
    }
    passed |= MaskToBits(df, pass) << (g * n);
  }
  return passed;
}

template <class Fn>
HWY_INLINE void DispatchDepth(const PipelineState& st, Fn&& fn) {
  // Hot loops are specialised per depth function and write flag at compile time.
  switch (st.depth_func) {
    case DepthFunc::Less:
      st.depth_write ? fn.template operator()<DepthFunc::Less, true>()
                     : fn.template operator()<DepthFunc::Less, false>();
      break;
    case DepthFunc::LessEqual:
      st.depth_write ? fn.template operator()<DepthFunc::LessEqual, true>()
                     : fn.template operator()<DepthFunc::LessEqual, false>();
      break;
    case DepthFunc::Always:
      st.depth_write ? fn.template operator()<DepthFunc::Always, true>()
                     : fn.template operator()<DepthFunc::Always, false>();
      break;
  }
}

HWY_INLINE uint32_t AllGroups() { return (1u << (kBlockLanes / hn::Lanes(DF()))) - 1u; }

// A triangle's varyings as Interpolate reads them: vertex 0's values and the differences to
// vertices 1 and 2. Made once per triangle and tile in the translucent pass, whose triangles
// cover many blocks each; the loads of the indices and vertices and the differences were a
// fifth of the interpolation's time when made per block.
struct TriVaryings {
  const float* a0;
  uint32_t count;
  float d1[kMaxVaryings], d2[kMaxVaryings];
};

HWY_INLINE void MakeTriVaryings(const FrameView& frame, const TriSetup& t, TriVaryings& tv) {
  const DrawCall& draw = frame.draws[t.draw];
  const uint32_t vc = draw.varying_count;
  const uint32_t* tri = draw.indices + 3 * size_t{t.primitive};
  const float* a0 = draw.varyings + size_t{tri[0]} * vc;
  const float* a1 = draw.varyings + size_t{tri[1]} * vc;
  const float* a2 = draw.varyings + size_t{tri[2]} * vc;
  tv.a0 = a0;
  tv.count = vc;
  for (uint32_t k = 0; k < vc; ++k) {
    tv.d1[k] = a1[k] - a0[k];
    tv.d2[k] = a2[k] - a0[k];
  }
}

// Interpolates triangle t's depth, primitive and varyings into the lanes `bits` of batch
// slot i. `whole`: all 16 lanes, so lanes the triangle does not cover hold its planes
// extrapolated (what derivatives need). Otherwise only the vector groups holding covered
// lanes are computed (a group no triangle has filled yet takes all its lanes from this
// one): several triangles of one draw share a slot, and a small triangle of a dense mesh
// usually covers one group of a block, so this halves the work on AVX2.
void Interpolate(TileScratch& s, uint32_t i, const TriSetup& t, const TriVaryings& tv, uint32_t bits, bool whole) {
  const DF df;
  const DU du;
  const size_t n = hn::Lanes(df);
  const uint32_t vc = tv.count;
  const auto tiny = hn::Set(df, 1e-30f);
  const auto bmin = hn::Set(df, -8.0f), bmax = hn::Set(df, 9.0f);
  const int32_t ox = s.batch_x[i] - t.x0, oy = s.batch_y[i] - t.y0;
  // Vertex 0's values are read where they are used: copied into an array like the
  // differences, the copy became a call to memmove per block (about 1 % of a furry-box frame).
  const float* a0 = tv.a0;
  const float* d1 = tv.d1;
  const float* d2 = tv.d2;
  for (size_t g = 0; g * n < kBlockLanes; ++g) {
    const auto m = BitsToMask(bits, g);
    if (!whole && hn::AllFalse(df, m)) continue;
    const size_t lane = i * kBlockLanes + g * n;
    const auto z = EvalDepth(t, ox, oy, g);
    // Lanes outside the triangle extrapolate the planes; clamping 1/w and the
    // barycentrics keeps their varyings finite without touching covered lanes.
    const auto w = hn::Div(hn::Set(df, 1.0f), hn::Max(EvalPlane(t.inv_w, ox, oy, g), tiny));
    const auto b1 = hn::Min(hn::Max(hn::Mul(EvalPlane(t.b1w, ox, oy, g), w), bmin), bmax);
    const auto b2 = hn::Min(hn::Max(hn::Mul(EvalPlane(t.b2w, ox, oy, g), w), bmin), bmax);
    auto varying = [&](uint32_t k) {
      return hn::Add(hn::Set(df, a0[k]), hn::Add(hn::Mul(b1, hn::Set(df, d1[k])), hn::Mul(b2, hn::Set(df, d2[k]))));
    };
    if (whole || !(s.batch_groups[i] & (1u << g))) {
      hn::Store(z, df, s.lane_depth + lane);
      hn::Store(hn::Set(du, t.primitive), du, s.lane_prim + lane);
      for (uint32_t k = 0; k < vc; ++k) hn::Store(varying(k), df, s.varyings[k] + lane);
      s.batch_groups[i] = static_cast<uint16_t>(s.batch_groups[i] | (1u << g));
      continue;
    }
    hn::Store(hn::IfThenElse(m, z, hn::Load(df, s.lane_depth + lane)), df, s.lane_depth + lane);
    hn::Store(hn::IfThenElse(hn::RebindMask(du, m), hn::Set(du, t.primitive), hn::Load(du, s.lane_prim + lane)),
              du, s.lane_prim + lane);
    for (uint32_t k = 0; k < vc; ++k)
      hn::Store(hn::IfThenElse(m, varying(k), hn::Load(df, s.varyings[k] + lane)), df, s.varyings[k] + lane);
  }
  s.batch_mask[i] = static_cast<uint16_t>(s.batch_mask[i] | bits);
}

// What a flush does with the shader's output.
enum class Flush {
  store,       // opaque colour into the tile
  blend,       // translucent colour onto it
  alpha_test,  // no colour: depth and visibility where alpha reaches the draw's cutoff
};

// Runs the draw's shader on the batch, then stores, blends or alpha-tests its output in the
// tile, block after block in batch order.
void FlushBatch(const FrameView& frame, TileScratch& s, Flush mode) {
  const uint32_t nb = s.batch_blocks;
  if (nb == 0) return;
  s.batch_blocks = 0;
  const DrawCall& draw = frame.draws[s.batch_draw];
  const DF df;
  const size_t n = hn::Lanes(df);
  const uint32_t vc = draw.varying_count;

  // Groups of packed slots that no triangle filled: copies of a filled group, finite
  // inputs for lanes whose outputs are ignored.
  const uint32_t all_groups = AllGroups();
  for (uint32_t i = 0; i < nb; ++i) {
    const uint32_t filled = s.batch_groups[i];
    if (filled == all_groups) continue;
    const size_t from = i * kBlockLanes + std::countr_zero(filled) * n;
    for (size_t g = 0; g * n < kBlockLanes; ++g) {
      if (filled & (1u << g)) continue;
      const size_t to = i * kBlockLanes + g * n;
      hn::Store(hn::Load(df, s.lane_depth + from), df, s.lane_depth + to);
      hn::Store(hn::Load(DU(), s.lane_prim + from), DU(), s.lane_prim + to);
      for (uint32_t k = 0; k < vc; ++k) hn::Store(hn::Load(df, s.varyings[k] + from), df, s.varyings[k] + to);
    }
  }

  FragmentBatch fb;
  fb.blocks = nb;
  fb.mask = s.batch_mask;
  fb.block_x = s.batch_x;
  fb.block_y = s.batch_y;
  fb.primitive = s.lane_prim;
  for (uint32_t k = 0; k < vc; ++k) fb.varying[k] = s.varyings[k];
  fb.depth = s.lane_depth;
  for (int c = 0; c < 4; ++c) fb.out[c] = s.out[c];
  draw.shader->shade(fb);
  s.lanes_shaded += uint64_t{nb} * kBlockLanes;
  const bool additive = draw.state.blend == BlendMode::Additive;
  const bool exact = frame.options.sort == SortMode::Exact;
  const bool blend = mode == Flush::blend;
  if (mode == Flush::alpha_test) {
    // Slot by slot in submission order, each slot one triangle's passed lanes: an earlier
    // slot's written depth is seen by the next (the test at append time was against the
    // depth before the batch).
    const auto cutoff = hn::Set(df, draw.state.alpha_cutoff);
    DispatchDepth(draw.state, [&]<DepthFunc F, bool W>() {
      for (uint32_t i = 0; i < nb; ++i) {
        uint32_t kept = 0;
        for (size_t g = 0; g * n < kBlockLanes; ++g)
          kept |= MaskToBits(df, hn::Ge(hn::Load(df, s.out[3] + i * kBlockLanes + g * n), cutoff)) << (g * n);
        kept &= s.batch_mask[i];
        if (kept == 0) continue;
        s.fragments_visible += std::popcount(DepthTestBlock<F, W, true>(*s.batch_tri[i], s.batch_x[i], s.batch_y[i],
                                                                         s.batch_offset[i], kept, s.batch_id[i], s));
      }
    });
    return;
  }
  const bool cut_out = draw.state.alpha_test;  // its kept fragments are opaque

  const uint32_t group_bits = GroupBits();
  for (uint32_t i = 0; i < nb; ++i) {
    const uint32_t off = s.batch_offset[i] * kBlockLanes;
    const uint32_t bits = s.batch_mask[i];
    for (size_t g = 0; g * n < kBlockLanes; ++g) {
      if (((bits >> (g * n)) & group_bits) == 0) continue;  // e.g. the uncovered half of an edge block
      const size_t lane = i * kBlockLanes + g * n;
      const auto m = BitsToMask(bits, g);
      if (!blend) {
        for (int c = 0; c < 4; ++c) {
          float* dst = s.color[c] + off + g * n;
          const auto v = c == 3 && cut_out ? hn::Set(df, 1.0f) : hn::Load(df, s.out[c] + lane);
          hn::Store(hn::IfThenElse(m, v, hn::Load(df, dst)), df, dst);
        }
        continue;
      }
      if (exact && !additive) {
        // Kept for the per-pixel sort at the end of the tile.
        for (size_t l = 0; l < n; ++l) {
          const uint32_t lane_in_block = uint32_t(g * n + l);
          if (!(bits & (1u << lane_in_block))) continue;
          TileScratch::Fragment f;
          f.depth = s.lane_depth[lane + l];
          for (int c = 0; c < 4; ++c) f.rgba[c] = s.out[c][lane + l];
          f.pixel = off + lane_in_block;
          s.fragments.push_back(f);
        }
        continue;
      }
      // Alpha clamped to [0, 1] so a shader's overshoot cannot push the framebuffer out
      // of range.
      const auto a = hn::Min(hn::Max(hn::Load(df, s.out[3] + lane), hn::Zero(df)), hn::Set(df, 1.0f));
      if (additive) {
        for (int c = 0; c < 3; ++c) {
          float* dst = s.color[c] + off + g * n;
          const auto d = hn::Load(df, dst);
          hn::Store(hn::IfThenElse(m, hn::Add(d, hn::Mul(hn::Load(df, s.out[c] + lane), a)), d), df, dst);
        }
        continue;
      }
      const auto keep = hn::Sub(hn::Set(df, 1.0f), a);
      for (int c = 0; c < 3; ++c) {
        float* dst = s.color[c] + off + g * n;
        const auto d = hn::Load(df, dst);
        const auto r = hn::Add(hn::Mul(hn::Load(df, s.out[c] + lane), a), hn::Mul(d, keep));
        hn::Store(hn::IfThenElse(m, r, d), df, dst);
      }
      float* dst = s.color[3] + off + g * n;
      const auto d = hn::Load(df, dst);
      hn::Store(hn::IfThenElse(m, hn::Add(a, hn::Mul(d, keep)), d), df, dst);
    }
  }
}

// RenderTarget::overdraw: one more fragment at the lanes `bits` of block `blk`.
HWY_INLINE void CountOverdraw(TileScratch& s, uint32_t blk, uint32_t bits) {
  const DU du;
  const size_t n = hn::Lanes(du);
  uint32_t* c = s.overdraw + blk * kBlockLanes;
  for (size_t g = 0; g * n < kBlockLanes; ++g) {
    const auto m = hn::RebindMask(du, BitsToMask(bits, g));
    hn::Store(hn::Add(hn::Load(du, c + g * n), hn::IfThenElseZero(m, hn::Set(du, 1u))), du, c + g * n);
  }
}

// Opens a batch slot for block `blk` of `draw` (flushing first when the batch holds
// another draw or is full); its lanes are filled by Interpolate.
uint32_t OpenSlot(const FrameView& frame, TileScratch& s, uint32_t draw, int32_t px, int32_t py,
                  uint32_t blk, Flush mode) {
  if (s.batch_blocks > 0 && s.batch_draw != draw) FlushBatch(frame, s, mode);
  if (s.batch_blocks == kBatchBlocks) FlushBatch(frame, s, mode);
  const uint32_t i = s.batch_blocks++;
  s.batch_draw = draw;
  s.batch_mask[i] = 0;
  s.batch_groups[i] = 0;
  s.batch_x[i] = px;
  s.batch_y[i] = py;
  s.batch_offset[i] = static_cast<uint16_t>(blk);
  return i;
}

// True when triangles a and b of `draw` share an edge, so that a block holding lanes of both
// still differentiates to the derivative of one continuous field.
HWY_INLINE bool SharesEdge(const DrawCall& draw, const TriSetup& a, const TriSetup& b) {
  return triangles_share_edge(draw.indices + 3 * size_t{a.primitive}, draw.indices + 3 * size_t{b.primitive});
}

// Appends the passed lanes `bits` of translucent triangle t in block `blk`. They join the
// block's latest slot when none of its lanes is taken there and (for a shader with
// derivatives) t shares an edge with the slot's latest triangle: every pixel still blends
// its fragments in order (earlier slots of the block come first, and the slot holds at
// most one fragment per pixel), and a fur shell's or fin's quads fill a block together
// instead of two or three slots holding a few lanes each.
void AppendTranslucent(const FrameView& frame, TileScratch& s, const TriSetup& t, const TriVaryings& tv, int32_t px,
                       int32_t py, uint32_t blk, uint32_t bits, bool derivatives) {
  const uint32_t i = s.block_slot[blk];
  const bool latest = i < s.batch_blocks && s.batch_offset[i] == blk && s.batch_draw == t.draw;
  if (latest && !(s.batch_mask[i] & bits) &&
      (!derivatives || SharesEdge(frame.draws[t.draw], *s.batch_tri[i], t))) {
    Interpolate(s, i, t, tv, bits, false);
    s.batch_tri[i] = &t;
    return;
  }
  const uint32_t slot = OpenSlot(frame, s, t.draw, px, py, blk, Flush::blend);
  Interpolate(s, slot, t, tv, bits, true);
  s.block_slot[blk] = static_cast<uint8_t>(slot);
  s.batch_tri[slot] = &t;
}

// A set-up triangle is two cache lines, written by the front end and first read here,
// usually from L3 or memory: fetching a few items ahead hides most of that latency (a
// dense scan's tiles spent a quarter of their time waiting on these loads).
inline constexpr size_t kPrefetchAhead = 8;
HWY_INLINE void PrefetchSetup(const TriSetup* t) {
  hwy::Prefetch(reinterpret_cast<const char*>(t));
  hwy::Prefetch(reinterpret_cast<const char*>(t) + 64);
}

// Calls fn(setup, setup_id, draw) for the tile's items in submission order. The draw comes
// from the chunk, so deciding what to do with an item does not wait on its set-up's load.
template <class Fn>
HWY_INLINE void ForEachItem(const FrameView& frame, uint32_t tile, Fn&& fn) {
  for (size_t c = 0; c < frame.chunk_count; ++c) {
    const BinChunk& ch = frame.chunks[c];
    const uint32_t* it = ch.items.data() + ch.tile_offsets[tile];
    const uint32_t* end = ch.items.data() + ch.tile_offsets[tile + 1];
    for (; it != end; ++it) {
      if (end - it > ptrdiff_t{kPrefetchAhead}) PrefetchSetup(&ch.setups[it[kPrefetchAhead]]);
      fn(ch.setups[*it], setup_id(c, *it), ch.draw);
    }
  }
}

void ClearTile(const FrameView& frame, int32_t tx0, int32_t ty0, TileScratch& s) {
  const DF df;
  const DU du;
  const size_t n = hn::Lanes(df);
  const glm::vec4 bg = frame.options.background;
  const float bgc[4] = {bg.r, bg.g, bg.b, bg.a};
  for (int c = 0; c < 4; ++c)
    for (size_t i = 0; i < kTilePixels; i += n) hn::Store(hn::Set(df, bgc[c]), df, s.color[c] + i);
  for (size_t i = 0; i < kTilePixels; i += n) {
    hn::Store(hn::Set(df, kClearDepth), df, s.depth + i);
    hn::Store(hn::Set(du, kNoPrimitive), du, s.vis + i);
  }
  if (frame.target.overdraw)
    for (size_t i = 0; i < kTilePixels; i += n) hn::Store(hn::Zero(du), du, s.overdraw + i);
  const int32_t w = frame.vp.width - tx0, h = frame.vp.height - ty0;
  if (w >= kTileSize && h >= kTileSize) {
    std::fill(s.block_valid, s.block_valid + kBlocksPerTile, uint16_t{0xFFFF});
    return;
  }
  for (int by = 0; by < kBlocksPerTileSide; ++by)
    for (int bx = 0; bx < kBlocksPerTileSide; ++bx) {
      uint32_t bits = 0;
      for (int l = 0; l < kBlockLanes; ++l)
        if (bx * kBlockSize + kLaneX[l] < w && by * kBlockSize + kLaneY[l] < h) bits |= 1u << l;
      s.block_valid[by * kBlocksPerTileSide + bx] = static_cast<uint16_t>(bits);
    }
}

// The triangle of a visibility-buffer id (setup_id in frame.h).
inline const TriSetup& SetupOf(const FrameView& frame, uint32_t id) {
  return frame.chunks[id >> kSetupIndexBits].setups[id & ((1u << kSetupIndexBits) - 1)];
}

// The tile's w x h pixels as RGBA8 bytes (unorm8 of each channel) into the target's rows from
// dst (the tile's top-left pixel, `stride` bytes a row): block by block, its 16 pixels' four
// channels packed into one 32-bit word a pixel with whole vectors, then its four rows copied out.
// Converting row by row, four pixels a vector, took about twice as long (`perf record` of a
// two-thread box `bench fps`: 1.8-2.0 % of the samples against 0.9 % now, with the copies of whole
// block rows inlined as single 16-byte stores).
void Resolve8(const TileScratch& s, int32_t w, int32_t h, uint8_t* dst, size_t stride) {
  const DF df;
  const DI di;
  const DU du;
  const size_t n = hn::Lanes(df);
  auto channel = [&](const float* p) {  // unorm8, a uint32 per lane
    const auto c = hn::Min(hn::Max(hn::Load(df, p), hn::Zero(df)), hn::Set(df, 1.0f));  // NaN: 0 (Max's second operand)
    return hn::BitCast(du, hn::ConvertTo(di, hn::Add(hn::Mul(c, hn::Set(df, 255.0f)), hn::Set(df, 0.5f))));
  };
  HWY_ALIGN uint32_t words[kBlockLanes];
  for (int32_t by = 0; by < h; by += kBlockSize)
    for (int32_t bx = 0; bx < w; bx += kBlockSize) {
      const size_t src = size_t{BlockIndex(bx, by, 0, 0)} * kBlockLanes;
      for (size_t i = 0; i < size_t(kBlockLanes); i += n) {
        const auto word = hn::Or(hn::Or(channel(s.color[0] + src + i), hn::ShiftLeft<8>(channel(s.color[1] + src + i))),
                                 hn::Or(hn::ShiftLeft<16>(channel(s.color[2] + src + i)),
                                        hn::ShiftLeft<24>(channel(s.color[3] + src + i))));
        hn::Store(word, du, words + i);
      }
      const size_t bytes = 4 * size_t(std::min(kBlockSize, w - bx));
      for (int32_t r = 0; r < kBlockSize && by + r < h; ++r) {
        uint8_t* to = dst + size_t(by + r) * stride + 4 * size_t(bx);
        if (bytes == sizeof(uint32_t) * kBlockSize) {
          std::memcpy(to, words + r * kBlockSize, sizeof(uint32_t) * kBlockSize);  // one 16-byte store, inlined
        } else {
          std::memcpy(to, words + r * kBlockSize, bytes);  // the tile's last, partial block column
        }
      }
    }
}

// Row y of a one-value-a-pixel tile plane (block-major) into `dst`, its w pixels: a block row of
// 4 values is contiguous in the plane, so one copy a block.
template <typename T>
HWY_INLINE void ResolvePlaneRow(const T* plane, int32_t y, int32_t w, T* dst) {
  const uint32_t lane_row = (y % kBlockSize) * kBlockSize;
  for (int32_t x = 0; x < w; x += kBlockSize)
    std::memcpy(dst + x, plane + BlockIndex(x, y, 0, 0) * kBlockLanes + lane_row, sizeof(T) * std::min(kBlockSize, w - x));
}

void ResolveTile(const FrameView& frame, int32_t tx0, int32_t ty0, TileScratch& s) {
  const RenderTarget& t = frame.target;
  const int32_t w = std::min(kTileSize, frame.vp.width - tx0);
  const int32_t h = std::min(kTileSize, frame.vp.height - ty0);
  if (t.color8)
    Resolve8(s, w, h, t.color8 + (static_cast<size_t>(ty0) * t.width + tx0) * 4, static_cast<size_t>(t.width) * 4);
  const int32_t whole = w & ~(kBlockSize - 1);  // columns resolved 4 at a time
  [[maybe_unused]] const hn::CappedTag<float, 4> d4;
  for (int32_t y = 0; y < h; ++y) {
    const size_t row = static_cast<size_t>(ty0 + y) * t.width + tx0;
    const uint32_t lane_row = (y % kBlockSize) * kBlockSize;
    if (t.color) {
      // A block row of 4 pixels is 4 contiguous floats per plane: interleave to RGBA.
      for (int32_t x = 0; x < whole; x += kBlockSize) {
        const uint32_t src = BlockIndex(x, y, 0, 0) * kBlockLanes + lane_row;
        float* dst = t.color + (row + x) * 4;
#if HWY_TARGET == HWY_SCALAR
        for (size_t i = 0; i < kBlockSize; ++i)
          for (int c = 0; c < 4; ++c) dst[i * 4 + c] = s.color[c][src + i];
#else
        // 4x4 transpose, then streaming stores: the frame is written once and not read
        // back by this worker, so skipping the read-for-ownership halves the traffic.
        const auto r = hn::LoadU(d4, s.color[0] + src), g = hn::LoadU(d4, s.color[1] + src);
        const auto b = hn::LoadU(d4, s.color[2] + src), a = hn::LoadU(d4, s.color[3] + src);
        const auto rg_lo = hn::InterleaveLower(d4, r, g), ba_lo = hn::InterleaveLower(d4, b, a);
        const auto rg_hi = hn::InterleaveUpper(d4, r, g), ba_hi = hn::InterleaveUpper(d4, b, a);
        const auto p0 = hn::ConcatLowerLower(d4, ba_lo, rg_lo), p1 = hn::ConcatUpperUpper(d4, ba_lo, rg_lo);
        const auto p2 = hn::ConcatLowerLower(d4, ba_hi, rg_hi), p3 = hn::ConcatUpperUpper(d4, ba_hi, rg_hi);
        if ((reinterpret_cast<uintptr_t>(dst) & 15) == 0) {
          hn::Stream(p0, d4, dst);
          hn::Stream(p1, d4, dst + 4);
          hn::Stream(p2, d4, dst + 8);
          hn::Stream(p3, d4, dst + 12);
        } else {
          hn::StoreU(p0, d4, dst);
          hn::StoreU(p1, d4, dst + 4);
          hn::StoreU(p2, d4, dst + 8);
          hn::StoreU(p3, d4, dst + 12);
        }
#endif
      }
      for (int32_t x = whole; x < w; ++x) {
        const uint32_t src = BlockIndex(x, y, 0, 0) * kBlockLanes + lane_row + (x % kBlockSize);
        for (int c = 0; c < 4; ++c) t.color[(row + x) * 4 + c] = s.color[c][src];
      }
    }
    if (t.depth) {
      ResolvePlaneRow(s.depth, y, w, t.depth + row);
      for (int32_t x = 0; x < w; ++x) t.depth[row + x] = std::min(t.depth[row + x], 1.0f);  // the clear reads 1
    }
    if (t.overdraw) ResolvePlaneRow(s.overdraw, y, w, t.overdraw + row);
    if (t.id)
      for (int32_t x = 0; x < w; ++x) {
        const uint32_t v = s.vis[BlockIndex(x, y, 0, 0) * kBlockLanes + lane_row + (x % kBlockSize)];
        if (v == kNoPrimitive) {
          t.id[row + x] = 0;
        } else {
          const TriSetup& tri = SetupOf(frame, v);
          const DrawCall& d = frame.draws[tri.draw];
          t.id[row + x] = d.id_base + (d.triangle_ids ? d.triangle_ids[tri.primitive] : tri.primitive) + 1;
        }
      }
  }
}

// A tile no triangle touches: the background written straight into the caller's planes,
// the same values ClearTile + ResolveTile would give, without the tile planes' round trip
// (most tiles of a frame with one object in the middle are empty).
void FillEmptyTile(const FrameView& frame, int32_t tx0, int32_t ty0) {
  const RenderTarget& t = frame.target;
  const int32_t w = std::min(kTileSize, frame.vp.width - tx0);
  const int32_t h = std::min(kTileSize, frame.vp.height - ty0);
  const glm::vec4 bg = frame.options.background;
#if HWY_TARGET != HWY_SCALAR
  const hn::CappedTag<float, 4> d4;
  alignas(16) const float rgba[4] = {bg.r, bg.g, bg.b, bg.a};
  const auto px = hn::Load(d4, rgba);
#endif
  for (int32_t y = 0; y < h; ++y) {
    const size_t row = static_cast<size_t>(ty0 + y) * t.width + tx0;
    if (t.color) {
      float* dst = t.color + row * 4;
      int32_t x = 0;
#if HWY_TARGET != HWY_SCALAR
      if ((reinterpret_cast<uintptr_t>(dst) & 15) == 0)
        for (; x < w; ++x) hn::Stream(px, d4, dst + 4 * x);
#endif
      for (; x < w; ++x)
        for (int c = 0; c < 4; ++c) dst[4 * x + c] = bg[c];
    }
    if (t.color8) std::memcpy(t.color8 + row * 4, frame.background8, 4 * size_t(w));
    if (t.depth) std::fill(t.depth + row, t.depth + row + w, 1.0f);
    if (t.overdraw) std::fill(t.overdraw + row, t.overdraw + row + w, 0u);
    if (t.id) std::fill(t.id + row, t.id + row + w, 0u);
  }
}

// Room for at least n elements, exactly n when the vector must grow and nothing copied (its
// elements are dropped then): the exact sort's lists hold at most the cap, which a vector grown
// by doubling could pass by half again.
template <class T>
void ReserveExactly(std::vector<T>& v, size_t n) {
  if (v.capacity() >= n) return;
  v.clear();
  v.reserve(n);
}

// SortMode::Exact: each pixel's fragments, farthest first (submission order among equal
// depths), composited src-over onto the opaque result. Called per tile, after pass 3.
//
// The fragments are first copied into runs, one per pixel, each in submission order: sorting
// indices into the tile's whole list (a few MB on a furry tile) made every comparison a cache
// miss, 43 % of an exact-sorted box frame. A short run is sorted in place by insertion, which
// moves a fragment only past strictly nearer ones and so keeps equal depths in submission
// order; a long one (a pile of translucent layers) through its indices, by the same order.
void CompositeExact(TileScratch& s) {
  const size_t count = s.fragments.size();
  if (count == 0) return;
  s.pixel_start.assign(kTilePixels + 1, 0);
  for (const auto& f : s.fragments) ++s.pixel_start[f.pixel + 1];
  for (uint32_t p = 0; p < kTilePixels; ++p) s.pixel_start[p + 1] += s.pixel_start[p];
  ReserveExactly(s.by_pixel, count);
  s.by_pixel.resize(count);
  s.pixel_next.assign(s.pixel_start.begin(), s.pixel_start.end() - 1);
  for (const auto& f : s.fragments) s.by_pixel[s.pixel_next[f.pixel]++] = f;
  constexpr uint32_t kInsertionMax = 64;
  for (uint32_t p = 0; p < kTilePixels; ++p) {
    TileScratch::Fragment* run = s.by_pixel.data() + s.pixel_start[p];
    const uint32_t n = s.pixel_start[p + 1] - s.pixel_start[p];
    if (n == 0) continue;
    float c[4] = {s.color[0][p], s.color[1][p], s.color[2][p], s.color[3][p]};
    // As FlushBatch's Max/Min: a NaN alpha counts as 0, so the sort mode changes only the order.
    auto blend = [&](const TileScratch::Fragment& f) {
      const float a = f.rgba[3] > 0.0f ? std::min(f.rgba[3], 1.0f) : 0.0f, keep = 1.0f - a;
      for (int k = 0; k < 3; ++k) c[k] = f.rgba[k] * a + c[k] * keep;
      c[3] = a + c[3] * keep;
    };
    if (n <= kInsertionMax) {
      for (uint32_t i = 1; i < n; ++i) {
        const TileScratch::Fragment f = run[i];
        uint32_t j = i;
        for (; j > 0 && run[j - 1].depth < f.depth; --j) run[j] = run[j - 1];
        run[j] = f;
      }
      for (uint32_t i = 0; i < n; ++i) blend(run[i]);
    } else {
      std::vector<uint32_t>& order = s.fragment_order;
      order.resize(n);
      for (uint32_t i = 0; i < n; ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return run[a].depth > run[b].depth || (run[a].depth == run[b].depth && a < b);
      });
      for (uint32_t i : order) blend(run[i]);
    }
    for (int k = 0; k < 4; ++k) s.color[k][p] = c[k];
  }
  s.fragments.clear();
}

// At most how many pixel centres triangle t covers in all: a convex set of area A and perimeter P
// holds at most A + P / 2 + 1 lattice points (Nosarzewska's bound), here with A from the edge
// functions' sum (512 A, less their floors) and P from their steps (1/256 pixel). A fur fin or a
// sliver, whose bounding box spans tiles it barely touches, is bounded by its few pixels.
inline uint64_t CentreBound(const TriSetup& t) {
  double two_area = 0.0, perimeter = 0.0;
  for (const EdgeEq& e : t.edge) {
    two_area += double(eval_edge(e, t.x0, t.y0));
    perimeter += std::hypot(double(e.a), double(e.b));
  }
  const double bound = two_area / 512.0 + perimeter / 512.0 + 2.0;  // + 1 for the floors and rounding
  return bound < 1e18 ? uint64_t(bound) : uint64_t{1} << 60;
}

// SortMode::Exact's translucent pass in regions of the tile that each leave at most `cap`
// fragments (RenderOptions::exact_fragment_cap): pass(valid, bx0, by0, bx1, by1) for each, its
// blocks [bx0, bx1] x [by0, by1] in `valid` (the tile's own valid lanes there, none elsewhere).
// An item leaves at most 16 fragments in each block of its bounding box, and at most its
// CentreBound: where the tile's sum of the smaller is within the cap (every furry tile measured)
// it is one pass, after a walk over its set-ups (2-3 % of an exact fur frame). Otherwise the fragments the
// depth test passes are counted per block first (coverage and depth alone, no write, no
// shading), and only a tile that leaves more than the cap is drawn in bands of whole block rows,
// a row over the cap alone in runs of its blocks. Each pixel still blends the same fragments in
// the same order; only how a batch packs its blocks changes, which for a shader with derivatives
// may move a block's level of detail (a slot merges the triangles the batch still holds), so a
// banded tile is the same image up to that. A tile that stays within the cap is drawn as it
// always was (the default scene's busiest tile holds 68 k fragments against the cap's 524 k).
template <class Pass>
void ExactPasses(const FrameView& frame, TileScratch& s, int32_t tx0, int32_t ty0, uint32_t cap, Pass&& pass) {
  constexpr int kSide = kBlocksPerTileSide;
  uint64_t total = 0;
  // Additive fragments blend at once and are never held: not counted.
  const auto held = [&](const TriSetup& t) { return frame.draws[t.draw].state.blend == BlendMode::AlphaOver; };
  // The set-ups are read here first, usually from L3 or memory: fetched ahead as the pass does.
  const size_t items = s.translucent.size();
  for (size_t k = 0; k < items; ++k) {
    if (k + kPrefetchAhead < items) PrefetchSetup(s.translucent[k + kPrefetchAhead].tri);
    const TriSetup& t = *s.translucent[k].tri;
    TileBlocks b;
    if (!held(t) || !tile_blocks(t, tx0, ty0, b)) continue;
    const uint64_t box = uint64_t(b.c1 - b.c0 + 1) * uint64_t(b.r1 - b.r0 + 1) * kBlockLanes;
    total += std::min(box, CentreBound(t));
  }
  // The list reserved to what the pass may hold, at most the cap.
  if (total <= cap) {
    ReserveExactly(s.fragments, size_t(total));
    return pass(s.block_valid, 0, 0, kSide - 1, kSide - 1);
  }
  uint64_t bound[kBlocksPerTile] = {};
  total = 0;
  for (const TranslucentRef& ref : s.translucent) {
    const TriSetup& t = *ref.tri;
    if (!held(t)) continue;
    TileEdges te;
    if (!tile_region_edges(t, tx0, ty0, te)) continue;
    DispatchDepth(frame.draws[t.draw].state, [&]<DepthFunc F, bool W>() {
      ForEachCoveredBlock(te, tx0, ty0, s.block_valid, [&](int32_t px, int32_t py, uint32_t blk, uint32_t bits) {
        const uint32_t passed = uint32_t(std::popcount(DepthTestBlock<F, false, false>(t, px, py, blk, bits, ref.id, s)));
        bound[blk] += passed;
        total += passed;
      });
    });
  }
  ReserveExactly(s.fragments, size_t(std::min<uint64_t>(total, cap)));
  if (total <= cap) return pass(s.block_valid, 0, 0, kSide - 1, kSide - 1);
  uint64_t row[kSide] = {};
  for (int b = 0; b < kBlocksPerTile; ++b) row[b / kSide] += bound[b];
  alignas(64) uint16_t valid[kBlocksPerTile];
  auto region = [&](int bx0, int by0, int bx1, int by1) {
    for (int b = 0; b < kBlocksPerTile; ++b) {
      const int bx = b % kSide, by = b / kSide;
      valid[b] = bx >= bx0 && bx <= bx1 && by >= by0 && by <= by1 ? s.block_valid[b] : uint16_t{0};
    }
    pass(valid, bx0, by0, bx1, by1);
  };
  for (int r = 0; r < kSide;) {
    if (row[r] > cap) {  // alone, in runs of blocks
      for (int c = 0; c < kSide;) {
        uint64_t sum = bound[r * kSide + c];
        int c1 = c + 1;
        while (c1 < kSide && sum + bound[r * kSide + c1] <= cap) sum += bound[r * kSide + c1++];
        region(c, r, c1 - 1, r);
        c = c1;
      }
      ++r;
      continue;
    }
    uint64_t sum = row[r];
    int r1 = r + 1;
    while (r1 < kSide && row[r1] <= cap && sum + row[r1] <= cap) sum += row[r1++];
    region(0, r, kSide - 1, r1 - 1);
    r = r1;
  }
}

void RasterTile(const FrameView& frame, uint32_t tile, TileScratch& s) {
  const int32_t tx0 = static_cast<int32_t>(tile % frame.tiles_x) * kTileSize;
  const int32_t ty0 = static_cast<int32_t>(tile / frame.tiles_x) * kTileSize;
  if (frame.tile_load[tile] == 0) {
    FillEmptyTile(frame, tx0, ty0);
    return;
  }
  ClearTile(frame, tx0, ty0, s);
  s.translucent.clear();
  s.alpha_tested.clear();
  s.fragments.clear();
  s.batch_blocks = 0;

  // Pass 1: opaque visibility.
  ForEachItem(frame, tile, [&](const TriSetup& t, uint32_t id, uint32_t draw_index) {
    const DrawCall& draw = frame.draws[draw_index];
    if (draw.state.blend != BlendMode::Opaque) {
      s.translucent.push_back({&t, id, t.sort_key});
      return;
    }
    if (draw.state.alpha_test) {
      s.alpha_tested.push_back({&t, id, t.sort_key});
      return;
    }
    TileEdges te;
    if (!tile_region_edges(t, tx0, ty0, te)) return;
    DispatchDepth(draw.state, [&]<DepthFunc F, bool W>() {
      ForEachCoveredBlock(te, tx0, ty0, s.block_valid, [&](int32_t px, int32_t py, uint32_t blk, uint32_t bits) {
        s.fragments_visible += std::popcount(DepthTestBlock<F, W, true>(t, px, py, blk, bits, id, s));
      });
    });
  });

  // Pass 1, alpha-tested draws: each triangle's fragments that pass the depth test as it
  // stands, one slot per (triangle, block) so that a slot's lanes are one triangle's (its
  // visibility id) and its derivatives its own; FlushBatch keeps those whose alpha reaches
  // the cutoff and tests them again, in order.
  for (const TranslucentRef& ref : s.alpha_tested) {
    const TriSetup& t = *ref.tri;
    const DrawCall& draw = frame.draws[t.draw];
    // The previous draw's kept fragments are written before this draw's are tested: under
    // DepthFunc::Always they may have raised the depth a test below would compare with.
    if (s.batch_blocks > 0 && s.batch_draw != t.draw) FlushBatch(frame, s, Flush::alpha_test);
    TileEdges te;
    if (!tile_region_edges(t, tx0, ty0, te)) continue;
    TriVaryings tv;  // made at the first block with a fragment
    bool tv_made = false;
    DispatchDepth(draw.state, [&]<DepthFunc F, bool W>() {
      ForEachCoveredBlock(te, tx0, ty0, s.block_valid, [&](int32_t px, int32_t py, uint32_t blk, uint32_t bits) {
        const uint32_t passed = DepthTestBlock<F, false, false>(t, px, py, blk, bits, ref.id, s);
        if (!passed) return;
        if (!tv_made) {
          MakeTriVaryings(frame, t, tv);
          tv_made = true;
        }
        const uint32_t slot = OpenSlot(frame, s, t.draw, px, py, blk, Flush::alpha_test);
        Interpolate(s, slot, t, tv, passed, true);
        s.batch_tri[slot] = &t;
        s.batch_id[slot] = ref.id;
      });
    });
  }
  FlushBatch(frame, s, Flush::alpha_test);

  // Pass 2: shade each visible opaque pixel once, with the triangle that owns it. The
  // visible triangles of a block share one batch slot (per draw), so the shader sees
  // full blocks rather than one block per (triangle, block) pair.
  s.visible.clear();
  {
    const DU du;
    const size_t n = hn::Lanes(du);
    // Lanes of the block whose visible triangle is `id`, as block bits.
    auto lanes_equal = [&](const uint32_t* vis, uint32_t id) {
      uint32_t bits = 0;
      for (size_t g = 0; g * n < kBlockLanes; ++g)
        bits |= MaskToBits(du, hn::Eq(hn::Load(du, vis + g * n), hn::Set(du, id))) << (g * n);
      return bits;
    };
    for (uint32_t blk = 0; blk < kBlocksPerTile; ++blk) {
      const uint32_t* vis = s.vis + blk * kBlockLanes;
      uint32_t left = ~lanes_equal(vis, kNoPrimitive) & 0xFFFFu;
      while (left) {
        const uint32_t id = vis[std::countr_zero(left)];
        const uint32_t bits = lanes_equal(vis, id);
        left &= ~bits;
        // The set-up's address and draw from its chunk, without loading the set-up itself
        // (pass 2's loop below prefetches it ahead of use).
        const BinChunk& ch = frame.chunks[id >> kSetupIndexBits];
        s.visible.push_back({ch.setups.data() + (id & ((1u << kSetupIndexBits) - 1)), ch.draw, blk, bits});
      }
    }
  }
  // Draw by draw (a batch holds one draw's blocks); within a draw in the order the list was
  // built: by block, then by the first lane a triangle owns in it (distinct within a block).
  // That key is total, so std::sort gives the stable order without a temporary buffer.
  if (frame.chunk_count > 0 && frame.chunks[0].draw != frame.chunks[frame.chunk_count - 1].draw)
    std::sort(s.visible.begin(), s.visible.end(), [](const TileScratch::Visible& a, const TileScratch::Visible& b) {
      if (a.draw != b.draw) return a.draw < b.draw;
      if (a.block != b.block) return a.block < b.block;
      return std::countr_zero(a.bits) < std::countr_zero(b.bits);
    });
  // Interpolation reads, per visible triangle, its set-up, its three indices and its
  // three vertices' varyings: dependent loads at random addresses of a large mesh. Each is
  // fetched a few triangles ahead of its use, once the load it depends on has arrived.
  auto prefetch_indices = [&](const TriSetup& t) {
    hwy::Prefetch(frame.draws[t.draw].indices + 3 * size_t{t.primitive});
  };
  auto prefetch_varyings = [&](const TriSetup& t) {
    const DrawCall& d = frame.draws[t.draw];
    const uint32_t* tri = d.indices + 3 * size_t{t.primitive};
    for (int c = 0; c < 3; ++c) {
      const float* a = d.varyings + size_t{tri[c]} * d.varying_count;
      hwy::Prefetch(a);
      if (d.varying_count > 0) hwy::Prefetch(a + d.varying_count - 1);
    }
  };
  const size_t visible_count = s.visible.size();
  uint32_t derivatives_draw = kNoPrimitive;  // uses_derivatives() asked once per draw, not per entry
  bool derivatives = true;
  for (size_t k = 0; k < visible_count; ++k) {
    if (k + 2 * kPrefetchAhead < visible_count) PrefetchSetup(s.visible[k + 2 * kPrefetchAhead].tri);
    if (k + kPrefetchAhead < visible_count) prefetch_indices(*s.visible[k + kPrefetchAhead].tri);
    if (k + kPrefetchAhead / 2 < visible_count) prefetch_varyings(*s.visible[k + kPrefetchAhead / 2].tri);
    const TileScratch::Visible& v = s.visible[k];
    if (v.draw != derivatives_draw) {
      derivatives_draw = v.draw;
      derivatives = frame.draws[v.draw].shader->uses_derivatives();
    }
    const bool same_slot = k > 0 && s.visible[k - 1].block == v.block &&
                           s.visible[k - 1].draw == v.draw && s.batch_blocks > 0 && !derivatives;
    const int32_t px = tx0 + int32_t(v.block % kBlocksPerTileSide) * kBlockSize;
    const int32_t py = ty0 + int32_t(v.block / kBlocksPerTileSide) * kBlockSize;
    const uint32_t slot = same_slot ? s.batch_blocks - 1 : OpenSlot(frame, s, v.draw, px, py, v.block, Flush::store);
    TriVaryings tv;
    MakeTriVaryings(frame, *v.tri, tv);
    Interpolate(s, slot, *v.tri, tv, v.bits, derivatives);
    s.pixels_shaded += std::popcount(v.bits);
  }
  FlushBatch(frame, s, Flush::store);

  // Pass 3: translucent fragments, back to front per tile when asked.
  // Back to front; equal keys keep submission order, which setup ids follow (frame.h).
  if (frame.options.sort == SortMode::Tile) sort_back_to_front(s.translucent, s.translucent_scratch);
  // The same chain of dependent loads as pass 2 (set-up, indices, varyings), fetched ahead in
  // the same stages: sorted back to front, a tile's triangles visit the mesh in no useful order.
  const size_t translucent_count = s.translucent.size();
  const bool count_overdraw = frame.target.overdraw != nullptr;
  const bool exact = frame.options.sort == SortMode::Exact;
  // The items whose bounding box meets the tile's blocks [bx0, bx1] x [by0, by1], on the blocks
  // `valid` holds; then their blend, or under the exact sort their composite.
  auto translucent_pass = [&](const uint16_t* valid, int32_t bx0, int32_t by0, int32_t bx1, int32_t by1) {
    const int32_t rx0 = tx0 + bx0 * kBlockSize, ry0 = ty0 + by0 * kBlockSize;
    const int32_t rx1 = tx0 + (bx1 + 1) * kBlockSize - 1, ry1 = ty0 + (by1 + 1) * kBlockSize - 1;
    for (size_t k = 0; k < translucent_count; ++k) {
      if (k + 2 * kPrefetchAhead < translucent_count) PrefetchSetup(s.translucent[k + 2 * kPrefetchAhead].tri);
      if (k + kPrefetchAhead < translucent_count) prefetch_indices(*s.translucent[k + kPrefetchAhead].tri);
      if (k + kPrefetchAhead / 2 < translucent_count) prefetch_varyings(*s.translucent[k + kPrefetchAhead / 2].tri);
      const TranslucentRef& ref = s.translucent[k];
      const TriSetup& t = *ref.tri;
      if (t.xmax < rx0 || t.x0 > rx1 || t.ymax < ry0 || t.y0 > ry1) continue;
      const DrawCall& draw = frame.draws[t.draw];
      TileEdges te;
      if (!tile_region_edges(t, tx0, ty0, te)) continue;
      if (t.draw != derivatives_draw) {
        derivatives_draw = t.draw;
        derivatives = draw.shader->uses_derivatives();
      }
      TriVaryings tv;  // made at the first block with a fragment
      bool tv_made = false;
      DispatchDepth(draw.state, [&]<DepthFunc F, bool W>() {
        ForEachCoveredBlock(te, tx0, ty0, valid, [&](int32_t px, int32_t py, uint32_t blk, uint32_t bits) {
          const uint32_t passed = DepthTestBlock<F, W, false>(t, px, py, blk, bits, ref.id, s);
          if (passed) {
            s.fragments_blended += std::popcount(passed);
            if (count_overdraw) CountOverdraw(s, blk, passed);
            if (!tv_made) {
              MakeTriVaryings(frame, t, tv);
              tv_made = true;
            }
            AppendTranslucent(frame, s, t, tv, px, py, blk, passed, derivatives);
          }
        });
      });
    }
    FlushBatch(frame, s, Flush::blend);
    if (exact) {
      ++s.exact_passes;
      s.exact_fragments_peak = std::max<uint64_t>(s.exact_fragments_peak, s.fragments.size());
      CompositeExact(s);
    }
  };
  if (!exact || translucent_count == 0)
    translucent_pass(s.block_valid, 0, 0, kBlocksPerTileSide - 1, kBlocksPerTileSide - 1);
  else
    ExactPasses(frame, s, tx0, ty0, frame.options.exact_fragment_cap, translucent_pass);

  ResolveTile(frame, tx0, ty0, s);
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {
HWY_EXPORT(RasterTile);

void raster_tile(const FrameView& frame, uint32_t tile, TileScratch& scratch) {
  HWY_DYNAMIC_DISPATCH(RasterTile)(frame, tile, scratch);
}
}  // namespace pelt::raster
#endif
