// EXR files read with OpenEXR's own library, not through OpenImageIO's module (image_backend.h),
// whose ~260 libraries took 0.4 s to load for a scene's EXR maps alone. It reads what OpenImageIO
// 2.4's EXR reader (on the same OpenEXR) gave pelt, to the bit (tests/tools/io/exr_reader_test.cpp
// compares the two on every pixel type, channel set, layout, level mode and compression):
//   - part 0 of a multi-part file, level 0 of a MIP- or RIP-mapped tiled one;
//   - its channels in OpenImageIO's order: by layer (the name up to its last dot; the root layer
//     first), within a layer R, Red, G, Green, B, Blue, Y, real, imag, A, Alpha, AR, RA, AG, GA, AB,
//     BA, Z, Depth, Zback (case ignored; X, Y, Z right after the colours in a layer holding X and Y
//     or Z), then the rest by name; alpha is the first whose last part is A or Alpha;
//   - every value as a 32-bit float: HALF and FLOAT as they are, UINT scaled to 0..1 as
//     OpenImageIO converts it (the value rounded to a float, times 2^-32);
//   - its data window and display window, which image_io compares.
// Refused, each with its reason: a deep file and one with subsampled channels (OpenImageIO's open
// or read failed on them), and, where OpenImageIO's channels would have been drawn as something
// they are not, a file of three or more channels whose first three (pelt's colour) are a
// luminance-chroma image (Y, RY, BY), include its alpha, or come from different layers; and a
// MIP-mapped cube-face environment map taller than wide (OpenImageIO made its frame one face, which
// image_io then refused as a data window).
#pragma once

#include <memory>
#include <string>

#include "tools/io/image_backend.h"

namespace pelt::io {

// Opens `file` and reads its headers and chunk tables, no pixels: OpenEXR's buffers for decoding,
// which grow with the image's width, are made in read(), after image_io has checked the size
// against the budget. nullptr with `error` set (OpenEXR's reason or pelt's) when it cannot. read()
// takes float (f32) and 1 up to the file's channel count, the first in the order above.
std::unique_ptr<ImageReader> open_exr(const std::string& file, std::string& error);

}  // namespace pelt::io
