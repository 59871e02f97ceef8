#include "tools/io/dissolve_map.h"

#include <algorithm>
#include <cmath>

#include "tools/io/image_io.h"

namespace pelt::io {
namespace {

// Channel `c` of texel (x, y) of `img` as a dissolve.
float dissolve_at(const ImageRGBA& img, int x, int y, char c) {
  const float* p = img.pixel(x, y);
  switch (c) {
    case 'r': return p[0];
    case 'g': return p[1];
    case 'b': return p[2];
    case 'm': return p[3];
    default: return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
  }
}

// `img`'s channel c, bilinear at (u, v) in [0, 1] (texel centres at (i + 0.5) / size), clamped.
float dissolve_bilinear(const ImageRGBA& img, float u, float v, char c) {
  const float x = u * float(img.width) - 0.5f, y = v * float(img.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const auto at = [&](float xi, float yi) {
    return dissolve_at(img, std::clamp(int(xi), 0, img.width - 1), std::clamp(int(yi), 0, img.height - 1), c);
  };
  const float top = at(fx, fy) * (1.0f - tx) + at(fx + 1.0f, fy) * tx;
  const float bottom = at(fx, fy + 1.0f) * (1.0f - tx) + at(fx + 1.0f, fy + 1.0f) * tx;
  return top * (1.0f - ty) + bottom * ty;
}

}  // namespace

ImageRGBA dissolved_color_map(const std::filesystem::path* color, const std::filesystem::path& dissolve, char channel,
                              const Budget& budget) {
  if (channel == 0) {
    const int channels = read_image_header(dissolve).channels;
    channel = channels == 2 || channels >= 4 ? 'm' : 'l';
  }
  const ImageRGBA d = read_image_rgba(dissolve, ColorEncoding::linear, budget);
  ImageRGBA out;
  if (color) {
    out = read_image_rgba(*color, ColorEncoding::srgb_unless_linear, budget, 3);
  } else {
    out.width = d.width;
    out.height = d.height;
    out.rgba.assign(size_t(d.width) * size_t(d.height) * 4, 1.0f);
  }
  const bool same_size = out.width == d.width && out.height == d.height;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const float a = same_size ? dissolve_at(d, x, y, channel)
                                : dissolve_bilinear(d, (float(x) + 0.5f) / float(out.width),
                                                    (float(y) + 0.5f) / float(out.height), channel);
      out.rgba[(size_t(y) * size_t(out.width) + size_t(x)) * 4 + 3] = a;
    }
  return out;
}

}  // namespace pelt::io
