// The image backend (image_backend.h) on OpenImageIO, built as the module libpelt_oiio.so.
// Nothing here throws pelt's errors: every failure comes back as OpenImageIO's text.
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "tools/io/image_backend.h"

namespace pelt::io {
namespace {

OIIO::TypeDesc oiio_type(StoredType t) {
  switch (t) {
    case StoredType::u8: return OIIO::TypeDesc::UINT8;
    case StoredType::u16: return OIIO::TypeDesc::UINT16;
    case StoredType::u32: return OIIO::TypeDesc::UINT32;
    case StoredType::f32: break;
  }
  return OIIO::TypeDesc::FLOAT;
}

class OiioReader final : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {
    const OIIO::ImageSpec& spec = in_->spec();
    info_.width = spec.width;
    info_.height = spec.height;
    info_.channels = spec.nchannels;
    info_.depth = spec.depth;
    info_.x = spec.x;
    info_.y = spec.y;
    info_.full_x = spec.full_x;
    info_.full_y = spec.full_y;
    info_.full_width = spec.full_width;
    info_.full_height = spec.full_height;
    for (const std::string& name : spec.channelnames) info_.channel_names += (info_.channel_names.empty() ? "" : ", ") + name;
    info_.alpha_channel = spec.alpha_channel;
    info_.declared_linear = std::string(in_->format_name()) == "png" &&
                            spec.get_string_attribute("oiio:ColorSpace") == "linear";
    info_.type = spec.format == OIIO::TypeDesc::UINT8    ? StoredType::u8
                 : spec.format == OIIO::TypeDesc::UINT16 ? StoredType::u16
                                                         : StoredType::f32;
  }
  ~OiioReader() override { in_->close(); }
  const ImageFileInfo& info() const override { return info_; }
  std::string read(int channels, StoredType type, void* out) override {
    // A truncated or corrupt JPEG or TIFF reads "successfully", its missing part grey or black,
    // with the decoder's complaint left as an error: taken as the read's failure. (Every valid
    // file the image hunt of 2026-11-27 made, PNG chunks and palettes included, leaves none.)
    const bool ok = in_->read_image(0, 0, 0, channels, oiio_type(type), out);
    if (ok && !in_->has_error()) return {};
    const std::string e = in_->geterror();
    return e.empty() ? "OpenImageIO gave no reason" : e;
  }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageFileInfo info_;
};

class OiioGif final : public GifFrames {
 public:
  OiioGif(std::unique_ptr<OIIO::ImageOutput> out, OIIO::ImageSpec spec) : out_(std::move(out)), spec_(spec) {}
  ~OiioGif() override {
    if (open_) out_->close();
  }
  std::string append(const std::string& temp, const uint8_t* rgb) override {
    const auto mode = open_ ? OIIO::ImageOutput::AppendSubimage : OIIO::ImageOutput::Create;
    if (!out_->open(temp, spec_, mode)) return out_->geterror();
    open_ = true;
    if (!out_->write_image(OIIO::TypeDesc::UINT8, rgb)) return out_->geterror();
    return {};
  }
  std::string close() override {
    open_ = false;
    return out_->close() ? std::string() : out_->geterror();
  }

