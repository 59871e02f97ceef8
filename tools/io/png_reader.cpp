#include "tools/io/png_reader.h"

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <vector>

#include "tools/io/c_file.h"
#include "tools/io/png_errors.h"

namespace pelt::io {
namespace {

class PngReader final : public ImageReader {
 public:
  ~PngReader() override {
    if (png_) png_destroy_read_struct(&png_, info_ptr_ ? &info_ptr_ : nullptr, nullptr);
  }

  // The header, and the transforms that give OpenImageIO's channels and types. Every C++ object
  // of this frame exists before the setjmp, so a longjmp skips no destructor.
  bool open(const std::string& file, std::string& error) {
    if (!file_.open(file, error)) return false;
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &failure_, png_failed, png_warned);
    if (png_) info_ptr_ = png_create_info_struct(png_);
    if (!png_ || !info_ptr_) {
      error = "libpng could not start reading";
      return false;
    }
    if (setjmp(png_jmpbuf(png_))) {
      error = failure_.message;
      return false;
    }
    png_init_io(png_, file_.get());
    png_read_info(png_, info_ptr_);
    const int color_type = png_get_color_type(png_, info_ptr_);
    const int bit_depth = png_get_bit_depth(png_, info_ptr_);
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png_);
    if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png_);
    if (png_get_valid(png_, info_ptr_, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png_);
    if (bit_depth == 16) png_set_swap(png_);  // the file's big-endian samples as this machine's
    png_set_interlace_handling(png_);
    png_read_update_info(png_, info_ptr_);
    info_.width = int(png_get_image_width(png_, info_ptr_));
    info_.height = int(png_get_image_height(png_, info_ptr_));
    info_.channels = png_get_channels(png_, info_ptr_);
    info_.full_width = info_.width;
    info_.full_height = info_.height;
    info_.type = png_get_bit_depth(png_, info_ptr_) == 16 ? StoredType::u16 : StoredType::u8;
    static constexpr const char* kNames[4] = {"Y", "Y, A", "R, G, B", "R, G, B, A"};
    info_.channel_names = info_.channels >= 1 && info_.channels <= 4 ? kNames[info_.channels - 1] : "";
    info_.alpha_channel = info_.channels == 2 || info_.channels == 4 ? info_.channels - 1 : -1;
    // OpenImageIO's rule: no sRGB chunk, and a gAMA whose exponent (1 / gamma) rounds to 1.00 at two
    // decimals (gAMA 99503 to 100502; 99500 reads "Gamma1.01" there, `oiiotool --info -v`).
    png_fixed_point gamma = 0;
    if (!png_get_valid(png_, info_ptr_, PNG_INFO_sRGB) && png_get_gAMA_fixed(png_, info_ptr_, &gamma) != 0 && gamma > 0)
      info_.declared_linear = std::lround(1e7 / double(gamma)) == 100;
    return true;
  }

  const ImageFileInfo& info() const override { return info_; }

  std::string read(int channels, StoredType type, void* out) override {
    if (channels != info_.channels || type != info_.type)
      return "pelt's PNG reader gives a file's own channels and type only";
    const size_t row = size_t(info_.width) * size_t(channels) * (type == StoredType::u16 ? 2 : 1);
    if (png_get_rowbytes(png_, info_ptr_) != row) return "libpng's rows are not the size expected";
    std::vector<png_bytep> rows(size_t(info_.height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = static_cast<png_bytep>(out) + y * row;
    if (setjmp(png_jmpbuf(png_))) return failure_.message;
    png_read_image(png_, rows.data());
    png_read_end(png_, nullptr);
    return {};
  }

 private:
  CFile file_;  // closed after png_ is destroyed
  png_structp png_ = nullptr;
  png_infop info_ptr_ = nullptr;
  PngFailure failure_;
  ImageFileInfo info_;
};

}  // namespace

std::unique_ptr<ImageReader> open_png(const std::string& file, std::string& error) {
  return open_reader<PngReader>(file, error);
}

}  // namespace pelt::io
