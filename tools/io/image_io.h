// Image files through OpenImageIO (in a module loaded on first use, image_backend.h), PNG
// files through libpng (png_writer.h, png_reader.h), JPEG input through libjpeg
// (jpeg_reader.h) and EXR files through OpenEXR (exr_writer.h, exr_reader.h): atomic writes of
// rendered images and AOVs, and colour-map reads. Failing to load the module is an InputError naming the
// file, like any other failure here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>

#include "tools/io/budget.h"
#include "tools/io/image.h"

namespace pelt::io {

// Type of the pixel values handed to write_image_atomic.
enum class PixelType {
  u8,   // bytes, written as they are
  u32,  // 32-bit unsigned integers (the id AOV)
  f32,  // linear floats
};

// Writes `width` x `height` pixels of `channels` (1..4) interleaved values of `type`,
// rows top to bottom, to `path`, choosing the file type by extension:
//   .png          u8 as is; f32 encoded to 8-bit sRGB (alpha, with 2 or 4 channels,
//                 linear), bit-exact with linear_to_srgb8.
//   .tif / .tiff  u8 as is; u32 with 1 channel as 32-bit unsigned; f32 with 1 channel as
//                 32-bit float; f32 with 2..4 channels as 8-bit sRGB like .png.
//   .exr          f32 as 32-bit float channels (1 = "Y", 2 = "Y", "A", 3 = RGB, 4 = RGBA), ZIP
//                 compressed, every value's bits kept (exr_writer.h).
// With 2 or 4 channels the last is alpha. 8-bit files hold straight (unassociated) colour and
// EXR premultiplied (associated) colour, OpenEXR's convention that its readers assume:
// float pixels are converted from `options.alpha` to the file's convention (colour divided
// by alpha for 8-bit files, where alpha is above 0, and 0 where it is 0; multiplied for EXR).
// u8 pixels are taken as straight.
// The data go first to `.NAME.tmp-PID-TOKEN-N` (io::temp_beside) in the target's folder, which is renamed over
// `path` only after the whole write succeeded; on any failure the temporary is removed
// and InputError(path, "", reason) is thrown, leaving no partial output. An unknown
// extension or an unsupported (type, channels) for the extension is an InputError too.
// PNG files: zlib level 0 (stored) to 9 (smallest, slowest), every row through libpng's
// Up filter. The default, 1, writes a 1024x768 fur frame in about half the time of level 6
// (OpenImageIO's own default) for a file about a sixth larger (README, `pelt render`).
inline constexpr int kDefaultPngCompression = 1;
struct ImageWriteOptions {
  int png_compression = kDefaultPngCompression;  // 0..9; other values are an InputError
  Alpha alpha = Alpha::straight;                 // how f32 colour with alpha is given
};
void write_image_atomic(const std::filesystem::path& path, int width, int height, int channels,
                        PixelType type, const void* pixels, const ImageWriteOptions& options = {});

// Whether writing `path` (by its extension; a GIF's too, gif_writer.h) or reading the image at
// `path` (by its signature, encoded_kind) loads OpenImageIO's module: PNG files are written and read by libpng
// itself (png_writer.h, png_reader.h), EXR files written and read by OpenEXR's library
// (exr_writer.h, exr_reader.h), JPEG files (FF D8 FF) read by libjpeg (jpeg_reader.h), every other
// type through the module. For a command that loads the module ahead, on a thread of its own, only
// where it will need it.
bool needs_image_module_to_write(const std::filesystem::path& path);
bool needs_image_module_to_read(const std::filesystem::path& path);

// Reads an image as linear float RGBA (grey is replicated, a missing alpha is 1), colour
// as stored (straight alpha for PNG; nothing is multiplied by alpha).
// 8 and 16-bit integer files are decoded with `encoding` (sRGB for colour maps); float
// and half files are taken as linear. Throws InputError naming the file.
// The header is read first: an image wider or taller than budget.max_texture_side is
// refused (InputError naming both sizes and --max-texture-side) before any pixel buffer
// is allocated.
// `used`: the channels (of r, g, b, a, in order) the caller draws. A non-finite value in one of
// them is refused naming its texel and channel; in another it is set to 0, since nothing reads
// it (a colour map's alpha, a length map's g, b and a).
ImageRGBA read_image_rgba(const std::filesystem::path& path, ColorEncoding encoding = ColorEncoding::srgb,
                          const Budget& budget = Budget{}, int used = 4);

// An image file's size from its header alone (no pixels are read),
// for estimating memory before loading. Throws InputError naming the file when it cannot
// be opened as an image.
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  int bytes_per_channel = 0;  // 1 or 2 for 8 and 16-bit files, 4 for everything read as float
};
ImageHeader read_image_header(const std::filesystem::path& path);

// An encoded image's type by its first bytes: the PNG signature (8 bytes), a JPEG's
// start-of-image marker and the marker after it (FF D8 FF), or OpenEXR's magic number (76 2F 31
// 01); `other` for anything else, or too few bytes. pelt reads PNG, JPEG and EXR files itself
// (png_reader.h, jpeg_reader.h, exr_reader.h), and checks the size of embedded PNG and JPEG ones
// before decoding them (encoded_image_size).
enum class EncodedKind { png, jpeg, exr, other };
inline constexpr size_t kEncodedKindBytes = 8;  // enough of a file's head for encoded_kind
EncodedKind encoded_kind(const uint8_t* bytes, size_t size);
// The same, of a file's head (`other` when it cannot be read).
EncodedKind encoded_kind(const std::filesystem::path& path);

// Width and height of an encoded PNG (IHDR) or JPEG (first SOFn marker) held in memory,
// from the header bytes alone; nullopt when the bytes are neither or the header is cut
// short or names a zero size. Used to check embedded glTF images before they are decoded.
struct EncodedImageSize {
  int64_t width = 0, height = 0;
};
std::optional<EncodedImageSize> encoded_image_size(const uint8_t* bytes, size_t size);

}  // namespace pelt::io
