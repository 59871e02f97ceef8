#include "tools/io/png_writer.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "tools/io/png_errors.h"

namespace pelt::io {
namespace {

// libpng's own writer reports a short write as "Write Error"; this one gives the system's reason
// (a full disk: "No space left on device").
void write_bytes(png_structp png, png_bytep data, size_t length) {
  if (std::fwrite(data, 1, length, static_cast<std::FILE*>(png_get_io_ptr(png))) != length)
    png_error(png, std::strerror(errno));
}
void flush_nothing(png_structp) {}  // the caller flushes once the file is whole

// The libpng calls alone, with no C++ object between setjmp and a longjmp that could skip its
// destructor. Returns false with `failure` filled.
bool encode(std::FILE* out, int width, int height, int channels, const uint8_t* pixels, int compression,
            PngFailure& failure) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &failure, png_failed, png_warned);
  if (!png) {
    std::snprintf(failure.message, sizeof failure.message, "libpng could not start a PNG");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    if (!info) std::snprintf(failure.message, sizeof failure.message, "libpng could not start a PNG");
    png_destroy_write_struct(&png, &info);
    return false;
  }
  static constexpr int kColorType[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_write_fn(png, out, write_bytes, flush_nothing);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, kColorType[channels - 1], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // sRGB, and for readers that do not know the chunk its gAMA and cHRM, as OpenImageIO wrote it
  // (rendering intent absolute colorimetric, its choice).
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_ABSOLUTE);
  png_set_compression_level(png, compression);
  // The Up filter on every row: as small or smaller than libpng's adaptive choice on rendered
  // frames, and no time spent choosing (README, --png-compression).
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_write_info(png, info);
  const size_t stride = size_t(width) * size_t(channels);
  for (int y = 0; y < height; ++y) png_write_row(png, pixels + size_t(y) * stride);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::string write_png8(const std::string& file, int width, int height, int channels, const uint8_t* pixels,
                       int compression) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || !pixels || compression < 0 || compression > 9)
    return "cannot write this PNG (size, channels or compression out of range)";
  std::FILE* out = std::fopen(file.c_str(), "wb");
  if (!out) return "cannot create the image file: " + std::string(std::strerror(errno));
  PngFailure failure;
  const bool encoded = encode(out, width, height, channels, pixels, compression, failure);
  // A short write shows at the latest here, where the buffered bytes reach the file.
  int error = 0;
  if (std::fflush(out) != 0) error = errno;
  if (std::fclose(out) != 0 && error == 0) error = errno;
  if (!encoded) return "writing the image failed: " + std::string(failure.message);
  if (error != 0) return "finishing the image file failed: " + std::string(std::strerror(error));
  return {};
}

}  // namespace pelt::io
