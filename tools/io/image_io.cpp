#include "tools/io/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "tools/io/exr_reader.h"
#include "tools/io/exr_writer.h"
#include "tools/io/image_backend.h"
#include "tools/io/input_error.h"
#include "tools/io/jpeg_reader.h"
#include "tools/io/output_file.h"
#include "tools/io/pixels.h"
#include "tools/io/png_reader.h"
#include "tools/io/png_writer.h"
#include "tools/io/srgb.h"

namespace pelt::io {
namespace {

enum class FileKind { png, tiff, exr };

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

FileKind kind_of(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return FileKind::png;
  if (ext == ".tif" || ext == ".tiff") return FileKind::tiff;
  if (ext == ".exr") return FileKind::exr;
  throw InputError(path.string(), "", "unsupported image extension `" + path.extension().string() +
                                          "` (expected .png, .tif, .tiff or .exr)");
}

const char* type_name(PixelType t) {
  switch (t) {
    case PixelType::u8: return "8-bit";
    case PixelType::u32: return "32-bit unsigned";
    case PixelType::f32: return "float";
  }
  return "?";
}

// Straight colour with alpha as EXR stores it: each colour channel times the pixel's alpha.
std::vector<float> premultiplied(const float* px, size_t pixels, int channels) {
  const size_t nc = static_cast<size_t>(channels);
  std::vector<float> out(px, px + pixels * nc);
  for (size_t p = 0; p < out.size(); p += nc)
    for (size_t c = 0; c + 1 < nc; ++c) out[p + c] *= out[p + nc - 1];
  return out;
}

}  // namespace

bool needs_image_module_to_write(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext != ".png" && ext != ".exr";
}

namespace {

using OpenImage = std::unique_ptr<ImageReader> (*)(const std::string& file, std::string& error);

// pelt's own reader of the image at `path`, by its signature: libpng's for a PNG, libjpeg's for
// a JPEG, OpenEXR's for an EXR; nullptr for every other file, which the module reads.
OpenImage own_reader(const std::filesystem::path& path) {
  switch (encoded_kind(path)) {
    case EncodedKind::png: return open_png;
    case EncodedKind::jpeg: return open_jpeg;
    case EncodedKind::exr: return open_exr;
    case EncodedKind::other: break;
  }
  return nullptr;
}

}  // namespace

bool needs_image_module_to_read(const std::filesystem::path& path) { return own_reader(path) == nullptr; }

void write_image_atomic(const std::filesystem::path& path, int width, int height, int channels,
                        PixelType type, const void* pixels, const ImageWriteOptions& options) {
  const std::string file = path.string();
  const FileKind kind = kind_of(path);
  if (width <= 0 || height <= 0) throw InputError(file, "", "image size must be positive");
  if (channels < 1 || channels > 4) throw InputError(file, "", "channels must be 1..4");
  if (!pixels) throw InputError(file, "", "no pixel data");
  if (options.png_compression < 0 || options.png_compression > 9)
    throw InputError(file, "", "PNG compression level " + std::to_string(options.png_compression) +
                                   " outside 0..9");

  // Decide what goes into the file, converting float colour to sRGB bytes where needed.
  StoredType file_type;
  const void* data = pixels;
  std::vector<uint8_t> encoded;
  std::vector<float> associated;
  const bool float_as_srgb8 = type == PixelType::f32 &&
                              (kind == FileKind::png || (kind == FileKind::tiff && channels > 1));
  if (float_as_srgb8) {
    encoded.resize(static_cast<size_t>(width) * height * channels);
    encode_srgb8_rows(static_cast<const float*>(pixels), static_cast<size_t>(width) * channels, encoded.data(),
                      static_cast<size_t>(width) * channels, width, height, channels, options.alpha);
    data = encoded.data();
    file_type = StoredType::u8;
  } else if (type == PixelType::u8 && kind != FileKind::exr) {
    file_type = StoredType::u8;
  } else if (type == PixelType::u32 && kind == FileKind::tiff && channels == 1) {
    file_type = StoredType::u32;
  } else if (type == PixelType::f32 && (kind == FileKind::exr || kind == FileKind::tiff)) {
    file_type = StoredType::f32;
    if (kind == FileKind::exr && (channels == 2 || channels == 4) && options.alpha == Alpha::straight) {
      associated = premultiplied(static_cast<const float*>(pixels), static_cast<size_t>(width) * height, channels);
      data = associated.data();
    }
  } else {
    throw InputError(file, "", std::string("cannot write ") + type_name(type) + " pixels with " +
                                   std::to_string(channels) + " channel(s) to this file type " +
                                   "(32-bit unsigned needs one channel and .tif; .exr needs float)");
  }

  // A PNG (u8 here) through libpng itself (png_writer.h), an EXR (f32) through OpenEXR's library
  // (exr_writer.h); a TIFF through the module.
  if (kind == FileKind::png || kind == FileKind::exr) {
    AtomicOutput out(path);
    const std::string error =
        kind == FileKind::png
            ? write_png8(out.write_path(), width, height, channels, static_cast<const uint8_t*>(data),
                         options.png_compression)
            : write_exr_f32(out.write_path(), width, height, channels, static_cast<const float*>(data));
    if (!error.empty()) throw InputError(file, "", out.named(error));
    out.commit("", "the finished image");
    return;
  }
  const ImageBackend& backend = image_backend_for(file);
  ImageWriteRequest request;
  request.target = file;
  request.width = width;
  request.height = height;
  request.channels = channels;
  request.type = file_type;
  request.pixels = data;
  AtomicOutput out(path);
  request.temp = out.write_path();
  if (const std::string error = backend.write(request); !error.empty()) throw InputError(file, "", out.named(error));
  out.commit("", "the finished image");
}

namespace {

// Bytes a channel of `type` takes in memory (the backend reports u8, u16 or f32 for files).
int bytes_of(StoredType type) { return type == StoredType::u8 ? 1 : type == StoredType::u16 ? 2 : 4; }

// Opens an image for reading its header; the caller reads pixels or only the header.
std::unique_ptr<ImageReader> open_image(const std::filesystem::path& path) {
  const std::string file = path.string();
  // Maps named inside a mesh file (an MTL's map_Kd, a glTF's uri) reach here unchecked: a pipe
  // named so hung the set-up.
  if (const std::string reason = unreadable_file_reason(path); !reason.empty())
    throw InputError(file, "", reason == kFileNotFound ? "image file not found" : reason + ", not an image file");
  std::string error;
  const OpenImage own = own_reader(path);
  auto in = own ? own(file, error) : image_backend_for(file).open(file, error);
  if (!in) throw InputError(file, "", "cannot read the image: " + error);
  const ImageFileInfo& info = in->info();
  if (info.width <= 0 || info.height <= 0 || info.channels <= 0) throw InputError(file, "", "the image is empty");
  if (info.depth > 1) throw InputError(file, "", "volume images are not supported");
  // Two channels are read as grey and alpha (a PNG's Y, A): two colour channels (an EXR's R, G,
  // a two-channel normal map) were drawn as grey, the second channel taken for alpha.
  if (info.channels == 2 && info.alpha_channel != 1)
    throw InputError(file, "",
                     "its 2 channels (" + info.channel_names +
                         ") are not grey and alpha, which is how pelt reads two channels; store it as RGB");
  // Read as stored, such a file put its data window's pixels over the whole map without a word:
  // a crop showed stretched, overscan squeezed in.
  if (info.x != info.full_x || info.y != info.full_y || info.width != info.full_width ||
      info.height != info.full_height)
    throw InputError(file, "",
                     "its pixels (" + std::to_string(info.width) + " x " + std::to_string(info.height) + " at " +
                         std::to_string(info.x) + ", " + std::to_string(info.y) + ") are not its frame (" +
                         std::to_string(info.full_width) + " x " + std::to_string(info.full_height) + " at " +
                         std::to_string(info.full_x) + ", " + std::to_string(info.full_y) +
                         "): pelt reads whole frames; e.g. `oiiotool IN --croptofull -o OUT` makes one");
  return in;
}

uint32_t big_endian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint32_t big_endian16(const uint8_t* p) { return (uint32_t{p[0]} << 8) | uint32_t{p[1]}; }

}  // namespace

ImageHeader read_image_header(const std::filesystem::path& path) {
  const auto in = open_image(path);
  const ImageFileInfo& info = in->info();
  return ImageHeader{info.width, info.height, info.channels, bytes_of(info.type)};
}

EncodedKind encoded_kind(const uint8_t* bytes, size_t size) {
  static constexpr uint8_t kPng[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  static_assert(sizeof kPng <= kEncodedKindBytes);
  if (bytes && size >= sizeof kPng && std::equal(kPng, kPng + sizeof kPng, bytes)) return EncodedKind::png;
  if (bytes && size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return EncodedKind::jpeg;
  // OpenEXR's magic number, 20000630 stored little-endian.
  if (bytes && size >= 4 && bytes[0] == 0x76 && bytes[1] == 0x2F && bytes[2] == 0x31 && bytes[3] == 0x01)
    return EncodedKind::exr;
  return EncodedKind::other;
}

EncodedKind encoded_kind(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  uint8_t head[kEncodedKindBytes] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return encoded_kind(head, size_t(in.gcount()));
}

std::optional<EncodedImageSize> encoded_image_size(const uint8_t* bytes, size_t size) {
  const EncodedKind kind = encoded_kind(bytes, size);
  if (kind == EncodedKind::png && size >= 24) {
    // The first chunk must be IHDR: length, type, then width and height.
    if (std::memcmp(bytes + 12, "IHDR", 4) != 0) return std::nullopt;
    const EncodedImageSize s{big_endian32(bytes + 16), big_endian32(bytes + 20)};
    if (s.width == 0 || s.height == 0) return std::nullopt;
    return s;
  }
  if (kind == EncodedKind::jpeg && size >= 4) {
    // Walk the marker segments up to the first start-of-frame (SOF0..SOF15 except DHT C4,
    // JPG C8 and DAC CC), whose body is precision, height, width.
    size_t i = 2;
    while (i + 4 <= size) {
      if (bytes[i] != 0xFF) return std::nullopt;
      const uint8_t marker = bytes[i + 1];
      if (marker == 0xFF) {  // fill byte before a marker
        ++i;
        continue;
      }
      if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {  // no length field
        i += 2;
        continue;
      }
      if (marker == 0xD9 || marker == 0xDA) return std::nullopt;  // image data before any frame
      const size_t length = big_endian16(bytes + i + 2);
      if (length < 2) return std::nullopt;
      if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
        if (length < 7 || i + 9 > size) return std::nullopt;
        const EncodedImageSize s{big_endian16(bytes + i + 7), big_endian16(bytes + i + 5)};
        if (s.width == 0 || s.height == 0) return std::nullopt;  // height 0: set later by DNL
        return s;
      }
      i += 2 + length;
    }
  }
  return std::nullopt;
}

ImageRGBA read_image_rgba(const std::filesystem::path& path, ColorEncoding encoding, const Budget& budget, int used) {
  const std::string file = path.string();
  const auto in = open_image(path);
  const ImageFileInfo& spec = in->info();
  if (spec.width > budget.max_texture_side || spec.height > budget.max_texture_side)
    throw InputError(file, "", texture_side_refusal(spec.width, spec.height, budget.max_texture_side));
  const int channels = std::min(spec.channels, 4);
  const int bytes = bytes_of(spec.type);
  std::vector<uint8_t> buffer(static_cast<size_t>(spec.width) * spec.height * channels * bytes);
  if (const std::string error = in->read(channels, spec.type, buffer.data()); !error.empty())
    throw InputError(file, "", "reading the pixels failed: " + error);
  if (encoding == ColorEncoding::srgb_unless_linear)
    encoding = spec.declared_linear ? ColorEncoding::linear : ColorEncoding::srgb;
  ImageRGBA img = pixels_to_rgba(buffer.data(), spec.width, spec.height, channels, 8 * bytes, encoding);
  for (size_t i = 0; i < img.rgba.size(); ++i)
    if (!std::isfinite(img.rgba[i])) {
      if (int(i % 4) >= used) {
        img.rgba[i] = 0.0f;
        continue;
      }
      const size_t texel = i / 4;
      throw InputError(file, "",
                       "texel (" + std::to_string(texel % size_t(img.width)) + ", " +
                           std::to_string(texel / size_t(img.width)) + ") channel " + "rgba"[i % 4] + " is " +
                           (std::isnan(img.rgba[i]) ? "NaN" : "infinite"));
    }
  return img;
}

}  // namespace pelt::io
