// Plain decoded image, the hand-off from loaders to texture code.
#pragma once

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
