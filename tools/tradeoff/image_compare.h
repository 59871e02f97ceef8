// Error of a rendered image against the reference, measured on what the user gets: the
// 8-bit sRGB PNG that `pelt render` writes, RGB only.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace pelt::tradeoff {

// An image as `pelt render` writes it to PNG: 8-bit, colour through the sRGB curve
// (clamped to [0, 1]), alpha linear, 4 bytes a pixel, rows top to bottom.
struct DisplayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// Encodes linear float RGBA with premultiplied colour (render::FrameImage::color) exactly as
// io::write_image_atomic does for .png, straight colour and all, so a row's error is the error
// of the file a user would look at.
// Throws std::invalid_argument when `rgba` does not hold width * height pixels.
DisplayImage to_display(int width, int height, std::span<const float> rgba);

// Channel values are bytes / 255, alpha is left out.
struct ImageError {
  double rmse = 0;  // over every pixel and RGB channel
  double psnr_db = std::numeric_limits<double>::infinity();  // 20 log10(1 / rmse); inf when identical
  double max_abs = 0;  // largest channel difference
  // Pixels with any RGB channel more than 1/255 off, over the pixel count. On 8-bit values
  // "more than 1/255" is a difference of at least 2 steps.
  double share_over_1_255 = 0;
};

// Compares with OpenImageIO's ImageBufAlgo::compare (io::image_backend()). Throws std::invalid_argument when the
// sizes differ (a caller's bug: every row is rendered at the reference's size).
ImageError compare(const DisplayImage& image, const DisplayImage& reference);

}  // namespace pelt::tradeoff
