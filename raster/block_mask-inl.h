// A block's 16-bit lane mask (bit l = lane l, FragmentBatch::mask) as vector masks, shared by
// the tile and texture kernels. A Highway per-target header: included after
// hwy/foreach_target.h, it is compiled once for every target by the toggle guard below.

#if defined(PELT_RASTER_BLOCK_MASK_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PELT_RASTER_BLOCK_MASK_INL_H_
#undef PELT_RASTER_BLOCK_MASK_INL_H_
#else
#define PELT_RASTER_BLOCK_MASK_INL_H_
#endif

#include "hwy/highway.h"
#include "raster/config.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The bits of one vector group of a block mask: N lanes (N <= 16; one AVX-512 vector is a block).
HWY_INLINE uint32_t GroupBits() {
  const size_t n = hn::Lanes(hn::ScalableTag<float>());
  return n >= size_t(kBlockLanes) ? 0xFFFFu : (1u << n) - 1u;
}

// Lanes [g N, g N + N) of block mask `bits` as a float vector mask.
HWY_INLINE hn::Mask<hn::ScalableTag<float>> BitsToMask(uint32_t bits, size_t g) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
#if HWY_TARGET <= HWY_AVX3
  // One vector is the block, and its mask register is the block mask itself: a move instead of a
  // broadcast, an AND and a compare per use (Highway 1.0 has no call for it).
  if constexpr (hn::MaxLanes(df) == size_t(kBlockLanes)) {
    (void)g;
    return hn::Mask<decltype(df)>{static_cast<__mmask16>(bits)};
  }
#endif
  const auto lane_bits = hn::LoadU(di, kLaneBit + g * hn::Lanes(di));
  return hn::RebindMask(df, hn::Ne(hn::And(hn::Set(di, static_cast<int32_t>(bits)), lane_bits), hn::Zero(di)));
}

// The lanes of mask m (a vector of at most 16 lanes) as bits, lane 0 in bit 0.
template <class D, class M>
HWY_INLINE uint32_t MaskToBits(D d, M m) {
#if HWY_TARGET <= HWY_AVX3
  if constexpr (hn::MaxLanes(d) == size_t(kBlockLanes)) return static_cast<uint32_t>(m.raw);  // a kmov
#endif
  uint8_t bytes[8] = {};
  hn::StoreMaskBits(d, m, bytes);
  return uint32_t{bytes[0]} | (uint32_t{bytes[1]} << 8);
}

}  // namespace pelt::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // PELT_RASTER_BLOCK_MASK_INL_H_ toggle
