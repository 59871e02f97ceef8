// Animated GIF output through OpenImageIO, frame by frame, with the same all-or-nothing
// guarantee as write_image_atomic: frames stream into a temporary file in the target's
// folder, which is renamed over the target only by commit(); a writer destroyed before
// commit() (an error, an interrupted render) removes the temporary and leaves no file.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace pelt::io {

// Why a GIF cannot be shown at `fps` frames per second, or nullopt when it can: GIF stores a
// frame's delay in whole hundredths of a second in 16 bits (100 / fps, truncated), so fps must
// lie in [100 / 65535, 100]. The writer refuses such an fps, and `pelt render` before any frame.
std::optional<std::string> gif_fps_refusal(double fps);

class AnimatedGifWriter {
 public:
  // Opens the temporary for `width` x `height` frames shown `fps` frames per second. Throws
  // InputError(path, "", reason) for an fps a GIF cannot hold (gif_fps_refusal) or when the
  // file cannot be created.
  AnimatedGifWriter(const std::filesystem::path& path, int width, int height, double fps);
  ~AnimatedGifWriter();
  AnimatedGifWriter(const AnimatedGifWriter&) = delete;
  AnimatedGifWriter& operator=(const AnimatedGifWriter&) = delete;

  // Appends one frame of linear float RGBA with premultiplied colour (a render's), rows top
  // to bottom, encoded to sRGB bytes like PNG output (then quantised by the writer). GIF
  // frames are opaque: alpha is dropped, so a transparent part shows as over black.
  void add_frame(const float* rgba);
  // Finishes the file and moves it into place. At least one frame must have been added.
  void commit();
  int frames() const { return frames_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int frames_ = 0;
};

}  // namespace pelt::io
