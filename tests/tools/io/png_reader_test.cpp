// PNG files read by libpng itself (tools/io/png_reader.h) give what OpenImageIO's PNG reader gave
// pelt: the same channels, channel names, sample type, alpha channel, linear declaration and
// values, on every colour type and bit depth PNG allows, with and without a tRNS chunk, interlaced
// or not, and with the gAMA and sRGB chunks that decide whether a file is linear. The files are made here
// with libpng, so each variant is exactly the one named.
#include "tools/io/png_reader.h"

#include <png.h>

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/oiio_view.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace png_reader_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Variant {
  int color_type, bit_depth;
  bool trns = false, interlaced = false;
  int gamma = 0;  // gAMA as libpng's fixed point (100000 = 1.0); 0: no chunk
  bool srgb = false;
  std::string name() const {
    return "type " + std::to_string(color_type) + ", " + std::to_string(bit_depth) + " bits" + (trns ? ", tRNS" : "") +
           (interlaced ? ", Adam7" : "") + (gamma ? ", gAMA " + std::to_string(gamma) : "") + (srgb ? ", sRGB" : "");
  }
};

constexpr int kW = 7, kH = 5;

// The variant as a file: samples vary over the whole range of the bit depth; a palette of 16
// colours, some of them transparent under tRNS.
void write_variant(const std::string& file, const Variant& v) {
  std::FILE* out = std::fopen(file.c_str(), "wb");
  ASSERT_NE(out, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_TRUE(png && info);
  const int channels = v.color_type == PNG_COLOR_TYPE_GRAY        ? 1
                       : v.color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                       : v.color_type == PNG_COLOR_TYPE_RGB        ? 3
                       : v.color_type == PNG_COLOR_TYPE_RGB_ALPHA  ? 4
                                                                   : 1;
  const uint32_t top = (1u << v.bit_depth) - 1;
  const uint32_t colours = v.color_type == PNG_COLOR_TYPE_PALETTE ? std::min<uint32_t>(16, top + 1) : top + 1;
  std::vector<uint8_t> rows(size_t(kH) * kW * channels * 2);
  std::vector<png_bytep> row_ptrs(kH);
  const size_t stride = size_t(kW) * channels * (v.bit_depth == 16 ? 2 : 1);
  for (int y = 0; y < kH; ++y) {
    row_ptrs[y] = rows.data() + size_t(y) * stride;
    for (int i = 0; i < kW * channels; ++i) {
      const uint32_t value = (uint32_t(y * kW * channels + i) * 2654435761u >> 7) % colours;
      if (v.bit_depth == 16) {
        const uint32_t wide = (value * 40503u) & 0xFFFF;  // spread over 16 bits
        row_ptrs[y][2 * i] = uint8_t(wide >> 8), row_ptrs[y][2 * i + 1] = uint8_t(wide);
      } else {
        row_ptrs[y][i] = uint8_t(v.bit_depth == 8 && v.color_type != PNG_COLOR_TYPE_PALETTE ? (value * 97u) & 0xFF : value);
      }
    }
  }
  if (setjmp(png_jmpbuf(png))) {
    ADD_FAILURE() << "libpng failed writing " << v.name();
    png_destroy_write_struct(&png, &info);
    std::fclose(out);
    return;
  }
  png_init_io(png, out);
  png_set_IHDR(png, info, kW, kH, v.bit_depth, v.color_type, v.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette(16);
  std::vector<png_byte> alphas(16);
  for (int k = 0; k < 16; ++k) {
    palette[k] = png_color{png_byte(k * 16), png_byte(255 - k * 9), png_byte(k * 5 + 3)};
    alphas[k] = png_byte(k % 3 == 0 ? 0 : k * 15);
  }
  if (v.color_type == PNG_COLOR_TYPE_PALETTE) png_set_PLTE(png, info, palette.data(), int(colours));
  if (v.trns) {
    if (v.color_type == PNG_COLOR_TYPE_PALETTE) {
      png_set_tRNS(png, info, alphas.data(), int(colours), nullptr);
    } else {
      png_color_16 key{};
      key.gray = png_uint_16(1 % (top + 1));
      key.red = png_uint_16(v.bit_depth == 16 ? 40503u : 97u), key.green = 0, key.blue = png_uint_16(top);
      png_set_tRNS(png, info, nullptr, 0, &key);
    }
  }
  if (v.gamma) png_set_gAMA_fixed(png, info, v.gamma);
  if (v.srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  if (v.bit_depth < 8) png_set_packing(png);  // one sample a byte in our rows
  png_write_image(png, row_ptrs.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(out);
}

std::vector<Variant> variants() {
  std::vector<Variant> out;
  for (int depth : {1, 2, 4, 8, 16}) {
    out.push_back({PNG_COLOR_TYPE_GRAY, depth});
    out.push_back({PNG_COLOR_TYPE_GRAY, depth, true});
  }
  for (int depth : {1, 2, 4, 8}) {
    out.push_back({PNG_COLOR_TYPE_PALETTE, depth});
    out.push_back({PNG_COLOR_TYPE_PALETTE, depth, true});
  }
  for (int depth : {8, 16}) {
    out.push_back({PNG_COLOR_TYPE_GRAY_ALPHA, depth});
    out.push_back({PNG_COLOR_TYPE_RGB, depth});
    out.push_back({PNG_COLOR_TYPE_RGB, depth, true});
    out.push_back({PNG_COLOR_TYPE_RGB_ALPHA, depth});
  }
  out.push_back({PNG_COLOR_TYPE_RGB, 8, false, true});
  out.push_back({PNG_COLOR_TYPE_PALETTE, 4, true, true});
  out.push_back({PNG_COLOR_TYPE_GRAY_ALPHA, 16, false, true});
  // (libpng refuses to write an sRGB chunk beside a gAMA far from sRGB's.)
  for (const int gamma : {100000, 45455, 99999, 99500, 99510, 100500, 100510, 200000})
    out.push_back({PNG_COLOR_TYPE_RGB, 8, false, false, gamma});
  out.push_back({PNG_COLOR_TYPE_RGB, 8, false, false, 45455, true});
  out.push_back({PNG_COLOR_TYPE_RGB, 8, false, false, 0, true});
  out.push_back({PNG_COLOR_TYPE_GRAY, 16, true, false, 100000});
  return out;
}

TEST(PngReader, ReadsWhatOpenImageIoReadOnEveryKindOfPng) {
  TempDir dir;
  int n = 0;
  for (const Variant& v : variants()) {
    const std::string file = (dir.path() / (std::to_string(n++) + ".png")).string();
    write_variant(file, v);
    ASSERT_EQ(encoded_kind(std::filesystem::path(file)), EncodedKind::png);
    std::string error;
    const auto ours = open_png(file, error);
    ASSERT_TRUE(ours) << v.name() << ": " << error;
    EXPECT_EQ(ours->info().width, kW);
    EXPECT_EQ(ours->info().height, kH);
    expect_read_as_by_oiio(*ours, file, v.name());
  }
}

// A file cut short or corrupted is an error naming the file, through read_image_rgba as before;
// libpng's own line is not printed (its warnings and errors come back as the reason).
TEST(PngReader, ACutOrCorruptFileIsAnError) {
  TempDir dir;
  const std::string good = (dir.path() / "good.png").string();
  write_variant(good, {PNG_COLOR_TYPE_RGB, 8});
  std::ifstream in(good, std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto expect_refused = [&](const std::string& name, const std::string& bytes) {
    const auto path = dir.path() / name;
    std::ofstream(path, std::ios::binary) << bytes;
    try {
      (void)read_image_rgba(path);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, path.string());
      EXPECT_FALSE(e.reason.empty());
    }
  };
  expect_refused("cut.png", all.substr(0, all.size() - 30));
  std::string corrupt = all;
  corrupt[all.size() - 20] = char(corrupt[all.size() - 20] ^ 0x5A);  // inside the IDAT: a CRC or zlib error
  expect_refused("corrupt.png", corrupt);
  expect_refused("header.png", all.substr(0, 20));
}

}  // namespace png_reader_test
}  // namespace pelt::io
