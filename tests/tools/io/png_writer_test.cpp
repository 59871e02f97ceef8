// PNG files written by libpng itself (tools/io/png_writer.h), without OpenImageIO's module: every
// channel count reads back through OpenImageIO with the bytes written and as sRGB, and a write
// that the disk refuses is reported, not taken for a file.
#include "tools/io/png_writer.h"

#include <cstdint>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "tests/tools/io/temp_dir.h"

namespace pelt::io {
namespace {

TEST(PngWriter, EveryChannelCountReadsBackAsWrittenAndAsSrgb) {
  TempDir dir;
  constexpr int kW = 9, kH = 7;
  for (int channels = 1; channels <= 4; ++channels) {
    std::vector<uint8_t> px(size_t(kW) * kH * size_t(channels));
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 53 + 7) % 256);
    std::string name = std::to_string(channels);  // appended: `"c" + string` trips GCC 12's -Wstringop-overflow
    name += ".png";
    const std::string file = (dir.path() / name).string();
    ASSERT_EQ(write_png8(file, kW, kH, channels, px.data(), 1), "");
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // as stored: no colour multiplied by alpha
    auto in = OIIO::ImageInput::open(file, &config);
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, kW);
    EXPECT_EQ(spec.height, kH);
    ASSERT_EQ(spec.nchannels, channels);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(spec.alpha_channel, channels == 2 || channels == 4 ? channels - 1 : -1);
    EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB") << channels;
    std::vector<uint8_t> back(px.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, back.data()));
    EXPECT_EQ(back, px) << channels << " channel(s)";
  }
}

// /dev/full takes the file but no byte of it: the write fails, with the system's reason.
TEST(PngWriter, ADiskThatRefusesTheBytesIsAnError) {
  std::vector<uint8_t> px(size_t(64) * 64 * 4, 200);
  const std::string error = write_png8("/dev/full", 64, 64, 4, px.data(), 0);
  EXPECT_NE(error.find("No space left on device"), std::string::npos) << error;  // not libpng's "Write Error"
  EXPECT_EQ(write_png8("/nonexistent-folder/a.png", 2, 2, 4, px.data(), 1).find("cannot create the image file"), 0u);
  EXPECT_NE(write_png8((TempDir().path() / "a.png").string(), 2, 2, 5, px.data(), 1), "");  // no such PNG
}

}  // namespace
}  // namespace pelt::io
