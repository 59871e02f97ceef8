// EXR files read by OpenEXR's own library (tools/io/exr_reader.h) give what OpenImageIO's module gave
// pelt (oiio_backend.cpp, reached here through image_backend()): the same size, windows, channel
// names and order, alpha channel and floats, on every pixel type, on channel sets from Y to layered
// and extra channels, scanline, tiled, MIP- and RIP-mapped, each compression and line order, odd sizes,
// offset windows and multi-part files; files the module failed on, or whose channels pelt would draw
// as what they are not, are refused with a reason; a cut or corrupt file is refused naming it; an
// image over the budget is refused from its header. The files are made here with OpenEXR's writer.
#include "tools/io/exr_reader.h"

#include <ImfChannelList.h>
#include <ImfDeepFrameBuffer.h>
#include <ImfDeepScanLineOutputFile.h>
#include <ImfEnvmapAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfThreading.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/temp_dir.h"
#include "tools/io/budget.h"
#include "tools/io/image_backend.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace exr_reader_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Channel {
  std::string name;
  Imf::PixelType type = Imf::HALF;
  int sampling = 1;
};

enum class Layout { scanline, tiled, mipmap, ripmap };

struct Variant {
  std::string name;
  std::vector<Channel> channels;
  int width = 7, height = 5;
  Layout layout = Layout::scanline;
  Imf::Compression compression = Imf::ZIP_COMPRESSION;
  Imf::LineOrder order = Imf::INCREASING_Y;
  Imath::Box2i display = {}, data = {};  // empty: both width x height at 0, 0
  bool second_part = false;    // a second part of other channels and values after this one
  bool cube = false;           // an envmap attribute saying cube faces
};

// A value of channel `c` at texel `i` on level `level`, as stored. Floats and halves cover negative,
// tiny (a half's denormals), large and non-finite values; UINT the ends of its range.
uint32_t uint_value(int c, int i, int level) {
  if (i == 0) return 0;
  if (i == 1) return 0xFFFFFFFFu;
  if (i == 2) return 1;
  return uint32_t((c * 7919 + i + level * 104729) * 2654435761u);
}
float float_value(int c, int i, int level) {
  if (i == 3) return std::numeric_limits<float>::infinity();
  if (i == 4) return std::nanf("");
  if (i == 5) return 1e-7f;  // a half's denormal
  if (i == 6) return -65504.0f;
  return (float(c) + 1.0f) * 0.37f + float(i) * 0.0131f - 0.2f + float(level) * 10.0f;
}

// The channels' values for one level of `w` x `h` pixels, one plane each (4 bytes a value, 2 for
// HALF), and a frame buffer over them whose origin is (x0, y0).
struct Planes {
  std::vector<std::vector<char>> planes;
  Imf::FrameBuffer frame;
  Planes(const std::vector<Channel>& channels, int x0, int y0, int w, int h, int level, float offset = 0.0f) {
    for (size_t c = 0; c < channels.size(); ++c) {
      const Channel& ch = channels[c];
      const size_t size = ch.type == Imf::HALF ? 2 : 4;
      const int cw = w / ch.sampling, chh = h / ch.sampling;
      planes.emplace_back(size_t(cw) * size_t(chh) * size);
      char* p = planes.back().data();
      for (int i = 0; i < cw * chh; ++i) {
        if (ch.type == Imf::UINT) {
          const uint32_t v = uint_value(int(c), i, level);
          std::memcpy(p + 4 * size_t(i), &v, 4);
        } else if (ch.type == Imf::FLOAT) {
          const float v = float_value(int(c), i, level) + offset;
          std::memcpy(p + 4 * size_t(i), &v, 4);
        } else {
          const half v(float_value(int(c), i, level) + offset);
          std::memcpy(p + 2 * size_t(i), &v, 2);
        }
      }
      frame.insert(ch.name, Imf::Slice::Make(ch.type, p, Imath::V2i(x0, y0), w, h, size, size * size_t(cw),
                                             ch.sampling, ch.sampling));
    }
  }
};

