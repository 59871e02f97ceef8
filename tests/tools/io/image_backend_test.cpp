// The OpenImageIO module is loaded when an image other than a PNG or JPEG is first read, or one
// other than a PNG or EXR first written, not at start-up, and a module that cannot be loaded is a
// clear InputError. Each case runs in a fresh process (a "threadsafe" death test re-executes this
// binary), since a process loads it only once.
#include "tools/io/image_backend.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/fresh_process.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace {

bool mapped(const std::string& library) {
  std::ifstream maps("/proc/self/maps");
  std::stringstream s;
  s << maps.rdbuf();
  return s.str().find(library) != std::string::npos;
}

size_t files_in(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

TEST(ImageBackend, LoadsOnlyWhenAnImageIsTouched) {
  in_fresh_process([]() -> std::string {
    if (mapped("libOpenImageIO")) return "OpenImageIO is loaded at start-up";
    if (image_backend_loaded()) return "the module is loaded at start-up";
    TempDir dir;
    const std::vector<float> px(4 * 3 * 4, 0.5f);
    // A PNG is written by libpng itself (png_writer.h): the module stays unloaded.
    write_image_atomic(dir.path() / "a.png", 4, 3, 4, PixelType::f32, px.data());
    if (image_backend_loaded() || mapped("libOpenImageIO")) return "writing a PNG loaded the module";
    // Nor does reading it back, or a JPEG (the default scene's colour map): libpng and libjpeg read
    // them (png_reader.h, jpeg_reader.h).
    const char* root = std::getenv("PELT_SOURCE_DIR");
    const auto jpeg = std::filesystem::path(root ? root : ".") / "tools/data/LeePerrySmith/Map-COL.jpg";
    if (read_image_rgba(dir.path() / "a.png").width != 4 || read_image_rgba(jpeg).width != 1024)
      return "a PNG or JPEG read back wrong";
    if (image_backend_loaded() || mapped("libOpenImageIO")) return "reading a PNG or JPEG loaded the module";
    // Nor does writing an EXR: OpenEXR's library writes it (exr_writer.h).
    write_image_atomic(dir.path() / "a.exr", 4, 3, 4, PixelType::f32, px.data());
    if (image_backend_loaded() || mapped("libOpenImageIO")) return "writing an EXR loaded the module";
    write_image_atomic(dir.path() / "a.tif", 4, 3, 4, PixelType::f32, px.data());
    if (!image_backend_loaded()) return "writing a TIFF did not load the module";
    if (!mapped("libpelt_oiio.so") || !mapped("libOpenImageIO")) return "the module or OpenImageIO is not mapped";
    const ImageHeader h = read_image_header(dir.path() / "a.png");
    if (h.width != 4 || h.height != 3 || h.channels != 4 || h.bytes_per_channel != 1) return "header read back wrong";
    return {};
  });
}

TEST(ImageBackend, AModuleThatCannotBeLoadedIsAnInputErrorAndLeavesNoFile) {
  in_fresh_process([]() -> std::string {
    TempDir dir;
    const std::string missing = (dir.path() / "nowhere" / "libpelt_oiio.so").string();
    ::setenv("PELT_IMAGE_MODULE", missing.c_str(), 1);
    const std::filesystem::path out = dir.path() / "a.tif";  // a PNG or an EXR needs no module (png_writer.h, exr_writer.h)
    const std::vector<float> px(2 * 2 * 4, 0.5f);
    try {
      write_image_atomic(out, 2, 2, 4, PixelType::f32, px.data());
      return "the write succeeded without the module";
    } catch (const InputError& e) {
      if (e.file != out.string()) return "the error names " + e.file;
      if (e.reason.find(missing) == std::string::npos) return "the reason does not name the module: " + e.reason;
      if (e.reason.find("PELT_IMAGE_MODULE") == std::string::npos) return "no hint of the override: " + e.reason;
    }
    if (files_in(dir.path()) != 0) return "a file was left behind";
    if (image_backend_loaded()) return "reported as loaded";
    // A later image fails the same way, without trying again.
    try {
      (void)read_image_header(out);
      return "reading succeeded";
    } catch (const InputError&) {
    }
    return {};
  });
}

TEST(ImageBackend, ALibraryWithoutTheEntryIsRefusedByName) {
  in_fresh_process([]() -> std::string {
    ::setenv("PELT_IMAGE_MODULE", "libm.so.6", 1);
    try {
      (void)image_backend();
      return "libm was taken for the module";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (what.find("libm.so.6") == std::string::npos || what.find(kImageBackendSymbol) == std::string::npos)
        return "unclear reason: " + what;
    }
    return {};
  });
}

TEST(ImageBackend, PreloadThenUse) {
  in_fresh_process([]() -> std::string {
    preload_image_backend();
    preload_image_backend();  // a second call while loading changes nothing
    const ImageBackend& b = image_backend();
    if (!image_backend_loaded()) return "not loaded after image_backend()";
    if (&b != &image_backend()) return "a second backend";
    return {};
  });
}

}  // namespace
}  // namespace pelt::io
