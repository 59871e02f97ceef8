// Fixed constants of the rasterizer. Everything that depends on them derives from them.
#pragma once

#include <cstdint>

namespace pelt::raster {

// A worker owns one tile; 64x64 float RGBA + depth + id is 96 KiB, resident in L2.
inline constexpr int kTileSize = 64;
// Pixels are shaded and stored in 4x4 blocks of 16 lanes (one AVX-512 vector, two AVX2).
inline constexpr int kBlockSize = 4;
inline constexpr int kBlockLanes = kBlockSize * kBlockSize;
inline constexpr int kBlocksPerTileSide = kTileSize / kBlockSize;
inline constexpr int kBlocksPerTile = kBlocksPerTileSide * kBlocksPerTileSide;
inline constexpr int kTilePixels = kTileSize * kTileSize;

// Lane layout of a 4x4 block, and each lane's bit in a block mask.
alignas(64) inline constexpr int32_t kLaneX[kBlockLanes] = {0, 1, 2, 3, 0, 1, 2, 3,
                                                            0, 1, 2, 3, 0, 1, 2, 3};
alignas(64) inline constexpr int32_t kLaneY[kBlockLanes] = {0, 0, 0, 0, 1, 1, 1, 1,
                                                            2, 2, 2, 2, 3, 3, 3, 3};
alignas(64) inline constexpr int32_t kLaneBit[kBlockLanes] = {
    1 << 0, 1 << 1, 1 << 2,  1 << 3,  1 << 4,  1 << 5,  1 << 6,  1 << 7,
    1 << 8, 1 << 9, 1 << 10, 1 << 11, 1 << 12, 1 << 13, 1 << 14, 1 << 15};

// 8 sub-pixel bits: positions snap to 1/256 pixel.
inline constexpr int kSubPixelBits = 8;
inline constexpr int kSubPixelScale = 1 << kSubPixelBits;

// Guard band, in pixels beyond each side of the viewport. Triangles are clipped in x/y
// only where they leave it. With the image limit below, every snapped coordinate span is
// at most 2^15 pixels = 2^23 sub-pixel units, so edge coefficients fit in 24 bits and an
// edge evaluated over a tile it crosses fits in int32 (see setup.h).
inline constexpr int kGuardBand = 8192;
inline constexpr int kMaxImageSide = 16384;

// Per-fragment interpolated attributes a draw may carry.
inline constexpr int kMaxVaryings = 24;

// A shader sees at most this many 4x4 blocks per call.
inline constexpr uint32_t kMaxBatchBlocks = 64;
inline constexpr uint32_t kMaxBatchLanes = kMaxBatchBlocks * kBlockLanes;

// Visibility-buffer value of an empty pixel.
inline constexpr uint32_t kNoPrimitive = 0xFFFFFFFFu;

// RenderOptions::exact_fragment_cap's default: 2^19 fragments, 24 MiB of a worker's two lists.
// A furry tile leaves about 70 k (the box at 1024 x 768); a power of two, so a list that grows
// by doubling stops at it.
inline constexpr uint32_t kExactFragmentCap = 1u << 19;

// The depth a tile is cleared to: one float step above the far plane's depth 1. Window depth is
// about 1 - near / distance, which rounds to exactly 1 for a surface more than about 2^24 x near
// away (near 1e-7 and a box 5 units off, or near 0.1 and an object 5e6 away); against a clear of
// 1 such a surface failed every depth test and the whole object vanished without a word. Against
// this clear it is drawn, at the far plane's depth (ties there go to the first drawn, as with any
// equal depths). The depth image reads the clear as 1.
inline constexpr float kClearDepth = 0x1.000002p+0f;

}  // namespace pelt::raster
