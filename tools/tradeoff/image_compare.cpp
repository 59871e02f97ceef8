#include "tools/tradeoff/image_compare.h"

#include <stdexcept>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "tools/io/srgb.h"

namespace pelt::tradeoff {
namespace {

// A view of the bytes as an OIIO image; OIIO reads UINT8 channels as byte / 255.
OIIO::ImageBuf wrap(const DisplayImage& img) {
  const OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::UINT8);
  return OIIO::ImageBuf(spec, const_cast<uint8_t*>(img.rgba.data()));
}

}  // namespace

DisplayImage to_display(int width, int height, std::span<const float> rgba) {
  if (width <= 0 || height <= 0 || rgba.size() != size_t(width) * size_t(height) * 4)
    throw std::invalid_argument("to_display: " + std::to_string(rgba.size()) + " floats for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " RGBA image");
  DisplayImage d;
  d.width = width;
  d.height = height;
  d.rgba.resize(rgba.size());
  io::encode_srgb8_rows(rgba.data(), size_t(width) * 4, d.rgba.data(), size_t(width) * 4, width, height, 4);
  return d;
}

ImageError compare(const DisplayImage& image, const DisplayImage& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.rgba.size() != reference.rgba.size() ||
      image.rgba.size() != size_t(image.width) * size_t(image.height) * 4)
    throw std::invalid_argument("compare: image " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " against reference " +
                                std::to_string(reference.width) + "x" + std::to_string(reference.height));
  const OIIO::ImageBuf a = wrap(image);
  const OIIO::ImageBuf b = wrap(reference);
  // Channels 0..2: alpha is not part of what the user sees on an opaque background.
  const OIIO::ROI rgb(0, image.width, 0, image.height, 0, 1, 0, 3);
  // OIIO counts a pixel in nfail when any channel differs by more than failthresh. Byte
  // differences are multiples of 1/255 up to float rounding, so 1.5/255 separates
  // "at most one step" from "two steps or more" without depending on that rounding.
  const float fail = 1.5f / 255.0f;
  const OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(a, b, fail, fail, rgb, 1);
  // r.error only says that some pixel failed the threshold; an OIIO malfunction is an
  // error on the buffers.
  if (a.has_error() || b.has_error())
    throw std::runtime_error("OpenImageIO compare failed: " + a.geterror() + b.geterror());
  ImageError e;
  e.rmse = r.rms_error;
  e.psnr_db = r.rms_error > 0 ? r.PSNR : std::numeric_limits<double>::infinity();
  e.max_abs = r.maxerror;
  e.share_over_1_255 = double(r.nfail) / (double(image.width) * double(image.height));
  return e;
}

}  // namespace pelt::tradeoff