Imf::Header header_of(const Variant& v) {
  const Imath::Box2i display = v.display.isEmpty() ? Imath::Box2i({0, 0}, {v.width - 1, v.height - 1}) : v.display;
  const Imath::Box2i data = v.data.isEmpty() ? display : v.data;
  Imf::Header h(display, data);
  h.compression() = v.compression;
  h.lineOrder() = v.order;
  for (const Channel& c : v.channels) h.channels().insert(c.name, Imf::Channel(c.type, c.sampling, c.sampling));
  if (v.layout != Layout::scanline) {
    const Imf::LevelMode mode = v.layout == Layout::tiled    ? Imf::ONE_LEVEL
                                : v.layout == Layout::mipmap ? Imf::MIPMAP_LEVELS
                                                             : Imf::RIPMAP_LEVELS;
    h.setTileDescription(Imf::TileDescription(4, 3, mode, Imf::ROUND_UP));
  }
  if (v.cube) h.insert("envmap", Imf::EnvmapAttribute(Imf::ENVMAP_CUBE));
  return h;
}

void write_variant(const std::string& file, const Variant& v) {
  Imf::Header h = header_of(v);
  const Imath::Box2i data = h.dataWindow();
  const int w = data.max.x - data.min.x + 1, ht = data.max.y - data.min.y + 1;
  if (v.second_part) {
    std::vector<Imf::Header> headers = {h, h};
    headers[0].setName("first");
    headers[0].setType(Imf::SCANLINEIMAGE);
    headers[1].setName("second");
    headers[1].setType(Imf::SCANLINEIMAGE);
    headers[1].channels() = Imf::ChannelList();
    headers[1].channels().insert("R", Imf::Channel(Imf::FLOAT));
    headers[1].channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::MultiPartOutputFile out(file.c_str(), headers.data(), 2);
    for (int part = 0; part < 2; ++part) {
      Imf::OutputPart p(out, part);
      const std::vector<Channel> channels =
          part == 0 ? v.channels : std::vector<Channel>{{"R", Imf::FLOAT}, {"Y", Imf::FLOAT}};
      Planes planes(channels, data.min.x, data.min.y, w, ht, 0, part * 5.0f);
      p.setFrameBuffer(planes.frame);
      p.writePixels(ht);
    }
    return;
  }
  if (v.layout == Layout::scanline) {
    Imf::OutputFile out(file.c_str(), h);
    Planes planes(v.channels, data.min.x, data.min.y, w, ht, 0);
    out.setFrameBuffer(planes.frame);
    out.writePixels(ht);
    return;
  }
  Imf::TiledOutputFile out(file.c_str(), h);
  for (int ly = 0; ly < out.numYLevels(); ++ly)
    for (int lx = 0; lx < out.numXLevels(); ++lx) {
      if (v.layout == Layout::mipmap && lx != ly) continue;
      const Imath::Box2i level = out.dataWindowForLevel(lx, ly);
      Planes planes(v.channels, level.min.x, level.min.y, level.max.x - level.min.x + 1,
                    level.max.y - level.min.y + 1, lx + 3 * ly);
      out.setFrameBuffer(planes.frame);
      out.writeTiles(0, out.numXTiles(lx) - 1, 0, out.numYTiles(ly) - 1, lx, ly);
    }
}

// The same floats: every bit, but any NaN for a NaN (image_io refuses or zeroes each one, so its
// payload never reaches pelt, and OpenImageIO's conversion of a half NaN need not keep it).
bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) && std::isnan(b[i])) continue;
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0) return false;
  }
  return true;
}

// What read_image_rgba reads of a file: its header, and its first channels (at most 4) as floats.
struct Read {
  ImageFileInfo info;
  std::vector<float> values;
  std::string error;  // the open's or read's reason; "" when both succeeded
};

