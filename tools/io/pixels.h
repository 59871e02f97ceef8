// Conversion of interleaved integer or float pixels into ImageRGBA.
#pragma once

#include <cstdint>

#include "tools/io/image.h"

namespace pelt::io {

// `data` holds width*height pixels of `channels` (1..4) values, each `bits` wide (8 or 16
// unsigned, or 32 for float), rows top to bottom. 1 channel is grey, 2 grey+alpha, 3 RGB,
// 4 RGBA; a missing alpha is 1. Integer colour channels are decoded with `encoding`;
// alpha and float channels are taken as linear. Returns an empty image for an
// unsupported (channels, bits) pair.
ImageRGBA pixels_to_rgba(const void* data, int width, int height, int channels, int bits,
                         ColorEncoding encoding);

}  // namespace pelt::io
