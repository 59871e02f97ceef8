#include "tools/io/gif_writer.h"

#include <string>
#include <system_error>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/srgb.h"

namespace pelt::io {

struct AnimatedGifWriter::Impl {
  std::filesystem::path path, tmp;
  int width = 0, height = 0;
  OIIO::ImageSpec spec;
  std::unique_ptr<OIIO::ImageOutput> out;
  std::vector<uint8_t> bytes;
  bool committed = false;
};

AnimatedGifWriter::AnimatedGifWriter(const std::filesystem::path& path, int width, int height, double fps)
    : impl_(std::make_unique<Impl>()) {
  const std::string file = path.string();
  if (width <= 0 || height <= 0 || width > 65535 || height > 65535)
    throw InputError(file, "", "GIF frames must be 1..65535 pixels on each side");
  if (!(fps > 0.0)) throw InputError(file, "", "frames per second must be positive");
  Impl& m = *impl_;
  m.path = path;
  m.tmp = temp_beside(path);
  m.width = width;
  m.height = height;
  m.out = OIIO::ImageOutput::create(file);
  if (!m.out) throw InputError(file, "", "no GIF writer in this OpenImageIO: " + OIIO::geterror());
  if (!m.out->supports("appendsubimage"))
    throw InputError(file, "", "this OpenImageIO cannot append GIF frames");
  m.spec = OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8);
  // OIIO's GIF writer turns this into the per-frame delay of 100 / fps centiseconds.
  m.spec.attribute("FramesPerSecond", static_cast<float>(fps));
  m.spec.attribute("oiio:ColorSpace", "sRGB");
  m.bytes.resize(static_cast<size_t>(width) * height * 3);
}

AnimatedGifWriter::~AnimatedGifWriter() {
  if (!impl_ || impl_->committed) return;
  if (frames_ > 0) impl_->out->close();
  std::error_code ec;
  std::filesystem::remove(impl_->tmp, ec);
}

void AnimatedGifWriter::add_frame(const float* rgba) {
  Impl& m = *impl_;
  const std::string file = m.path.string();
  if (m.committed) throw InputError(file, "", "frame added after the GIF was finished");
  for (size_t p = 0, n = static_cast<size_t>(m.width) * m.height; p < n; ++p)
    for (int c = 0; c < 3; ++c) m.bytes[p * 3 + c] = linear_to_srgb8_fast(rgba[p * 4 + c]);
  const auto mode = frames_ == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendSubimage;
  if (!m.out->open(m.tmp.string(), m.spec, mode))
    throw InputError(file, "", "cannot write GIF frame " + std::to_string(frames_) + ": " + m.out->geterror());
  if (!m.out->write_image(OIIO::TypeDesc::UINT8, m.bytes.data()))
    throw InputError(file, "", "cannot write GIF frame " + std::to_string(frames_) + ": " + m.out->geterror());
  ++frames_;
}

void AnimatedGifWriter::commit() {
  Impl& m = *impl_;
  const std::string file = m.path.string();
  if (frames_ == 0) throw InputError(file, "", "a GIF needs at least one frame");
  if (!m.out->close()) throw InputError(file, "", "finishing the GIF failed: " + m.out->geterror());
  std::error_code ec;
  std::filesystem::rename(m.tmp, m.path, ec);
  if (ec) throw InputError(file, "", "cannot move the finished GIF into place: " + ec.message());
  m.committed = true;
}

}  // namespace pelt::io
