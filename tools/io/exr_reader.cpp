#include "tools/io/exr_reader.h"

#include <ImfChannelList.h>
#include <ImfEnvmapAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfPartType.h>
#include <ImfThreading.h>
#include <ImfTileDescription.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "tools/io/exr_writer.h"

namespace pelt::io {
namespace {

bool same_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
           return lower(x) == lower(y);
         });
}

// A channel as OpenImageIO 2.4's EXR reader sorted them.
struct ExrChannel {
  std::string name;
  std::string layer, suffix;  // `name` up to and including its last dot, and after it
  int rank = 10000;                // the suffix's place in the reader's list of known names
  Imf::PixelType type = Imf::HALF;
  int x_sampling = 1, y_sampling = 1;
};

// OpenImageIO's rank of a suffix: colours, then luminance, complex parts, alpha, depth; the rest after
// (10000), by name. In a layer that holds X and Y or Z (a position or a normal), X, Y, Z come right
// after the colours instead.
int rank_of(std::string_view suffix, bool xyz) {
  static constexpr const char* kUsual[] = {"R",  "Red", "G",  "Green", "B",  "Blue", "Y",     "real", "imag", "A",
                                           "Alpha", "AR", "RA", "AG",   "GA", "AB",  "BA", "Z",    "Depth", "Zback"};
  static constexpr const char* kXyz[] = {"R",  "Red", "G",  "Green", "B",  "Blue", "X",  "Y",  "Z",     "real",
                                         "imag", "A", "Alpha", "AR",  "RA", "AG",   "GA", "AB", "BA", "Depth", "Zback"};
  const auto find = [&](const auto& names) {
    for (size_t i = 0; i < std::size(names); ++i)
      if (same_ignoring_case(suffix, names[i])) return int(i);
    return 10000;
  };
  return xyz ? find(kXyz) : find(kUsual);
}

// The header's channels (which OpenEXR keeps sorted by name) in OpenImageIO's order.
std::vector<ExrChannel> channels_in_order(const Imf::ChannelList& list) {
  std::vector<ExrChannel> out;
  for (auto c = list.begin(); c != list.end(); ++c)
    out.push_back({c.name(), {}, {}, 10000, c.channel().type, c.channel().xSampling, c.channel().ySampling});
  for (ExrChannel& c : out) {
    const size_t dot = c.name.find_last_of('.');
    c.layer = dot == std::string::npos ? std::string() : c.name.substr(0, dot + 1);
    c.suffix = dot == std::string::npos ? c.name : c.name.substr(dot + 1);
  }
  for (ExrChannel& c : out) {
    const auto in_layer = [&](std::string_view suffix) {
      return std::any_of(out.begin(), out.end(),
                         [&](const ExrChannel& o) { return o.layer == c.layer && same_ignoring_case(o.suffix, suffix); });
    };
    c.rank = rank_of(c.suffix, in_layer("X") && (in_layer("Y") || in_layer("Z")));
  }
  // Names are unique, so this order is total and any sort gives it.
  std::sort(out.begin(), out.end(), [](const ExrChannel& a, const ExrChannel& b) {
    if (a.layer != b.layer) return a.layer < b.layer;
    if (a.rank != b.rank) return a.rank < b.rank;
    return a.suffix < b.suffix;
  });
  return out;
}

std::string name_list(const std::vector<ExrChannel>& channels, size_t count) {
  std::string out;
  for (size_t c = 0; c < count && c < channels.size(); ++c) out += (c ? ", " : "") + channels[c].name;
  return out;
}

// Why the channels pelt would draw as colour, the first three of three or more, are not colour;
// "" when they may be. One channel is a value whatever its name, and image_io checks two.
std::string colour_channels_problem(const std::vector<ExrChannel>& channels, int alpha) {
  if (channels.size() < 3) return {};
  const std::string used = name_list(channels, 3), all = name_list(channels, channels.size());
  for (size_t c = 0; c < 3; ++c)
    if (same_ignoring_case(channels[c].suffix, "RY") || same_ignoring_case(channels[c].suffix, "BY"))
      return "its channels (" + all + ") are luminance and chroma, which pelt would draw as red, green and blue (" +
             used + "); store it as RGB";
  if (alpha >= 0 && alpha < 3)
    return "its channels (" + all + ") put its alpha " + channels[size_t(alpha)].name +
           " among the first three, which pelt draws as red, green and blue (" + used + "); store it as RGB or RGBA";
  if (channels[1].layer != channels[0].layer || channels[2].layer != channels[0].layer)
    return "the first three of its channels (" + all + "), which pelt draws as red, green and blue, come from " +
           "different layers (" + used + "); store the layer to draw as RGB or RGBA";
  return {};
}