 private:
  std::unique_ptr<OIIO::ImageOutput> out_;
  OIIO::ImageSpec spec_;
  bool open_ = false;
};

class OiioBackend final : public ImageBackend {
 public:
  std::string write(const ImageWriteRequest& r) const override {
    // create() picks the writer from the target's extension; open() then writes to the
    // temporary name, whose own extension means nothing to OIIO.
    auto out = OIIO::ImageOutput::create(r.target);
    if (!out) return "no image writer for this extension: " + OIIO::geterror();
    const OIIO::TypeDesc type = oiio_type(r.type);
    OIIO::ImageSpec spec(r.width, r.height, r.channels, type);
    if (r.exr_grey_names) {
      if (r.channels == 1) spec.channelnames = {"Y"};
      else if (r.channels == 2) spec.channelnames = {"Y", "A"};
    }
    if (r.channels == 2 || r.channels == 4) {
      spec.alpha_channel = r.channels - 1;
      // 8-bit files get straight colour (write_image_atomic divided it), stored as given:
      // without this OIIO's PNG writer would divide the sRGB bytes by alpha again, and TIFF
      // would be marked associated. Float files (EXR) are premultiplied, the format's own
      // convention, which is OIIO's default.
      if (type == OIIO::TypeDesc::UINT8) spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    if (type == OIIO::TypeDesc::UINT8) spec.attribute("oiio:ColorSpace", "sRGB");
    else if (type == OIIO::TypeDesc::FLOAT) spec.attribute("oiio:ColorSpace", "Linear");
    // OIIO's EXR and TIFF writers stamp the wall-clock time (DateTime) into the header unless
    // the spec names one; an empty one writes none. A frame's bytes then depend on its pixels
    // alone, so renders compare with cmp across runs and thread counts.
    spec.attribute("DateTime", "");
    if (!out->open(r.temp, spec)) return "cannot create the image file: " + out->geterror();
    const bool wrote = out->write_image(type, r.pixels);
    const std::string write_error = wrote ? std::string() : out->geterror();
    const bool closed = out->close();
    if (!wrote) return "writing the image failed: " + write_error;
    if (!closed) return "finishing the image file failed: " + out->geterror();
    return {};
  }

  std::unique_ptr<ImageReader> open(const std::string& file, std::string& error) const override {
    // Keep stored values: by default OIIO multiplies PNG colour by alpha on read.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(file, &config);
    if (!in) {
      error = OIIO::geterror();
      return nullptr;
    }
    return std::make_unique<OiioReader>(std::move(in));
  }

  std::unique_ptr<GifFrames> gif(const std::string& target, int width, int height, double fps,
                                 std::string& error) const override {
    auto out = OIIO::ImageOutput::create(target);
    if (!out) {
      error = "no GIF writer in this OpenImageIO: " + OIIO::geterror();
      return nullptr;
    }
    if (!out->supports("appendsubimage")) {
      error = "this OpenImageIO cannot append GIF frames";
      return nullptr;
    }
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    // OIIO's GIF writer turns this into the per-frame delay of 100 / fps centiseconds.
    spec.attribute("FramesPerSecond", static_cast<float>(fps));
    spec.attribute("oiio:ColorSpace", "sRGB");
    return std::make_unique<OiioGif>(std::move(out), spec);
  }

  std::string compare_rgb8(const uint8_t* a, const uint8_t* b, int width, int height, float threshold,
                           RgbComparison& out) const override {
    // Views of the bytes; OIIO reads UINT8 channels as byte / 255.
    const OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::UINT8);
    const OIIO::ImageBuf ia(spec, const_cast<uint8_t*>(a));
    const OIIO::ImageBuf ib(spec, const_cast<uint8_t*>(b));
    const OIIO::ROI rgb(0, width, 0, height, 0, 1, 0, 3);
    const OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(ia, ib, threshold, threshold, rgb, 1);
    // r.error only says that some pixel failed the threshold; an OIIO malfunction is an
    // error on the buffers.
    if (ia.has_error() || ib.has_error()) return "OpenImageIO compare failed: " + ia.geterror() + ib.geterror();
    out.rms_error = r.rms_error;
    out.psnr = r.PSNR;
    out.max_error = r.maxerror;
    out.pixels_over_threshold = r.nfail;
    return {};
  }
};

}  // namespace
}  // namespace pelt::io

extern "C" __attribute__((visibility("default"))) pelt::io::ImageBackend* pelt_image_backend(int abi) {
  static pelt::io::OiioBackend backend;
  return abi == pelt::io::kImageBackendAbi ? &backend : nullptr;
}
