#include "tools/io/gif_writer.h"

#include <cstdio>
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

std::optional<std::string> gif_fps_refusal(double fps) {
  char shown[32];
  std::snprintf(shown, sizeof shown, "%g", fps);
  if (!(fps >= 100.0 / 65535.0))
    return std::string("a GIF frame lasts at most 655.35 s, so a GIF needs at least 0.0016 frames per second; got ") +
           shown;
  // OIIO writes int(100 / fps): 0 above 100 fps, which viewers play at their own pace.
  if (fps > 100.0)
    return std::string("a GIF frame lasts at least 1/100 s, so a GIF plays at most 100 frames per second; got ") +
           shown;
  return std::nullopt;
}

AnimatedGifWriter::AnimatedGifWriter(const std::filesystem::path& path, int width, int height, double fps)
    : impl_(std::make_unique<Impl>()) {
  const std::string file = path.string();
  if (width <= 0 || height <= 0 || width > 65535 || height > 65535)
    throw InputError(file, "", "GIF frames must be 1..65535 pixels on each side");
  if (const std::optional<std::string> refusal = gif_fps_refusal(fps)) throw InputError(file, "", *refusal);
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
