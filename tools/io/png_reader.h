// PNG files read with libpng itself, not through OpenImageIO's module (image_backend.h), whose
// ~260 libraries took 0.4 s to load for a scene's PNG maps alone. It reads what OpenImageIO's
// PNG reader gave pelt, to the value (tests/tools/io/png_reader_test.cpp compares the two on
// every colour type and bit depth): palettes expanded to RGB, a tRNS chunk to an alpha channel,
// grey of 1, 2 or 4 bits to 8, 16-bit samples kept, no gamma applied, values as stored (no
// alpha association); a file whose gAMA exponent rounds to 1.00 and that has no sRGB chunk is
// declared linear.
#pragma once

#include <memory>
#include <string>

#include "tools/io/image_backend.h"

namespace pelt::io {

// Opens `file` and reads its header; nullptr with `error` set (libpng's reason or the system's)
// when it cannot. The reader's read() takes the file's own channel count and type.
std::unique_ptr<ImageReader> open_png(const std::string& file, std::string& error);

}  // namespace pelt::io