// OpenEXR sizes an attribute's value by the size its header gives and reads it byte by byte: a
// string attribute whose size a flipped bit made 1.4 GB held that much for seconds, and a 916-byte
// file whose `name` said 2 GB kept a render 23 s at 2.2 GB (OpenImageIO's reader did the same). Each header's attributes
// are walked here first, and a size past the end of the file is refused before OpenEXR sees it.
// "" when none is; other damage is left to OpenEXR, which names it.
std::string attribute_size_problem(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  const uint64_t length = std::filesystem::file_size(file, ec);
  if (!in || ec) return {};
  const auto text = [&](std::string& out) {  // a name or type: at most 255 characters and its NUL
    out.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (out.size() == 255) return false;
      out += c;
    }
    return false;
  };
  char head[8];
  if (!in.read(head, sizeof head)) return {};
  const bool multipart = (uint8_t(head[5]) & 0x10) != 0;  // the version field's bit 12
  for (bool first = true; first || multipart; first = false) {
    std::string name, type;
    if (!text(name)) return {};
    if (name.empty()) return {};  // the end of the headers (an empty one, or a single part's end)
    while (!name.empty()) {
      uint8_t size_bytes[4];
      if (!text(type) || !in.read(reinterpret_cast<char*>(size_bytes), 4)) return {};
      const int32_t size = int32_t(uint32_t(size_bytes[0]) | uint32_t(size_bytes[1]) << 8 |
                                   uint32_t(size_bytes[2]) << 16 | uint32_t(size_bytes[3]) << 24);
      const std::streamoff at = in.tellg();
      if (at < 0) return {};
      if (size < 0 || uint64_t(size) > length - uint64_t(at))
        return "its header is cut short or corrupt: attribute `" + name + "` (" + type + ") says it holds " +
               std::to_string(size) + " bytes, and " + std::to_string(length - uint64_t(at)) + " follow it in the file";
      in.seekg(size, std::ios::cur);
      if (!text(name)) return {};
    }
  }
  return {};
}

class ExrReader final : public ImageReader {
 public:
  bool open(const std::string& file, std::string& error) {
    try {
      if (std::string problem = attribute_size_problem(file); !problem.empty()) {
        error = std::move(problem);
        return false;
      }
      start_exr_threads();
      // The headers and chunk tables only (OpenEXR checks that the file holds a table of more than
      // 2^20 chunks before it allocates it). The part's line buffers, as wide as the image, are made
      // in read(), after image_io's budget check.
      file_ = std::make_unique<Imf::MultiPartInputFile>(file.c_str(), Imf::globalThreadCount());
      return describe(file_->header(0), error);
    } catch (const std::exception& e) {
      error = e.what();
    } catch (...) {
      error = "OpenEXR failed without a reason";
    }
    return false;
  }

  const ImageFileInfo& info() const override { return info_; }