Read read_with(std::unique_ptr<ImageReader> in, const std::string& open_error) {
  Read r;
  if (!in) {
    r.error = "open: " + open_error;
    return r;
  }
  r.info = in->info();
  const int channels = std::min(r.info.channels, 4);
  r.values.resize(size_t(r.info.width) * size_t(r.info.height) * size_t(channels));
  if (const std::string e = in->read(channels, StoredType::f32, r.values.data()); !e.empty()) r.error = "read: " + e;
  return r;
}
Read read_by_module(const std::string& file) {
  std::string error;
  auto in = image_backend().open(file, error);
  return read_with(std::move(in), error);
}
Read read_by_pelt(const std::string& file) {
  std::string error;
  auto in = open_exr(file, error);
  return read_with(std::move(in), error);
}

// read_image_rgba's reason for refusing `file`, checking that it names the file; a failure where
// it reads it.
std::string refusal(const std::string& file, const Budget& budget = Budget{}) {
  try {
    (void)read_image_rgba(file, ColorEncoding::srgb, budget);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, file);
    return e.reason;
  }
  ADD_FAILURE() << file << " was read";
  return {};
}

void expect_same(const Read& ours, const Read& theirs, const std::string& name) {
  ASSERT_EQ(theirs.error, "") << name << ": the module did not read it";
  ASSERT_EQ(ours.error, "") << name;
  EXPECT_EQ(ours.info.width, theirs.info.width) << name;
  EXPECT_EQ(ours.info.height, theirs.info.height) << name;
  EXPECT_EQ(ours.info.channels, theirs.info.channels) << name;
  EXPECT_EQ(ours.info.depth, theirs.info.depth) << name;
  EXPECT_EQ(ours.info.x, theirs.info.x) << name;
  EXPECT_EQ(ours.info.y, theirs.info.y) << name;
  EXPECT_EQ(ours.info.full_x, theirs.info.full_x) << name;
  EXPECT_EQ(ours.info.full_y, theirs.info.full_y) << name;
  EXPECT_EQ(ours.info.full_width, theirs.info.full_width) << name;
  EXPECT_EQ(ours.info.full_height, theirs.info.full_height) << name;
  EXPECT_EQ(ours.info.channel_names, theirs.info.channel_names) << name;
  EXPECT_EQ(ours.info.alpha_channel, theirs.info.alpha_channel) << name;
  EXPECT_EQ(ours.info.type, theirs.info.type) << name;
  EXPECT_EQ(ours.info.declared_linear, theirs.info.declared_linear) << name;
  EXPECT_TRUE(same_floats(ours.values, theirs.values)) << name;
}

