// Test helper for pelt's own image readers (png_reader.h, jpeg_reader.h): a file as OpenImageIO's
// module read it for pelt (oiio_backend.cpp), and the check that a reader gives the same.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "tools/io/image_backend.h"

namespace pelt::io {

// OpenImageIO's view of a file; `read` is false where its open or read failed or left an error,
// which pelt took as the read's failure.
struct OiioView {
  bool read = false;
  int width = 0, height = 0, channels = 0, alpha = -1;
  std::string names;  // "R, G, B"
  StoredType type = StoredType::f32;
  bool linear = false;
  int orientation = 0;  // Exif's, 0 where none
  std::vector<uint8_t> bytes;
};

inline OiioView oiio_view(const std::string& file) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(file, &config);
  OiioView v;
  if (!in) {
    (void)OIIO::geterror();
    return v;
  }
  const OIIO::ImageSpec& spec = in->spec();
  v.width = spec.width, v.height = spec.height;
  v.channels = spec.nchannels;
  v.alpha = spec.alpha_channel;
  for (const std::string& name : spec.channelnames) v.names += (v.names.empty() ? "" : ", ") + name;
  v.type = spec.format == OIIO::TypeDesc::UINT8    ? StoredType::u8
           : spec.format == OIIO::TypeDesc::UINT16 ? StoredType::u16
                                                   : StoredType::f32;
  v.linear = std::string(in->format_name()) == "png" && spec.get_string_attribute("oiio:ColorSpace") == "linear";
  v.orientation = spec.get_int_attribute("Orientation", 0);
  v.bytes.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels) * spec.format.size());
  // Native samples: the bytes asked for as spec.format give, without the 64 MB buffer OpenImageIO
  // allocates for a read that could convert (about 60 ms a file under ASan).
  v.read = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UNKNOWN, v.bytes.data()) && !in->has_error();
  (void)in->geterror();
  return v;
}

// Expects `ours`, pelt's reader of `file`, to give what OpenImageIO gave: its size, channels,
// their names and type, alpha channel, linear declaration and every byte.
inline void expect_read_as_by_oiio(ImageReader& ours, const std::string& file, const std::string& name) {
  const OiioView theirs = oiio_view(file);
  ASSERT_TRUE(theirs.read) << name << ": OpenImageIO did not read it";
  const ImageFileInfo& info = ours.info();
  EXPECT_EQ(info.width, theirs.width) << name;
  EXPECT_EQ(info.height, theirs.height) << name;
  EXPECT_EQ(info.full_width, theirs.width) << name;
  EXPECT_EQ(info.full_height, theirs.height) << name;
  EXPECT_EQ(info.channels, theirs.channels) << name;
  EXPECT_EQ(info.channel_names, theirs.names) << name;
  EXPECT_EQ(info.type, theirs.type) << name;
  EXPECT_EQ(info.alpha_channel, theirs.alpha) << name;
  EXPECT_EQ(info.declared_linear, theirs.linear) << name;
  if (info.channels != theirs.channels || info.type != theirs.type) return;
  std::vector<uint8_t> bytes(theirs.bytes.size());
  ASSERT_EQ(ours.read(info.channels, info.type, bytes.data()), "") << name;
  EXPECT_EQ(bytes, theirs.bytes) << name;
}

}  // namespace pelt::io
