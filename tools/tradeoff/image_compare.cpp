#include "tools/tradeoff/image_compare.h"

#include <stdexcept>
#include <string>

#include "tools/io/image_backend.h"
#include "tools/io/srgb.h"

namespace pelt::tradeoff {
DisplayImage to_display(int width, int height, std::span<const float> rgba) {
  if (width <= 0 || height <= 0 || rgba.size() != size_t(width) * size_t(height) * 4)
    throw std::invalid_argument("to_display: " + std::to_string(rgba.size()) + " floats for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " RGBA image");
  DisplayImage d;
  d.width = width;
  d.height = height;
  d.rgba.resize(rgba.size());
  io::encode_srgb8_rows(rgba.data(), size_t(width) * 4, d.rgba.data(), size_t(width) * 4, width, height, 4,
                        io::Alpha::premultiplied);
  return d;
}

ImageError compare(const DisplayImage& image, const DisplayImage& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.rgba.size() != reference.rgba.size() ||
      image.rgba.size() != size_t(image.width) * size_t(image.height) * 4)
    throw std::invalid_argument("compare: image " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " against reference " +
                                std::to_string(reference.width) + "x" + std::to_string(reference.height));
  // Channels 0..2: alpha is not part of what the user sees on an opaque background.
  // OIIO counts a pixel over the threshold when any channel differs by more than it. Byte
  // differences are multiples of 1/255 up to float rounding, so 1.5/255 separates
  // "at most one step" from "two steps or more" without depending on that rounding.
  const float fail = 1.5f / 255.0f;
  io::RgbComparison r;
  const std::string error =
      io::image_backend().compare_rgb8(image.rgba.data(), reference.rgba.data(), image.width, image.height, fail, r);
  if (!error.empty()) throw std::runtime_error(error);
  ImageError e;
  e.rmse = r.rms_error;
  e.psnr_db = r.rms_error > 0 ? r.psnr : std::numeric_limits<double>::infinity();
  e.max_abs = r.max_error;
  e.share_over_1_255 = double(r.pixels_over_threshold) / (double(image.width) * double(image.height));
  return e;
}

}  // namespace pelt::tradeoff