std::vector<Variant> variants() {
  using Imf::FLOAT, Imf::HALF, Imf::UINT;
  std::vector<Variant> out;
  for (const Imf::PixelType t : {HALF, FLOAT, UINT}) {
    const std::string type = t == HALF ? "half" : t == FLOAT ? "float" : "uint";
    out.push_back({type + " Y", {{"Y", t}}});
    out.push_back({type + " YA", {{"Y", t}, {"A", t}}});
    out.push_back({type + " RGB", {{"R", t}, {"G", t}, {"B", t}}});
    out.push_back({type + " RGBA", {{"R", t}, {"G", t}, {"B", t}, {"A", t}}});
  }
  out.push_back({"mixed types", {{"R", HALF}, {"G", FLOAT}, {"B", UINT}, {"A", HALF}}});
  out.push_back({"half and uint", {{"R", HALF}, {"G", UINT}, {"B", HALF}}});
  out.push_back({"extra channels", {{"R", HALF}, {"G", HALF}, {"B", HALF}, {"A", HALF}, {"Z", FLOAT}, {"id", UINT}}});
  out.push_back({"long names, any case", {{"red", HALF}, {"Green", HALF}, {"blue", HALF}, {"alpha", HALF}}});
  out.push_back({"lower case", {{"r", FLOAT}, {"g", FLOAT}, {"b", FLOAT}, {"a", FLOAT}}});
  out.push_back({"one layer", {{"diffuse.R", HALF}, {"diffuse.G", HALF}, {"diffuse.B", HALF}}});
  out.push_back({"nested layer", {{"a.b.R", HALF}, {"a.b.G", HALF}, {"a.b.B", HALF}, {"a.b.A", HALF}}});
  out.push_back({"root and layers",
                 {{"R", HALF}, {"G", HALF}, {"B", HALF}, {"A", HALF}, {"diffuse.R", HALF}, {"spec.G", FLOAT}}});
  out.push_back({"a normal's X, Y, Z", {{"X", FLOAT}, {"Y", FLOAT}, {"Z", FLOAT}}});
  out.push_back({"N.X, N.Y, N.Z", {{"N.Z", HALF}, {"N.Y", HALF}, {"N.X", HALF}}});
  out.push_back({"Y and Z", {{"Z", FLOAT}, {"Y", HALF}}});  // alpha none: image_io refuses two such
  out.push_back({"one A", {{"A", HALF}}});
  out.push_back({"one Z", {{"Z", FLOAT}}});
  out.push_back({"odd names", {{"foo", HALF}, {"bar", FLOAT}, {"baz", UINT}}});
  out.push_back({"R, G, B, Z (no alpha)", {{"R", HALF}, {"G", HALF}, {"B", HALF}, {"Z", FLOAT}}});
  const std::vector<Channel> rgba = {{"R", HALF}, {"G", HALF}, {"B", HALF}, {"A", HALF}};
  const std::vector<Channel> rgb_f = {{"R", FLOAT}, {"G", FLOAT}, {"B", FLOAT}};
  for (const auto& [c, name] : std::vector<std::pair<Imf::Compression, std::string>>{
           {Imf::NO_COMPRESSION, "none"},
           {Imf::RLE_COMPRESSION, "RLE"},
           {Imf::ZIPS_COMPRESSION, "ZIPS"},
           {Imf::PIZ_COMPRESSION, "PIZ"},
           {Imf::PXR24_COMPRESSION, "PXR24"},
           {Imf::B44_COMPRESSION, "B44"},
           {Imf::B44A_COMPRESSION, "B44A"},
           {Imf::DWAA_COMPRESSION, "DWAA"},
           {Imf::DWAB_COMPRESSION, "DWAB"}}) {
    Variant v{name + " RGBA 37 x 29", rgba, 37, 29};
    v.compression = c;
    out.push_back(v);
    Variant f{name + " float RGB 37 x 29, decreasing y", rgb_f, 37, 29};
    f.compression = c;
    f.order = Imf::DECREASING_Y;
    out.push_back(f);
    Variant t{name + " tiled RGBA 13 x 11", rgba, 13, 11, Layout::tiled};
    t.compression = c;
    out.push_back(t);
  }
  out.push_back({"tiled 1 x 1", {{"Y", FLOAT}}, 1, 1, Layout::tiled});
  out.push_back({"tiled, random y", rgba, 9, 7, Layout::tiled, Imf::ZIP_COMPRESSION, Imf::RANDOM_Y});
  out.push_back({"MIP-mapped", rgba, 13, 9, Layout::mipmap});
  out.push_back({"MIP-mapped uint", {{"Y", UINT}}, 13, 9, Layout::mipmap});
  out.push_back({"RIP-mapped", rgb_f, 13, 9, Layout::ripmap});
  out.push_back({"scanline 1 x 1", rgba, 1, 1});
  out.push_back({"scanline 1 x 40", {{"Y", HALF}}, 1, 40});
  Variant cube{"MIP-mapped square cube map", rgb_f, 8, 8, Layout::mipmap};
  cube.cube = true;
  out.push_back(cube);
  Variant flat_cube{"cube map of one level", rgb_f, 8, 48, Layout::tiled};
  flat_cube.cube = true;
  out.push_back(flat_cube);
  Variant offset{"windows at 10, -3", rgba, 7, 5};
  offset.display = offset.data = Imath::Box2i({10, -3}, {16, 1});
  out.push_back(offset);
  Variant tiled_offset{"tiled windows at -5, 7", rgba, 9, 8, Layout::tiled};
  tiled_offset.display = tiled_offset.data = Imath::Box2i({-5, 7}, {3, 14});
  out.push_back(tiled_offset);
  Variant crop{"data window inside the display window", rgba};
  crop.display = Imath::Box2i({0, 0}, {9, 9});
  crop.data = Imath::Box2i({2, 3}, {8, 7});
  out.push_back(crop);
  Variant overscan{"data window around the display window", rgb_f};
  overscan.display = Imath::Box2i({0, 0}, {4, 2});
  overscan.data = Imath::Box2i({-1, -1}, {5, 3});
  out.push_back(overscan);
  Variant multi{"two parts", rgba};
  multi.second_part = true;
  out.push_back(multi);
  Variant multi_y{"two parts, the first Y", {{"Y", FLOAT}}};
  multi_y.second_part = true;
  out.push_back(multi_y);
  return out;
}

