#include "tools/io/jpeg_reader.h"

#include <csetjmp>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <jpeglib.h>  // after <cstdio> and <cstddef>: it needs FILE and size_t

#include "tools/io/c_file.h"

namespace pelt::io {
namespace {

// What libjpeg reported, for the reader's reason: its error, after which control goes back to
// the setjmp of the call in progress, and its first warning, which libjpeg would print.
struct JpegFailure {
  std::jmp_buf jump;
  char error[JMSG_LENGTH_MAX] = {};
  char warning[JMSG_LENGTH_MAX] = {};
};

JpegFailure& failure_of(j_common_ptr jpeg) { return *static_cast<JpegFailure*>(jpeg->client_data); }

// libjpeg calls this on an error; it must not return (libjpeg's own exits the process).
[[noreturn]] void jpeg_failed(j_common_ptr jpeg) {
  JpegFailure& f = failure_of(jpeg);
  (*jpeg->err->format_message)(jpeg, f.error);
  std::longjmp(f.jump, 1);
}

// libjpeg calls this for its first warning (a later one only counts); its own prints to stderr.
void jpeg_warned(j_common_ptr jpeg) {
  JpegFailure& f = failure_of(jpeg);
  if (f.warning[0] == '\0') (*jpeg->err->format_message)(jpeg, f.warning);
}

// libjpeg calls this before each row of blocks it decodes (and each row it gives), with the
// scan's marker already counted: the scan past the limit is refused before a block of it is
// decoded. A comparison alone: it runs for every row of blocks of every scan.
void jpeg_progressed(j_common_ptr jpeg) {
  if (reinterpret_cast<j_decompress_ptr>(jpeg)->input_scan_number <= kMaxJpegScans) return;
  JpegFailure& f = failure_of(jpeg);
  std::snprintf(f.error, sizeof f.error,
                "a JPEG of more than %d scans (each scan may walk the whole image): refused as too slow to "
                "decode; re-save it with fewer scans",
                kMaxJpegScans);
  std::longjmp(f.jump, 1);
}

// OpenImageIO's CMYK to RGB, which takes the stored values as Adobe's inverted CMYK: a colour
// channel is C * K / 255 rounded to the nearest (computed there in floats; no value lies within
// 1 / 510 of a half, so the integers give its every result).
uint8_t cmyk_channel(unsigned colour, unsigned k) { return uint8_t((2 * colour * k + 255) / 510); }

class JpegReader final : public ImageReader {
 public:
  ~JpegReader() override { jpeg_destroy_decompress(&jpeg_); }  // nothing to free while jpeg_ is all zeros

  // The header alone: libjpeg decodes nothing until read(), so a file's size is checked against
  // the budget before a progressive file's coefficients are held.
  bool open(const std::string& file, std::string& error) {
    if (!file_.open(file, error) || !read_header(error)) return false;
    // libjpeg gives CMYK for a CMYK or YCCK file (its default output for both; OpenImageIO asked
    // for it all the same); the conversion to RGB is read()'s.
    cmyk_ = jpeg_.jpeg_color_space == JCS_CMYK || jpeg_.jpeg_color_space == JCS_YCCK;
    const int channels = cmyk_ ? 3 : jpeg_.num_components;
    // Its scans find no component past the fourth (OpenImageIO's open failed on "Invalid component
    // ID 4 in SOS"); four are CMYK or YCCK, so a file gives 1 to 3 channels.
    if (channels > 3) {
      error = std::to_string(channels) + " components, more than libjpeg decodes (4)";
      return false;
    }
    info_.width = int(jpeg_.image_width);
    info_.height = int(jpeg_.image_height);
    info_.channels = channels;
    info_.full_width = info_.width;
    info_.full_height = info_.height;
    info_.type = StoredType::u8;
    // OpenImageIO's default names; none is alpha.
    static constexpr const char* kNames[3] = {"Y", "R, G", "R, G, B"};
    info_.channel_names = kNames[channels - 1];
    return true;
  }

  const ImageFileInfo& info() const override { return info_; }

  std::string read(int channels, StoredType type, void* out) override {
    if (channels != info_.channels || type != info_.type)
      return "pelt's JPEG reader gives a file's own channels and type only";
    to_ = static_cast<uint8_t*>(out);
    row_.resize(cmyk_ ? size_t(info_.width) * 4 : 0);  // CMYK as libjpeg gives it
    // Nothing of this frame changes after the setjmp (decode's locals go with its frame).
    if (setjmp(failure_.jump)) return failure_.error;
    return decode();
  }

 private:
  // libjpeg's part of open(). Every C++ object of this frame exists before the setjmp, so a
  // longjmp skips no destructor, and nothing of it changes after.
  [[gnu::noinline]] bool read_header(std::string& error) {
    jpeg_.err = jpeg_std_error(&manager_);
    manager_.error_exit = jpeg_failed;
    manager_.output_message = jpeg_warned;
    jpeg_.client_data = &failure_;  // kept by jpeg_create_decompress, like err
    progress_.progress_monitor = jpeg_progressed;
    if (setjmp(failure_.jump)) {
      error = failure_.error;
      return false;
    }
    jpeg_create_decompress(&jpeg_);
    // Set after jpeg_create_decompress, which clears it. jpeg_read_header stops at the first scan
    // and calls no monitor; the scans are counted in decode(), under read()'s setjmp.
    jpeg_.progress = &progress_;
    jpeg_stdio_src(&jpeg_, file_.get());
    jpeg_read_header(&jpeg_, TRUE);  // a file of tables and no image is an error
    return true;
  }

  // libjpeg's rows into to_; an error longjmps out to read().
  [[gnu::noinline]] std::string decode() {
    jpeg_start_decompress(&jpeg_);  // a progressive file's every scan is decoded here
    const size_t width = size_t(info_.width), channels = size_t(info_.channels);
    if (jpeg_.output_width != width || jpeg_.output_height != unsigned(info_.height) ||
        size_t(jpeg_.output_components) != (cmyk_ ? 4 : channels))
      return "libjpeg's rows are not the size expected";
    uint8_t* to = to_;
    while (jpeg_.output_scanline < jpeg_.output_height && failure_.warning[0] == '\0') {
      JSAMPROW into = cmyk_ ? row_.data() : to;
      if (jpeg_read_scanlines(&jpeg_, &into, 1) != 1) return "libjpeg gave no row";
      if (cmyk_)
        for (size_t x = 0; x < width; ++x)
          for (size_t c = 0; c < 3; ++c) to[3 * x + c] = cmyk_channel(row_[4 * x + c], row_[4 * x + 3]);
      to += width * channels;
    }
    // A warning on the header or a row (the loop stops at the first). No jpeg_finish_decompress:
    // OpenImageIO stopped at the last row too. Aborted instead, which reads nothing more: a
    // progressive file's coefficients (6-8 bytes a texel) are freed before the caller converts
    // the pixels, not when the reader goes.
    if (failure_.warning[0] != '\0') return failure_.warning;
    jpeg_abort_decompress(&jpeg_);
    return {};
  }

  CFile file_;  // closed after jpeg_ is destroyed
  jpeg_decompress_struct jpeg_{};
  jpeg_error_mgr manager_{};
  jpeg_progress_mgr progress_{};
  JpegFailure failure_;
  bool cmyk_ = false;
  ImageFileInfo info_;
  uint8_t* to_ = nullptr;  // read()'s pixels
  std::vector<JSAMPLE> row_;
};

}  // namespace

std::unique_ptr<ImageReader> open_jpeg(const std::string& file, std::string& error) {
  return open_reader<JpegReader>(file, error);
}

}  // namespace pelt::io
