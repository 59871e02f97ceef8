#include "tools/io/gif_writer.h"

#include <string>
#include <system_error>
#include <vector>

#include "tools/io/image_backend.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/io/srgb.h"

namespace pelt::io {

struct AnimatedGifWriter::Impl {
  std::filesystem::path path;
  std::unique_ptr<TempFile> tmp;  // removed unless committed; declared before `out`, which closes it first
  int width = 0, height = 0;
  std::unique_ptr<GifFrames> out;
  std::vector<uint8_t> rgba, bytes;  // a frame's RGBA and RGB sRGB bytes
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
  // A device or a pipe is written in place (no temporary to rename over it).
  if (!writes_through(path)) m.tmp = std::make_unique<TempFile>(temp_beside(path));
  m.width = width;
  m.height = height;
  std::string error;
  m.out = image_backend_for(file).gif(file, width, height, fps, error);
  if (!m.out) throw InputError(file, "", error);
  m.rgba.resize(static_cast<size_t>(width) * height * 4);
  m.bytes.resize(static_cast<size_t>(width) * height * 3);
}

AnimatedGifWriter::~AnimatedGifWriter() = default;

void AnimatedGifWriter::add_frame(const float* rgba) {
  Impl& m = *impl_;
  const std::string file = m.path.string();
  if (m.committed) throw InputError(file, "", "frame added after the GIF was finished");
  // The SIMD resolve over all four channels (alpha's bytes are dropped), then RGB.
  encode_srgb8_span(rgba, m.rgba.data(), m.rgba.size());
  for (size_t p = 0, n = static_cast<size_t>(m.width) * m.height; p < n; ++p)
    for (int c = 0; c < 3; ++c) m.bytes[p * 3 + c] = m.rgba[p * 4 + c];
  const std::string target = m.tmp ? m.tmp->write_path() : file;
  if (const std::string error = m.out->append(target, m.bytes.data()); !error.empty())
    throw InputError(file, "", "cannot write GIF frame " + std::to_string(frames_) + ": " +
                                   (m.tmp ? m.tmp->named(error) : error));
  ++frames_;
}

void AnimatedGifWriter::commit() {
  Impl& m = *impl_;
  const std::string file = m.path.string();
  if (frames_ == 0) throw InputError(file, "", "a GIF needs at least one frame");
  if (const std::string error = m.out->close(); !error.empty())
    throw InputError(file, "", "finishing the GIF failed: " + error);
  if (m.tmp) {
    std::error_code ec;
    std::filesystem::rename(m.tmp->path(), m.path, ec);
    if (ec) throw InputError(file, "", "cannot move the finished GIF into place: " + ec.message());
    m.tmp->release();
  }
  m.committed = true;
}

}  // namespace pelt::io