TEST(ExrReader, ReadsWhatOpenImageIoReadOnEveryKindOfExr) {
  TempDir dir;
  int n = 0;
  for (const Variant& v : variants()) {
    const std::string file = (dir.path() / (std::to_string(n++) + ".exr")).string();
    write_variant(file, v);
    ASSERT_EQ(encoded_kind(std::filesystem::path(file)), EncodedKind::exr) << v.name;
    EXPECT_FALSE(needs_image_module_to_read(file)) << v.name;
    expect_same(read_by_pelt(file), read_by_module(file), v.name);
  }
}

// The same floats on OpenEXR's pool of any size, none included (decoding on the calling thread).
TEST(ExrReader, ReadsTheSameOnAnyThreadCount) {
  TempDir dir;
  const std::string file = (dir.path() / "big.exr").string();
  Variant v{"PIZ", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::FLOAT}, {"A", Imf::UINT}}, 301, 257};
  v.compression = Imf::PIZ_COMPRESSION;
  write_variant(file, v);
  const Read first = read_by_pelt(file);
  ASSERT_EQ(first.error, "");
  for (const int threads : {0, 1, 3, 8}) {
    Imf::setGlobalThreadCount(threads);
    const Read again = read_by_pelt(file);
    EXPECT_EQ(again.error, "") << threads;
    EXPECT_TRUE(same_floats(again.values, first.values)) << threads;
  }
  Imf::setGlobalThreadCount(int(std::thread::hardware_concurrency()));
}

// The module's open failed on subsampled channels, and its read on a deep file (after giving its
// header): both are refused at the open, with a reason.
TEST(ExrReader, RefusesWhatOpenImageIoCouldNotRead) {
  TempDir dir;
  const std::string sub = (dir.path() / "sub.exr").string();
  write_variant(sub, {"", {{"Y", Imf::HALF}, {"RY", Imf::HALF, 2}, {"BY", Imf::HALF, 2}}, 8, 6});
  EXPECT_NE(read_by_module(sub).error.find("open: Subsampled channels are not supported"), std::string::npos);
  EXPECT_NE(read_by_pelt(sub).error.find("open: subsampled channels are not supported (channel \"BY\" has sampling 2, 2)"),
            std::string::npos)
      << read_by_pelt(sub).error;

  const std::string deep = (dir.path() / "deep.exr").string();
  {
    Imf::Header h(4, 3);
    h.setType(Imf::DEEPSCANLINE);
    h.compression() = Imf::ZIPS_COMPRESSION;
    h.channels().insert("R", Imf::Channel(Imf::HALF));
    h.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    Imf::DeepScanLineOutputFile out(deep.c_str(), h);
    std::vector<unsigned> counts(12, 1);
    std::vector<half> r(12, half(0.5f));
    std::vector<float> z(12, 1.0f);
    std::vector<half*> rp(12);
    std::vector<float*> zp(12);
    for (size_t i = 0; i < 12; ++i) rp[i] = &r[i], zp[i] = &z[i];
    Imf::DeepFrameBuffer frame;
    frame.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()), 4, 16));
    frame.insert("R", Imf::DeepSlice(Imf::HALF, reinterpret_cast<char*>(rp.data()), sizeof(half*), sizeof(half*) * 4,
                                     sizeof(half)));
    frame.insert("Z", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(zp.data()), sizeof(float*),
                                     sizeof(float*) * 4, sizeof(float)));
    out.setFrameBuffer(frame);
    out.writePixels(3);
  }
  EXPECT_EQ(read_by_module(deep).error.rfind("read: ", 0), 0u) << read_by_module(deep).error;
  EXPECT_NE(read_by_pelt(deep).error.find("open: a deep EXR"), std::string::npos) << read_by_pelt(deep).error;
  try {
    (void)read_image_header(deep);
    ADD_FAILURE() << "the deep file's header was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, deep);
    EXPECT_NE(e.reason.find("deep EXR"), std::string::npos) << e.reason;
  }
}

