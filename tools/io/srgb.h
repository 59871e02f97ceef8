// sRGB encoding and decoding (IEC 61966-2-1), exact to the byte.
#pragma once

#include <cstddef>
#include <cstdint>

#include "tools/io/image.h"

namespace pelt::io {

// The reference: s = 12.92 x for x <= 0.0031308, else 1.055 x^(1/2.4) - 0.055, evaluated
// in double; result round-half-up(255 s). x <= 0 and NaN give 0, x >= 1 gives 255.
uint8_t linear_to_srgb8(float x);

// round-half-up(255 x) with the same clamping: for alpha and other linear data.
uint8_t linear_to_unorm8(float x);

// The sRGB value of byte b decoded to linear (inverse transfer function, in double,
// rounded once to float).
float srgb8_to_linear(uint8_t b);

// Table-driven linear_to_srgb8, bit-identical to it for every float. For the 8-bit
// resolve of whole images.
uint8_t linear_to_srgb8_fast(float x);

// linear_to_srgb8 of n floats into n bytes, bit for bit, with SIMD: raster::srgb_bytes, the
// colour resolve of image writes.
void encode_srgb8_span(const float* src, uint8_t* dst, size_t n);

// Encodes `height` rows of `width` pixels with `channels` floats each (1..4) into bytes.
// Colour channels go through the sRGB curve; with 2 or 4 channels the last one is alpha
// and is encoded linearly (linear_to_unorm8), and colour given premultiplied is divided by it
// first (8-bit files hold straight colour; alpha at or below 0 gives colour 0, alpha 1 or
// more leaves it as it is). Strides are in elements (floats / bytes).
void encode_srgb8_rows(const float* src, size_t src_row_stride, uint8_t* dst, size_t dst_row_stride, int width,
                       int height, int channels, Alpha alpha);

// The smallest float whose sRGB byte is greater than b (b in 0..254): the boundaries the
// fast path is built on, exposed for the exhaustive boundary test.
float srgb8_threshold(int b);

}  // namespace pelt::io
