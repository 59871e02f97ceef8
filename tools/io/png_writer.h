// 8-bit PNG files written with libpng itself, not through OpenImageIO's module (image_backend.h):
// loading that module's ~260 libraries took 0.4 s, twenty times the render of a small frame, and
// a PNG is what most renders write. The file holds what OpenImageIO's PNG writer put there for
// pelt (the same pixels, sRGB with its gAMA and cHRM chunks, every row through the Up filter at
// the given zlib level) without its oFFs and `oiio:ColorSpace` text chunks.
#pragma once

#include <cstdint>
#include <string>

namespace pelt::io {

// Writes `width` x `height` pixels of `channels` (1 grey, 2 grey and alpha, 3 RGB, 4 RGBA)
// interleaved bytes, rows top to bottom, to `file` (created or truncated), at zlib level
// `compression` (0..9). Returns "" on success, else the reason (libpng's or the system's), and
// the caller removes the file.
std::string write_png8(const std::string& file, int width, int height, int channels, const uint8_t* pixels,
                       int compression);

}  // namespace pelt::io