// Where the module gave channels that pelt would draw as what they are not, the file is refused:
// each case first checks what the module gave.
TEST(ExrReader, RefusesChannelsThatWouldBeDrawnAsWhatTheyAreNot) {
  TempDir dir;
  struct Case {
    Variant v;
    std::string module_names;  // what the module gave
    int module_alpha;
    std::string reason;  // a part of pelt's
  };
  const std::vector<Case> cases = {
      {{"luminance-chroma", {{"Y", Imf::HALF}, {"RY", Imf::HALF}, {"BY", Imf::HALF}}, 8, 6},
       "Y, BY, RY", -1, "are luminance and chroma"},
      {{"R, G, A", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"A", Imf::HALF}}}, "R, G, A", 2, "put its alpha A among"},
      {{"Y, A, Z", {{"Y", Imf::FLOAT}, {"A", Imf::FLOAT}, {"Z", Imf::FLOAT}}}, "Y, A, Z", 1, "put its alpha A among"},
      {{"B, Z, alpha, red", {{"B", Imf::HALF}, {"Z", Imf::FLOAT}, {"alpha", Imf::HALF}, {"red", Imf::HALF}}},
       "red, B, alpha, Z", 2, "put its alpha alpha among"},
      {{"two layers", {{"a.R", Imf::HALF}, {"b.G", Imf::HALF}, {"R", Imf::HALF}}}, "R, a.R, b.G", -1,
       "come from different layers (R, a.R, b.G)"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::string file = (dir.path() / (std::to_string(n++) + ".exr")).string();
    write_variant(file, c.v);
    const Read theirs = read_by_module(file);
    EXPECT_EQ(theirs.error, "") << c.v.name;
    EXPECT_EQ(theirs.info.channel_names, c.module_names) << c.v.name;
    EXPECT_EQ(theirs.info.alpha_channel, c.module_alpha) << c.v.name;
    const std::string reason = refusal(file);
    EXPECT_NE(reason.find(c.reason), std::string::npos) << c.v.name << ": " << reason;
  }
  // A MIP-mapped cube map's frame was one face, so the module's view of a stack of faces met the
  // data-window refusal, whose advice does not fit it.
  Variant cube{"MIP-mapped cube map", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}, 8, 48, Layout::mipmap};
  cube.cube = true;
  const std::string file = (dir.path() / "cube.exr").string();
  write_variant(file, cube);
  const Read theirs = read_by_module(file);
  EXPECT_EQ(theirs.info.height, 48);
  EXPECT_EQ(theirs.info.full_height, 8);
  EXPECT_NE(read_by_pelt(file).error.find("a cube-face environment map with MIP levels"), std::string::npos);
}

