#include "tools/io/pixels.h"

#include <cmath>
#include <cstring>

#include "tools/io/srgb.h"

namespace pelt::io {
namespace {

float srgb_to_linear(double s) {
  return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

}  // namespace

ImageRGBA pixels_to_rgba(const void* data, int width, int height, int channels, int bits,
                         ColorEncoding encoding) {
  ImageRGBA out;
  if (channels < 1 || channels > 4 || (bits != 8 && bits != 16 && bits != 32) || width <= 0 ||
      height <= 0)
    return out;
  out.width = width;
  out.height = height;
  const size_t count = static_cast<size_t>(width) * height;
  out.rgba.resize(count * 4);
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour = has_alpha ? channels - 1 : channels;
  const auto* bytes = static_cast<const uint8_t*>(data);
  const auto value = [&](size_t i, bool is_alpha) -> float {
    if (bits == 8) {
      const uint8_t b = bytes[i];
      return (!is_alpha && encoding == ColorEncoding::srgb) ? srgb8_to_linear(b)
                                                            : static_cast<float>(b / 255.0);
    }
    if (bits == 16) {
      uint16_t v;
      std::memcpy(&v, bytes + 2 * i, 2);
      const double s = v / 65535.0;
      return (!is_alpha && encoding == ColorEncoding::srgb) ? srgb_to_linear(s) : static_cast<float>(s);
    }
    float f;
    std::memcpy(&f, bytes + 4 * i, 4);
    return f;
  };
  for (size_t p = 0; p < count; ++p) {
    float* d = out.rgba.data() + 4 * p;
    const size_t base = p * channels;
    if (colour == 1) {
      d[0] = d[1] = d[2] = value(base, false);
    } else {
      for (int c = 0; c < 3; ++c) d[c] = value(base + c, false);
    }
    d[3] = has_alpha ? value(base + colour, true) : 1.0f;
  }
  return out;
}

}  // namespace pelt::io
