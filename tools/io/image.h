// Plain decoded image, the hand-off from loaders to texture code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace pelt::io {

// Linear float RGBA, 4 floats a pixel, rows top to bottom (the first row is the top of
// the image as stored in the file), no padding.
struct ImageRGBA {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;

  bool empty() const { return rgba.empty(); }
  const float* pixel(int x, int y) const {
    return rgba.data() + (static_cast<size_t>(y) * width + x) * 4;
  }
};

// A value of `img` read bilinearly, in double, at (u, v): texel centres at half-integers of
// u * width and v * height, v = 0 the top row, as the sampler reads a map; past the edges the
// texels repeat, or (not `repeat`) the edge ones are read. `value(pixel)` is a texel's value (one
// of its four floats, or a mix of them). A non-finite coordinate reads as 0; beyond 2^52 texels a
// coordinate has no fraction left, and the wrap stays exact. For data read once (a length map at
// the mesh's vertices, a dissolve map resampled), where the raster's 8-bit textures would lose it.
template <class Value>
double bilinear_at(const ImageRGBA& img, double u, double v, bool repeat, Value value) {
  const long long W = img.width, H = img.height;
  const auto texel = [&](long long x, long long y) {
    x = repeat ? ((x % W) + W) % W : std::clamp(x, 0LL, W - 1);
    y = repeat ? ((y % H) + H) % H : std::clamp(y, 0LL, H - 1);
    return double(value(img.pixel(int(x), int(y))));
  };
  const double x = std::isfinite(u) ? u * double(W) - 0.5 : 0.0;
  const double y = std::isfinite(v) ? v * double(H) - 0.5 : 0.0;
  const double fx = std::floor(x), fy = std::floor(y);
  // The first texel's index, kept in range of long long (the clamp reads its edge texel anyway).
  const auto first = [&](double f, long long size) {
    return repeat ? (long long)std::fmod(f, double(size)) : (long long)std::clamp(f, -1.0, double(size));
  };
  const long long x0 = first(fx, W), y0 = first(fy, H);
  const double tx = x - fx, ty = y - fy;
  const double top = texel(x0, y0) * (1.0 - tx) + texel(x0 + 1, y0) * tx;
  const double bottom = texel(x0, y0 + 1) * (1.0 - tx) + texel(x0 + 1, y0 + 1) * tx;
  return top * (1.0 - ty) + bottom * ty;
}

// How an RGBA buffer's colour relates to its alpha. pelt's renders are premultiplied
// (associated: colour already multiplied by alpha), which is what src-over blending and the
// average of samples need; 8-bit files (PNG, TIFF) store straight colour, EXR premultiplied
// (OpenEXR's convention), and io::write_image_atomic converts between them.
enum class Alpha { straight, premultiplied };

// How 8/16-bit integer channels are turned into linear values: colour maps are sRGB
// encoded, data maps (normal maps, masks) are not. srgb_unless_linear: sRGB, but linear where
// the file says its values are (a PNG's gAMA 1.0 without an sRGB chunk), for colour maps whose
// namer does not rule that out (glTF tells loaders to ignore a PNG's gamma).
enum class ColorEncoding { srgb, linear, srgb_unless_linear };

}  // namespace pelt::io