// The data-window refusal is image_io's, on the windows the reader reports (the same as the module's,
// above): through read_image_rgba and read_image_header alike, with its text.
TEST(ExrReader, ADataWindowThatIsNotTheDisplayWindowIsRefused) {
  TempDir dir;
  Variant crop{"crop", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}};
  crop.display = Imath::Box2i({0, 0}, {9, 9});
  crop.data = Imath::Box2i({2, 3}, {8, 7});
  const std::string file = (dir.path() / "crop.exr").string();
  write_variant(file, crop);
  const std::string reason =
      "its pixels (7 x 5 at 2, 3) are not its frame (10 x 10 at 0, 0): pelt reads whole frames; e.g. `oiiotool IN "
      "--croptofull -o OUT` makes one";
  EXPECT_EQ(refusal(file), reason);
  try {
    (void)read_image_header(file);
    ADD_FAILURE() << "the header was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.reason, reason);
  }
  const std::string rg = (dir.path() / "rg.exr").string();
  write_variant(rg, {"rg", {{"R", Imf::HALF}, {"G", Imf::HALF}}});
  EXPECT_NE(refusal(rg).find("its 2 channels (R, G) are not grey and alpha"), std::string::npos) << refusal(rg);
}

// Through read_image_rgba: an EXR's values as floats (grey replicated, alpha 1 where none), its
// header's size, channels and 4 bytes a channel, and a non-finite value refused in a used channel
// and zeroed in another, as for any map.
TEST(ExrReader, ReadImageRgbaTakesTheFloatsAndChecksThem) {
  TempDir dir;
  const std::string file = (dir.path() / "y.exr").string();
  write_variant(file, {"", {{"Y", Imf::FLOAT}, {"A", Imf::HALF}}, 3, 3});
  const ImageHeader h = read_image_header(file);
  EXPECT_EQ(h.width, 3);
  EXPECT_EQ(h.height, 3);
  EXPECT_EQ(h.channels, 2);
  EXPECT_EQ(h.bytes_per_channel, 4);
  // Texel 3 holds infinity, 4 NaN (float_value).
  EXPECT_EQ(refusal(file), "texel (0, 1) channel r is infinite");
  const std::string ok = (dir.path() / "ok.exr").string();
  write_variant(ok, {"", {{"Y", Imf::FLOAT}}, 3, 1});
  const ImageRGBA img = read_image_rgba(ok, ColorEncoding::srgb, Budget{}, 1);
  ASSERT_EQ(img.rgba.size(), 12u);
  for (int x = 0; x < 3; ++x) {
    EXPECT_EQ(img.pixel(x, 0)[0], float_value(0, x, 0));
    EXPECT_EQ(img.pixel(x, 0)[2], float_value(0, x, 0));
    EXPECT_EQ(img.pixel(x, 0)[3], 1.0f);
  }
}