  std::string read(int channels, StoredType type, void* out) override {
    if (type != StoredType::f32 || channels < 1 || channels > info_.channels)
      return "pelt's EXR reader gives floats of the file's first channels only";
    const size_t count = size_t(channels), pixel = sizeof(float) * count;
    char* const base = static_cast<char*>(out);
    try {
      Imf::InputPart part(*file_, 0);  // level 0 of a tiled part
      const Imath::Box2i& window = part.header().dataWindow();
      Imf::FrameBuffer frame;
      for (size_t c = 0; c < count; ++c) {
        // UINT as stored, scaled below; HALF and FLOAT as floats, converted by OpenEXR.
        const Imf::PixelType as = channels_[c].type == Imf::UINT ? Imf::UINT : Imf::FLOAT;
        frame.insert(channels_[c].name, Imf::Slice::Make(as, base + c * sizeof(float), window, pixel,
                                                         pixel * size_t(info_.width)));
      }
      part.setFrameBuffer(frame);
      part.readPixels(window.min.y, window.max.y);
    } catch (const std::exception& e) {
      return e.what();
    } catch (...) {
      return "OpenEXR failed without a reason";
    }
    // OpenImageIO's UINT to float: the value rounded to a float, times 1 / 4294967295 as a float
    // (2^-32), so 0xFFFFFFFF reads 1.
    const size_t texels = size_t(info_.width) * size_t(info_.height);
    for (size_t c = 0; c < count; ++c) {
      if (channels_[c].type != Imf::UINT) continue;
      for (size_t p = 0; p < texels; ++p) {
        char* at = base + p * pixel + c * sizeof(float);
        uint32_t stored;
        std::memcpy(&stored, at, sizeof stored);
        const float value = float(stored) * 0x1p-32f;
        std::memcpy(at, &value, sizeof value);
      }
    }
    return {};
  }

 private:
  bool describe(const Imf::Header& header, std::string& error) {
    // OpenImageIO's reader opened a deep file but failed to read it ("called
    // OpenEXRInput::read_native_scanlines without an open file"), after its header had been taken.
    if (header.hasType() && Imf::isDeepData(header.type())) {
      error = "a deep EXR (a list of samples in each pixel, " + header.type() +
              "), which pelt does not read; flatten it to a plain image first";
      return false;
    }
    channels_ = channels_in_order(header.channels());
    if (channels_.empty()) {
      error = "No channels found";
      return false;
    }
    for (const ExrChannel& c : channels_)
      if (c.x_sampling != 1 || c.y_sampling != 1) {
        error = "subsampled channels are not supported (channel \"" + c.name + "\" has sampling " +
                std::to_string(c.x_sampling) + ", " + std::to_string(c.y_sampling) + ")";
        return false;
      }
    const Imath::Box2i& data = header.dataWindow();
    const Imath::Box2i& display = header.displayWindow();
    info_.x = data.min.x, info_.y = data.min.y;
    info_.width = data.max.x - data.min.x + 1, info_.height = data.max.y - data.min.y + 1;
    info_.full_x = display.min.x, info_.full_y = display.min.y;
    info_.full_width = display.max.x - display.min.x + 1, info_.full_height = display.max.y - display.min.y + 1;
    info_.channels = int(channels_.size());
    info_.channel_names = name_list(channels_, channels_.size());
    for (size_t c = 0; c < channels_.size() && info_.alpha_channel < 0; ++c)
      if (same_ignoring_case(channels_[c].suffix, "A") || same_ignoring_case(channels_[c].suffix, "Alpha"))
        info_.alpha_channel = int(c);
    info_.type = StoredType::f32;
    // OpenImageIO gave the frame of a MIP- or RIP-mapped cube map as one face, square, so a face
    // stack taller than wide met image_io's data-window refusal, whose advice does not fit it.
    const bool levels = header.hasTileDescription() && header.tileDescription().mode != Imf::ONE_LEVEL &&
                        header.hasType() && header.type() == Imf::TILEDIMAGE;
    const auto* envmap = header.findTypedAttribute<Imf::EnvmapAttribute>("envmap");
    if (levels && envmap && envmap->value() == Imf::ENVMAP_CUBE && info_.height != info_.width) {
      error = "a cube-face environment map with MIP levels, which pelt does not read as a plain image";
      return false;
    }
    if (const std::string problem = colour_channels_problem(channels_, info_.alpha_channel); !problem.empty()) {
      error = problem;
      return false;
    }
    return true;
  }

  std::unique_ptr<Imf::MultiPartInputFile> file_;
  std::vector<ExrChannel> channels_;
  ImageFileInfo info_;
};

}  // namespace

std::unique_ptr<ImageReader> open_exr(const std::string& file, std::string& error) {
  return open_reader<ExrReader>(file, error);
}

}  // namespace pelt::io
