#include "tools/io/gif_writer.h"

#include <string>
#include <vector>

#include "tools/io/image_backend.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/io/srgb.h"

namespace pelt::io {

struct AnimatedGifWriter::Impl {
  std::filesystem::path path;
  std::unique_ptr<AtomicOutput> file;  // removed unless committed; declared before `out`, which closes it first
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
  // OIIO writes int(100 / fps): 0 above 100 fps, which viewers play at their own pace.
  if (!(fps >= 100.0 / 65535.0 && fps <= 100.0))
    throw InputError(file, "", "a GIF's frame delay is whole hundredths of a second in 16 bits, so its frames per "
                               "second must lie in [0.0016, 100]; got " + std::to_string(fps));
  Impl& m = *impl_;
  m.path = path;
  m.file = std::make_unique<AtomicOutput>(path);
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
  if (const std::string error = m.out->append(m.file->write_path(), m.bytes.data()); !error.empty())
    throw InputError(file, "", "cannot write GIF frame " + std::to_string(frames_) + ": " + m.file->named(error));
  ++frames_;
}

void AnimatedGifWriter::commit() {
  Impl& m = *impl_;
  const std::string file = m.path.string();
  if (frames_ == 0) throw InputError(file, "", "a GIF needs at least one frame");
  if (const std::string error = m.out->close(); !error.empty())
    throw InputError(file, "", "finishing the GIF failed: " + error);
  m.file->commit("", "the finished GIF");
  m.committed = true;
}

}  // namespace pelt::io
