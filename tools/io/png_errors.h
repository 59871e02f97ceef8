// libpng's error and warning callbacks for pelt's PNG reader and writer (png_reader.h,
// png_writer.h): an error's text is kept for the caller's message and control goes back to the
// setjmp of the call in progress; warnings are dropped, where libpng would print its own line.
#pragma once

#include <png.h>

#include <cstdio>

namespace pelt::io {

struct PngFailure {
  char message[256] = {};
};

// libpng calls this on an error; it must not return.
[[noreturn]] inline void png_failed(png_structp png, png_const_charp message) {
  auto* f = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(f->message, sizeof f->message, "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}

inline void png_warned(png_structp, png_const_charp) {}

}  // namespace pelt::io
