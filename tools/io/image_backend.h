// The OpenImageIO side of pelt's image files, in a module of its own (libpelt_oiio.so,
// beside the pelt executable) that is loaded on first use.
//
// Why a module: OpenImageIO pulls in some 260 shared libraries (OpenCV, GDAL, DCMTK,
// FFmpeg, ...), and linking it into pelt made every run pay for loading them, 0.3-0.8 s
// here, whether or not it touched an image: `pelt --version`, `pelt bench`, a scene error,
// and each of the test suite's processes. The module keeps that cost to the commands that
// read images other than PNG, JPEG and EXR or write them as anything but PNG and EXR (libpng writes
// and reads PNG itself, png_writer.h, png_reader.h; libjpeg reads JPEG, jpeg_reader.h; OpenEXR's
// library writes and reads EXR, exr_writer.h, exr_reader.h), and `pelt render` loads it while it
// renders (preload below).
//
// The split: the module only drives OpenImageIO and reports its errors as text; the checks,
// the sRGB encoding, the temporaries and the wording of errors (InputError) stay in pelt_io.
// The module and pelt are built together from one tree by one compiler, so the interface
// is C++ (virtual calls, std::string); kImageBackendAbi guards against a stale module.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace pelt::io {

// A channel type as stored in a file (and as pixels are handed over).
enum class StoredType : uint8_t { u8, u16, u32, f32 };

struct ImageWriteRequest {
  std::string target;  // the file the user asked for: its extension picks the writer
  std::string temp;    // the file actually written (renamed over target by the caller)
  int width = 0, height = 0, channels = 0;
  StoredType type = StoredType::u8;  // of both the pixels and the file's channels
  // Name 1 and 2 channels "Y" and "Y", "A" in an EXR. pelt_io writes EXR files with OpenEXR's
  // library (exr_writer.h); the module's EXR writer is kept for the tests that compare the two.
  bool exr_grey_names = false;
  const void* pixels = nullptr;      // interleaved, rows top to bottom
};

struct ImageFileInfo {
  int width = 0, height = 0, channels = 0, depth = 1;
  StoredType type = StoredType::f32;  // u8, u16, or f32 for every other stored type
  // The pixels stored (the data window: `width` x `height` at `x`, `y`) against the image's own
  // frame (the display window: `full_width` x `full_height` at `full_x`, `full_y`); they differ
  // in EXR files cropped to their content or holding overscan.
  int x = 0, y = 0, full_x = 0, full_y = 0, full_width = 0, full_height = 0;
  // The file's channel names ("R, G") and which channel is alpha (-1: none).
  std::string channel_names;
  int alpha_channel = -1;
  // The file says its integer values are linear (a PNG whose gAMA is 1.0 and that has no sRGB
  // chunk: OpenImageIO's oiio:ColorSpace "linear").
  bool declared_linear = false;
};

// An open image file, its values kept as stored (no alpha association).
class ImageReader {
 public:
  virtual ~ImageReader() = default;
  virtual const ImageFileInfo& info() const = 0;
  // Channels 0..channels-1 of the whole image as `type` (u8, u16 or f32) into `out`, which
  // holds width * height * channels values. Returns "" or the reason it failed.
  virtual std::string read(int channels, StoredType type, void* out) = 0;
};

// Opens a reader of pelt's own (png_reader.h, jpeg_reader.h, exr_reader.h), whose
// `bool open(file, error)` reads the header: the reader, or nullptr with `error` set.
template <class Reader>
std::unique_ptr<ImageReader> open_reader(const std::string& file, std::string& error) {
  auto reader = std::make_unique<Reader>();
  if (!reader->open(file, error)) return nullptr;
  return reader;
}

// An animated GIF being written frame by frame.
class GifFrames {
 public:
  virtual ~GifFrames() = default;
  // Appends a frame of width * height * 3 sRGB bytes to `temp` (the first call creates it).
  virtual std::string append(const std::string& temp, const uint8_t* rgb) = 0;
  virtual std::string close() = 0;
};

// OpenImageIO's ImageBufAlgo::compare of the RGB channels of two RGBA8 images.
struct RgbComparison {
  double rms_error = 0, psnr = 0, max_error = 0;
  uint64_t pixels_over_threshold = 0;
};

class ImageBackend {
 public:
  virtual ~ImageBackend() = default;
  // Returns "" or the reason the file could not be written.
  virtual std::string write(const ImageWriteRequest& request) const = 0;
  // nullptr with `error` set when `file` cannot be opened as an image.
  virtual std::unique_ptr<ImageReader> open(const std::string& file, std::string& error) const = 0;
  // A GIF writer for `target` (by its extension), frames shown `fps` a second; nullptr with
  // `error` set when this OpenImageIO cannot write animated GIFs.
  virtual std::unique_ptr<GifFrames> gif(const std::string& target, int width, int height, double fps,
                                         std::string& error) const = 0;
  // Compares RGB of a and b (width * height * 4 bytes each, byte / 255 per channel); a pixel
  // is over the threshold when any channel differs by more than `threshold`.
  virtual std::string compare_rgb8(const uint8_t* a, const uint8_t* b, int width, int height, float threshold,
                                   RgbComparison& out) const = 0;
};

inline constexpr int kImageBackendAbi = 3;
// The module's one exported symbol: the backend, or nullptr when `abi` is not its own.
inline constexpr const char* kImageBackendSymbol = "pelt_image_backend";
using ImageBackendEntry = ImageBackend* (*)(int abi);

// The backend, loading the module on the first call (thread-safe; later calls return at
// once). The module is PELT_IMAGE_MODULE when that is set, else libpelt_oiio.so beside the
// executable, else the one this build made. Throws std::runtime_error naming each path
// tried and why it failed.
const ImageBackend& image_backend();
// The same, failing with InputError(file, "", reason): for loading on behalf of a file.
const ImageBackend& image_backend_for(const std::string& file);

// Starts loading the module on a thread of its own and returns; image_backend() then
// waits for it. For a command that will write images once it has done other work.
void preload_image_backend();

// Waits until a preload started above has finished (nothing to do without one). A process must
// not end while the module's libraries load: their constructors register destructors with
// exit's list as exit walks it (a PNG render of an OBJ, which needs no image, corrupted the heap
// at exit about one run in five). PreloadJoin calls it on every way out of a command, before exit
// begins: the same wait as an exit handler (std::atexit, inside exit) still crashed 8 of 30 such
// renders, the libraries' destructors then registered during exit itself.
void wait_for_image_backend_preload();
struct PreloadJoin {
  PreloadJoin() = default;
  PreloadJoin(const PreloadJoin&) = delete;
  PreloadJoin& operator=(const PreloadJoin&) = delete;
  ~PreloadJoin() { wait_for_image_backend_preload(); }
};

// True once the module is loaded (for tests and stats; never loads it).
bool image_backend_loaded();

}  // namespace pelt::io