std::string contents(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A cut file is refused, at any length, naming it; so is a corrupt one wherever OpenEXR notices
// (a flipped byte in uncompressed pixels is only another value): never a crash or a hang.
TEST(ExrReader, ACutOrCorruptFileIsRefusedNamingIt) {
  TempDir dir;
  int n = 0;
  for (const Variant& v :
       {Variant{"ZIP scanline", {{"R", Imf::HALF}, {"G", Imf::FLOAT}, {"B", Imf::UINT}}, 19, 37},
        Variant{"PIZ tiled", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}, 13, 11, Layout::tiled,
                Imf::PIZ_COMPRESSION},
        Variant{"DWAB MIP-mapped", {{"Y", Imf::HALF}}, 40, 33, Layout::mipmap, Imf::DWAB_COMPRESSION},
        Variant{"uncompressed two parts", {{"Y", Imf::HALF}}, 9, 9, Layout::scanline, Imf::NO_COMPRESSION,
                Imf::INCREASING_Y, {}, {}, true}}) {
    const std::string good = (dir.path() / ("good" + std::to_string(n) + ".exr")).string();
    write_variant(good, v);
    const std::string all = contents(good);
    const ImageRGBA whole = read_image_rgba(good, ColorEncoding::linear, Budget{}, 0);
    // A cut file is read only where what it lost is never read (another part, a smaller level), and
    // then as the whole file; `cut`: bytes is a cut file.
    const auto refused = [&](const std::string& bytes, bool cut) {
      const std::string path = (dir.path() / ("bad" + std::to_string(n++) + ".exr")).string();
      std::ofstream(path, std::ios::binary) << bytes;
      try {
        const ImageRGBA img = read_image_rgba(path, ColorEncoding::linear, Budget{}, 0);
        if (cut && v.layout != Layout::mipmap && !v.second_part)
          ADD_FAILURE() << v.name << ": " << bytes.size() << " of " << all.size() << " bytes were read";
        if (cut) {
          EXPECT_EQ(img.rgba, whole.rgba) << v.name << ": " << bytes.size() << " of " << all.size() << " bytes";
        }
      } catch (const InputError& e) {
        EXPECT_EQ(e.file, path) << v.name;
        EXPECT_FALSE(e.reason.empty()) << v.name;
      }
    };
    for (size_t cut = 4; cut < all.size(); cut += std::max<size_t>(1, all.size() / 97)) refused(all.substr(0, cut), true);
    refused(all.substr(0, all.size() - 1), true);
    uint32_t seed = 12345;
    for (int k = 0; k < 200; ++k) {
      std::string bytes = all;
      for (int flips = 0; flips < 1 + k % 3; ++flips) {
        seed = seed * 1664525u + 1013904223u;
        const size_t at = 4 + (seed >> 8) % (bytes.size() - 4);  // past the magic number
        bytes[at] = char(bytes[at] ^ (1 + (seed & 0x7F)));
      }
      refused(bytes, false);
    }
  }
  // An attribute's size past the end of the file is refused before OpenEXR reads it: OpenEXR (and
  // OpenImageIO's reader with it) allocated all of it, and took seconds to fail.
  const std::string two = (dir.path() / "two.exr").string();
  write_variant(two, {"", {{"Y", Imf::HALF}}, 9, 9, Layout::scanline, Imf::NO_COMPRESSION, Imf::INCREASING_Y, {}, {},
                      true});
  std::string bytes = contents(two);
  const std::string key("name\0string\0", 12);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const int32_t size = 0x7FFFFFF0;
  std::memcpy(&bytes[at + key.size()], &size, 4);
  std::ofstream(two, std::ios::binary | std::ios::trunc) << bytes;
  const std::string reason = refusal(two);
  EXPECT_NE(reason.find("attribute `name` (string) says it holds 2147483632 bytes, and " +
                        std::to_string(bytes.size() - at - key.size() - 4) + " follow it in the file"),
            std::string::npos)
      << reason;
}

// The header's size is checked against the budget before anything as large as the image is made:
// a header that says 1,000,000,000 x 1 (a file of a few hundred bytes, its one chunk a 1-wide row)
// is refused for its size, not met by a failed allocation or OpenEXR's complaint about the row.
TEST(ExrReader, AnImageOverTheBudgetIsRefusedFromItsHeader) {
  TempDir dir;
  const std::string small = (dir.path() / "small.exr").string();
  write_variant(small, {"", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}, 40, 30});
  Budget budget;
  budget.max_texture_side = 32;
  EXPECT_EQ(refusal(small, budget), texture_side_refusal(40, 30, 32));
  const std::string wide = (dir.path() / "wide.exr").string();
  write_variant(wide, {"", {{"R", Imf::HALF}, {"G", Imf::HALF}, {"B", Imf::HALF}}, 1, 1});
  std::string bytes = contents(wide);
  for (const std::string attribute : {"dataWindow", "displayWindow"}) {
    const std::string key = attribute + std::string("\0box2i\0", 7);
    const size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos) << attribute;
    const int32_t box[4] = {0, 0, 999999999, 0};  // little-endian, as OpenEXR stores it
    std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);
  }
  std::ofstream(wide, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_EQ(refusal(wide), texture_side_refusal(1000000000, 1, Budget{}.max_texture_side));
  const ImageHeader h = read_image_header(wide);
  EXPECT_EQ(h.width, 1000000000);
  EXPECT_EQ(h.height, 1);
}

}  // namespace exr_reader_test
}  // namespace pelt::io
