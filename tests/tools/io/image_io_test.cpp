#include "tools/io/image_io.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tests/tools/io/linear_png.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"
#include "tools/io/srgb.h"

namespace pelt::io {
namespace {

std::vector<float> ramp(int w, int h, int c) {
  std::vector<float> v(static_cast<size_t>(w) * h * c);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>((i * 37) % 101) / 100.0f;
  return v;
}

// Reads a file back with OIIO in its own stored type, values as stored (no multiplying
// by alpha on read).
template <class T>
std::vector<T> read_back(const std::filesystem::path& p, OIIO::TypeDesc type, OIIO::ImageSpec& spec) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(p.string(), &config);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  spec = in->spec();
  std::vector<T> data(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, type, data.data()));
  return data;
}

size_t files_in(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

// A truncated or corrupt JPEG or TIFF: OpenImageIO's read succeeds with the missing part grey or
// black and the decoder's complaint left as an error, which is the read's failure.
TEST(ImageIo, TruncatedJpegAndTiffAreRefused) {
  TempDir dir;
  std::vector<uint8_t> noise(64 * 64 * 3);
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = uint8_t((i * 2654435761u) >> 24);
  for (const char* name : {"full.jpg", "full.tif"}) {
    const std::filesystem::path full = dir.path() / name;
    auto out = OIIO::ImageOutput::create(full.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(64, 64, 3, OIIO::TypeDesc::UINT8);
    if (std::string(name) == "full.tif") spec.attribute("compression", "zip");
    ASSERT_TRUE(out->open(full.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, noise.data()));
    ASSERT_TRUE(out->close());
    EXPECT_EQ(read_image_rgba(full).width, 64) << name;  // whole, it reads
    std::string bytes;
    {
      std::ifstream in(full, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::filesystem::path cut = dir.path() / (std::string("cut_") + name);
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * 2 / 3));
    try {
      read_image_rgba(cut);
      ADD_FAILURE() << cut << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(e.reason.find("reading the pixels failed: "), std::string::npos) << e.what();
    }
  }
}

// An EXR whose stored pixels (data window) are not its frame (display window) is refused: read
// as stored, a crop's pixels covered the whole map. A non-finite texel is named.
TEST(ImageIo, AWindowedExrIsRefusedAndANonFiniteTexelNamed) {
  TempDir dir;
  const auto write_exr = [&](const std::string& name, int x, int y, const std::vector<float>& px) {
    const std::filesystem::path path = dir.path() / name;
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::FLOAT);
    spec.x = x, spec.y = y;
    spec.full_x = 0, spec.full_y = 0, spec.full_width = 8, spec.full_height = 8;
    if (x == 0 && y == 0) spec.full_width = spec.full_height = 4;
    EXPECT_TRUE(out->open(path.string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    EXPECT_TRUE(out->close());
    return path;
  };
  std::vector<float> grey(4 * 4 * 3, 0.5f);
  const auto cropped = write_exr("cropped.exr", 2, 2, grey);
  for (int header = 0; header < 2; ++header) {
    try {
      if (header) read_image_header(cropped);
      else read_image_rgba(cropped, ColorEncoding::linear);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(e.reason.find("its pixels (4 x 4 at 2, 2) are not its frame (8 x 8 at 0, 0)"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(read_image_rgba(write_exr("whole.exr", 0, 0, grey), ColorEncoding::linear).width, 4);
  grey[(2 * 4 + 3) * 3 + 1] = std::nanf("");
  try {
    read_image_rgba(write_exr("nan.exr", 0, 0, grey), ColorEncoding::linear);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason.find("texel (3, 2) channel g is NaN"), std::string::npos) << e.what();
  }
  // A channel the caller does not draw may hold anything (until 2026-11-27 a NaN there refused
  // the map): a length map reads r alone, so g's NaN reads as 0 and r stays.
  const ImageRGBA first = read_image_rgba(dir.path() / "nan.exr", ColorEncoding::linear, Budget{}, 1);
  EXPECT_EQ(first.rgba[(2 * 4 + 3) * 4 + 1], 0.0f);
  EXPECT_EQ(first.rgba[(2 * 4 + 3) * 4 + 0], 0.5f);
}

// A PNG that says its values are linear (gAMA 1.0, no sRGB chunk) is read linear where the
// caller allows it (srgb_unless_linear: colour maps not named by a glTF), and as sRGB where the
// caller says sRGB (glTF tells loaders to ignore a PNG's gamma). A 4 x 4 image of 128s.
TEST(ImageIo, APngDeclaredLinearIsReadLinearWhereAllowed) {
  TempDir dir;
  const std::filesystem::path linear_png = dir.path() / "linear.png";
  write_linear_png(linear_png);
  const float as_linear = read_image_rgba(linear_png, ColorEncoding::srgb_unless_linear).rgba[0];
  const float as_srgb = read_image_rgba(linear_png, ColorEncoding::srgb).rgba[0];
  EXPECT_FLOAT_EQ(as_linear, 128.0f / 255.0f);
  EXPECT_NEAR(as_srgb, 0.2158605f, 1e-6f);
  // A PNG without the chunk reads as sRGB either way.
  const std::vector<uint8_t> grey(4 * 4 * 3, 128);
  write_image_atomic(dir.path() / "plain.png", 4, 4, 3, PixelType::u8, grey.data());
  EXPECT_NEAR(read_image_rgba(dir.path() / "plain.png", ColorEncoding::srgb_unless_linear).rgba[0], 0.2158605f, 1e-6f);
}

// Two channels are read as grey and alpha: a grey-alpha PNG reads so, an EXR of R and G (two
// colour channels, as two-channel normal maps are stored) is refused instead of drawn grey.
TEST(ImageIo, TwoChannelsMustBeGreyAndAlpha) {
  TempDir dir;
  const std::vector<float> px(4 * 4 * 2, 0.5f);
  for (const char* name : {"ya.png", "rg.exr"}) {
    const std::filesystem::path path = dir.path() / name;
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(4, 4, 2, std::string(name) == "ya.png" ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (std::string(name) == "ya.png") {
      spec.channelnames = {"Y", "A"};
      spec.alpha_channel = 1;
    } else {
      spec.channelnames = {"R", "G"};
      spec.alpha_channel = -1;
    }
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    ASSERT_TRUE(out->close());
  }
  const ImageRGBA ya = read_image_rgba(dir.path() / "ya.png");
  EXPECT_EQ(ya.rgba[0], ya.rgba[1]);  // grey
  try {
    read_image_rgba(dir.path() / "rg.exr", ColorEncoding::linear);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason.find("its 2 channels (R, G) are not grey and alpha"), std::string::npos) << e.what();
  }
}

// An image named inside a mesh file (an MTL's map_Kd, a glTF's uri) reaches the reader with no
// scene-level check: a folder, a pipe or a device is refused unread (a pipe hung the set-up).
TEST(ImageIo, AFolderPipeOrDeviceIsRefusedUnread) {
  TempDir dir;
  const std::filesystem::path folder = dir.path() / "folder.png", pipe = dir.path() / "pipe.png",
                              device = dir.path() / "device.png";
  std::filesystem::create_directory(folder);
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0644), 0);
  std::filesystem::create_symlink("/dev/zero", device);
  for (const auto& [path, reason] : {std::pair{folder, "is a folder, not an image file"},
                                     std::pair{pipe, "is not a regular file (a device, a pipe or a socket)"},
                                     std::pair{device, "is not a regular file (a device, a pipe or a socket)"}}) {
    for (int header = 0; header < 2; ++header) {
      try {
        if (header) read_image_header(path);
        else read_image_rgba(path);
        ADD_FAILURE() << path << " accepted";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file, path.string());
        EXPECT_NE(e.reason.find(reason), std::string::npos) << e.what();
      }
    }
  }
}

TEST(ImageIo, PngFromLinearFloatIsExactSrgb) {
  TempDir dir;
  const auto f = dir.path() / "out.png";
  const auto px = ramp(7, 5, 4);
  write_image_atomic(f, 7, 5, 4, PixelType::f32, px.data());
  OIIO::ImageSpec spec;
  const auto bytes = read_back<uint8_t>(f, OIIO::TypeDesc::UINT8, spec);
  ASSERT_EQ(spec.width, 7);
  ASSERT_EQ(spec.height, 5);
  ASSERT_EQ(spec.nchannels, 4);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  for (size_t i = 0; i < px.size(); ++i)
    ASSERT_EQ(bytes[i], i % 4 == 3 ? linear_to_unorm8(px[i]) : linear_to_srgb8(px[i])) << i;
  EXPECT_EQ(files_in(dir.path()), 1u);  // no temporary left
}

// PNG holds straight colour: a render's premultiplied colour is divided by alpha first, so a
// half-covered edge of a green square over a transparent background is green at half alpha
// (not a darker green, nor the background's colour).
TEST(ImageIo, PngFromPremultipliedFloatStoresStraightColour) {
  TempDir dir;
  const std::vector<float> px = {0.0f, 0.5f, 0.0f, 0.5f,  0.0f, 1.0f, 0.0f, 1.0f,  0.1f, 0.2f, 0.3f, 0.0f,
                                 0.2f, 0.1f, 0.05f, 0.25f};
  ImageWriteOptions premultiplied;
  premultiplied.alpha = Alpha::premultiplied;
  for (const char* name : {"p.png", "p.tif"}) {
    write_image_atomic(dir.path() / name, 4, 1, 4, PixelType::f32, px.data(), premultiplied);
    OIIO::ImageSpec spec;
    const auto bytes = read_back<uint8_t>(dir.path() / name, OIIO::TypeDesc::UINT8, spec);
    const std::vector<uint8_t> want = {0,   255, 0, 128, 0, 255, 0, 255, 0, 0, 0, 0, linear_to_srgb8(0.8f),
                                       linear_to_srgb8(0.4f), linear_to_srgb8(0.2f), 64};
    EXPECT_EQ(bytes, want) << name;
  }
}

// Every compression level stores the same bytes; the levels trade size for time. The image
// is smooth, as rendered frames are, so zlib finds something to squeeze.
TEST(ImageIo, PngCompressionLevelsStoreTheSameBytes) {
  TempDir dir;
  constexpr int kW = 64, kH = 48;
  std::vector<float> px(size_t(kW) * kH * 4);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 4; ++c) px[(size_t(y) * kW + x) * 4 + c] = c == 3 ? 1.0f : float(x + y * c) / float(kW + kH * 3);
  std::vector<uintmax_t> sizes;
  std::vector<uint8_t> first;
  for (int level : {0, 1, 6, 9}) {
    std::string name = std::to_string(level);  // appended: `"l" + string` trips GCC 12's -Wstringop-overflow
    name += ".png";
    const auto f = dir.path() / name;
    write_image_atomic(f, kW, kH, 4, PixelType::f32, px.data(), ImageWriteOptions{level});
    OIIO::ImageSpec spec;
    const auto bytes = read_back<uint8_t>(f, OIIO::TypeDesc::UINT8, spec);
    if (first.empty()) first = bytes;
    EXPECT_EQ(bytes, first) << "level " << level;
    sizes.push_back(std::filesystem::file_size(f));
  }
  EXPECT_GT(sizes[0], sizes[1]);  // 0 stores the rows uncompressed
  EXPECT_GE(sizes[1], sizes[3]);
  // The default is level 1.
  write_image_atomic(dir.path() / "d.png", kW, kH, 4, PixelType::f32, px.data());
  EXPECT_EQ(std::filesystem::file_size(dir.path() / "d.png"), sizes[1]);
}

TEST(ImageIo, PngCompressionOutsideZeroToNineIsAnInputErrorAndWritesNothing) {
  TempDir dir;
  const std::vector<float> px(4, 0.5f);
  for (int level : {-1, 10}) {
    try {
      write_image_atomic(dir.path() / "a.png", 1, 1, 4, PixelType::f32, px.data(), ImageWriteOptions{level});
      ADD_FAILURE() << "level " << level << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(e.reason.find("outside 0..9"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(files_in(dir.path()), 0u);
}

TEST(ImageIo, TiffEightBitAndUint32AndFloat) {
  TempDir dir;
  const auto rgb = ramp(4, 3, 3);
  write_image_atomic(dir.path() / "c.tif", 4, 3, 3, PixelType::f32, rgb.data());
  OIIO::ImageSpec spec;
  const auto bytes = read_back<uint8_t>(dir.path() / "c.tif", OIIO::TypeDesc::UINT8, spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  for (size_t i = 0; i < rgb.size(); ++i) ASSERT_EQ(bytes[i], linear_to_srgb8(rgb[i]));

  std::vector<uint32_t> ids = {0, 1, 70000, 4000000000u, 5, 6};
  write_image_atomic(dir.path() / "id.tiff", 3, 2, 1, PixelType::u32, ids.data());
  const auto back = read_back<uint32_t>(dir.path() / "id.tiff", OIIO::TypeDesc::UINT32, spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT32);
  EXPECT_EQ(back, ids);

  std::vector<float> depth = {0.5f, 1e-7f, 123456.75f, -2.0f};
  write_image_atomic(dir.path() / "d.tif", 2, 2, 1, PixelType::f32, depth.data());
  const auto dback = read_back<float>(dir.path() / "d.tif", OIIO::TypeDesc::FLOAT, spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(dback, depth);
}

// EXR holds premultiplied colour (OpenEXR's convention, which its readers assume): a render's
// premultiplied floats are stored as they are, straight ones multiplied by alpha.
TEST(ImageIo, ExrFloatRgbaAndOneChannel) {
  TempDir dir;
  const auto rgba = ramp(5, 4, 4);
  std::vector<float> hdr = rgba;
  hdr[0] = 1234.5f;
  ImageWriteOptions premultiplied;
  premultiplied.alpha = Alpha::premultiplied;
  write_image_atomic(dir.path() / "c.exr", 5, 4, 4, PixelType::f32, hdr.data(), premultiplied);
  OIIO::ImageSpec spec;
  EXPECT_EQ(read_back<float>(dir.path() / "c.exr", OIIO::TypeDesc::FLOAT, spec), hdr);
  EXPECT_EQ(spec.nchannels, 4);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  write_image_atomic(dir.path() / "s.exr", 5, 4, 4, PixelType::f32, hdr.data());  // straight
  std::vector<float> want = hdr;
  for (size_t p = 0; p < want.size(); p += 4)
    for (int c = 0; c < 3; ++c) want[p + c] *= want[p + 3];
  EXPECT_EQ(read_back<float>(dir.path() / "s.exr", OIIO::TypeDesc::FLOAT, spec), want);
  // OIIO's own reading (which associates what a file marks unassociated) finds the same.
  auto in = OIIO::ImageInput::open((dir.path() / "s.exr").string());
  ASSERT_TRUE(in);
  std::vector<float> plain(want.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, plain.data()));
  EXPECT_EQ(plain, want);
  EXPECT_EQ(in->spec().get_int_attribute("oiio:UnassociatedAlpha", 0), 0);
  std::vector<float> z = {0.25f, 3.0e10f, 7.0f, 0.0f, 1.0f, 2.0f};
  write_image_atomic(dir.path() / "z.exr", 3, 2, 1, PixelType::f32, z.data());
  EXPECT_EQ(read_back<float>(dir.path() / "z.exr", OIIO::TypeDesc::FLOAT, spec), z);
  EXPECT_EQ(spec.nchannels, 1);
}

// A file's bytes depend on its pixels only: no wall-clock time in the header (OIIO's TIFF writer,
// and its EXR writer that pelt used until 2026-11-28, add DateTime unless told not to; pelt's own
// EXR writer writes none), so two renders of a frame compare with cmp.
TEST(ImageIo, ExrAndTiffCarryNoWriteTime) {
  TempDir dir;
  const auto px = ramp(3, 2, 4);
  for (const char* name : {"t.exr", "t.tif"}) {
    write_image_atomic(dir.path() / name, 3, 2, 4, PixelType::f32, px.data());
    OIIO::ImageSpec spec;
    EXPECT_EQ(read_back<float>(dir.path() / name, OIIO::TypeDesc::FLOAT, spec).size(), px.size()) << name;
    EXPECT_EQ(spec.find_attribute("DateTime"), nullptr) << name << ": " << spec.get_string_attribute("DateTime");
  }
}

TEST(ImageIo, OverwritesAnExistingFileWhole) {
  TempDir dir;
  const auto f = dir.path() / "o.exr";
  const auto a = ramp(8, 8, 4);
  ImageWriteOptions as_stored;  // premultiplied floats go into an EXR as they are
  as_stored.alpha = Alpha::premultiplied;
  write_image_atomic(f, 8, 8, 4, PixelType::f32, a.data(), as_stored);
  std::vector<float> b = {1, 2, 3, 4};
  write_image_atomic(f, 1, 1, 4, PixelType::f32, b.data(), as_stored);
  OIIO::ImageSpec spec;
  EXPECT_EQ(read_back<float>(f, OIIO::TypeDesc::FLOAT, spec), b);
  EXPECT_EQ(files_in(dir.path()), 1u);
}

void expect_write_error(const std::filesystem::path& f, int channels, PixelType type, const void* px,
                        const std::string& reason_part) {
  try {
    write_image_atomic(f, 2, 2, channels, type, px);
    FAIL() << f;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, f.string());
    EXPECT_NE(e.reason.find(reason_part), std::string::npos) << e.what();
  }
}

TEST(ImageIo, FailedWritesLeaveNothingBehind) {
  TempDir dir;
  const auto px = ramp(2, 2, 4);
  expect_write_error(dir.path() / "missing" / "out.png", 4, PixelType::f32, px.data(), "cannot create");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "missing"));
  EXPECT_EQ(files_in(dir.path()), 0u);
  if (::geteuid() != 0) {  // root ignores permission bits
    std::filesystem::create_directories(dir.path() / "ro");
    ::chmod((dir.path() / "ro").c_str(), 0555);
    expect_write_error(dir.path() / "ro" / "out.exr", 4, PixelType::f32, px.data(), "cannot create");
    EXPECT_EQ(files_in(dir.path() / "ro"), 0u);
    ::chmod((dir.path() / "ro").c_str(), 0755);
  }
  // The target is a folder: the temporary is written, the rename fails, and both the
  // folder and the folder's parent are left as they were.
  std::filesystem::create_directories(dir.path() / "taken.png" / "inside");
  expect_write_error(dir.path() / "taken.png", 4, PixelType::f32, px.data(), "cannot move");
  EXPECT_TRUE(std::filesystem::is_directory(dir.path() / "taken.png" / "inside"));
  EXPECT_EQ(files_in(dir.path()), 1u);
}

TEST(ImageIo, RejectsUnknownExtensionsAndUnsupportedCombinations) {
  TempDir dir;
  const auto px = ramp(2, 2, 4);
  std::vector<uint32_t> ids(4, 1);
  expect_write_error(dir.path() / "o.jpg", 4, PixelType::f32, px.data(), "unsupported image extension `.jpg`");
  expect_write_error(dir.path() / "o", 4, PixelType::f32, px.data(), "unsupported image extension");
  expect_write_error(dir.path() / "id.png", 1, PixelType::u32, ids.data(), "cannot write 32-bit unsigned");
  expect_write_error(dir.path() / "id.exr", 1, PixelType::u32, ids.data(), "cannot write 32-bit unsigned");
  expect_write_error(dir.path() / "c.tif", 4, PixelType::u32, ids.data(), "cannot write 32-bit unsigned");
  expect_write_error(dir.path() / "c.exr", 4, PixelType::u8, ids.data(), "cannot write 8-bit");
  EXPECT_EQ(files_in(dir.path()), 0u);
}

TEST(ImageIo, ReadRgbaDecodesSrgbBytes) {
  TempDir dir;
  std::vector<uint8_t> grey = {0, 64, 128, 255};
  write_image_atomic(dir.path() / "g.png", 2, 2, 1, PixelType::u8, grey.data());
  const ImageRGBA img = read_image_rgba(dir.path() / "g.png");
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 2);
  for (int i = 0; i < 4; ++i) {
    const float* p = img.pixel(i % 2, i / 2);
    EXPECT_EQ(p[0], srgb8_to_linear(grey[i]));
    EXPECT_EQ(p[1], p[0]);
    EXPECT_EQ(p[2], p[0]);
    EXPECT_EQ(p[3], 1.0f);
  }
  const ImageRGBA lin = read_image_rgba(dir.path() / "g.png", ColorEncoding::linear);
  EXPECT_FLOAT_EQ(lin.pixel(1, 0)[0], 64.0f / 255.0f);
  // Float files are linear already, and read as stored.
  const auto rgba = ramp(3, 2, 4);
  ImageWriteOptions as_stored;
  as_stored.alpha = Alpha::premultiplied;
  write_image_atomic(dir.path() / "f.exr", 3, 2, 4, PixelType::f32, rgba.data(), as_stored);
  EXPECT_EQ(read_image_rgba(dir.path() / "f.exr").rgba, rgba);
}

TEST(ImageIo, ReadShippedColourMap) {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  const auto f = std::filesystem::path(root ? root : ".") / "tools/data/BoxTextured-glTF/CesiumLogoFlat.png";
  const ImageRGBA img = read_image_rgba(f);
  EXPECT_EQ(img.width, 211);
  EXPECT_EQ(img.height, 211);
}

TEST(ImageIo, ReadErrorsNameTheFile) {
  TempDir dir;
  const auto bad = dir.write("bad.png", "not a png at all");
  try {
    read_image_rgba(bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, bad.string());
  }
  try {
    read_image_rgba(dir.path() / "none.png");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.reason, "image file not found");
  }
}

}  // namespace
}  // namespace pelt::io
