// JPEG files read by libjpeg itself (tools/io/jpeg_reader.h) give what OpenImageIO's JPEG reader
// gave pelt: the same size, channels, channel names, sample type, alpha channel and linear
// declaration, and the same samples to the bit, on every colour space libjpeg writes (grey,
// YCbCr, RGB, CMYK, YCCK, with and without their JFIF and Adobe markers, and other component
// counts), every chroma subsampling, baseline, optimised, progressive and arithmetic coding,
// restart markers, two qualities and sizes that leave partial MCUs; and a file OpenImageIO's
// read left an error on (cut, corrupt, a header libjpeg doubts, 12-bit) is refused, and so is one
// of more scans than the limit, which it read. The files are made here with libjpeg, so each
// variant is exactly the one named.
#include "tools/io/jpeg_reader.h"

#include <algorithm>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <jpeglib.h>

#include <gtest/gtest.h>

#include "tests/tools/io/oiio_view.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace jpeg_reader_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

enum class Coding { baseline, optimized, progressive, arithmetic, arithmetic_progressive, restart_mcus, restart_rows };

struct Variant {
  const char* colour;               // what the rows hold and how they are stored, for the name
  J_COLOR_SPACE in = JCS_RGB;       // the rows handed to libjpeg
  int components = 3;               // their samples a pixel
  J_COLOR_SPACE stored = JCS_YCbCr;
  int jfif = -1, adobe = -1;        // the markers: -1 as libjpeg writes them for `stored`, 0 none, 1 one
  int h = 1, v = 1;                 // the first component's sampling factors; the others' are 1
  Coding coding = Coding::baseline;
  int quality = 75;
  int width = 17, height = 13;
  int jfif_major = 1;               // another is a header libjpeg warns about
  bool exif_rotated = false;        // an Exif block saying the image is turned 90 degrees
  bool icc = false;                 // an ICC profile (APP2)
  std::vector<jpeg_scan_info> script = {};  // libjpeg's scan script, none for its own
  std::string name() const {
    static constexpr const char* kCoding[] = {"baseline", "optimized", "progressive", "arithmetic",
                                              "arithmetic progressive", "restart every MCU", "restart every row"};
    return std::string(colour) + ", " + std::to_string(h) + "x" + std::to_string(v) + ", " +
           kCoding[int(coding)] + ", quality " + std::to_string(quality) + ", " + std::to_string(width) + "x" +
           std::to_string(height) + (exif_rotated ? ", Exif orientation 6" : "") + (icc ? ", ICC" : "") +
           (script.empty() ? "" : ", " + std::to_string(script.size()) + " scans");
  }
};

// Samples that vary smoothly and with noise over the whole range, in every channel.
std::vector<uint8_t> samples(const Variant& v) {
  std::vector<uint8_t> out(size_t(v.width) * size_t(v.height) * size_t(v.components));
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
      for (int c = 0; c < v.components; ++c) {
        const uint32_t noise = (uint32_t((y * v.width + x) * v.components + c) * 2654435761u) >> 26;  // 0..63
        out[(size_t(y) * size_t(v.width) + size_t(x)) * size_t(v.components) + size_t(c)] =
            uint8_t(x * 255 / v.width * (c % 2 ? 1 : -1) + y * 199 / v.height + c * 71 + int(noise));
      }
  return out;
}

struct WriteFailure {
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

[[noreturn]] void write_failed(j_common_ptr jpeg) {
  auto* f = static_cast<WriteFailure*>(jpeg->client_data);
  (*jpeg->err->format_message)(jpeg, f->message);
  std::longjmp(f->jump, 1);
}

// The variant as a file, written by libjpeg.
void write_variant(const std::string& file, const Variant& v) {
  const std::vector<uint8_t> pixels = samples(v);
  // An Exif block: a little-endian TIFF header and one IFD entry, Orientation (0x0112) = 6.
  static constexpr uint8_t kExif[] = {'E', 'x', 'i', 'f', 0, 0, 'I', 'I', 42, 0, 8, 0, 0, 0, 1, 0,
                                      0x12, 1, 3, 0, 1, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0};
  std::vector<uint8_t> icc(132, 0);  // a profile header's size field and nothing of use
  icc[3] = 132;
  std::FILE* out = std::fopen(file.c_str(), "wb");
  ASSERT_NE(out, nullptr);
  jpeg_compress_struct jpeg{};
  jpeg_error_mgr manager{};
  WriteFailure failure;
  jpeg.err = jpeg_std_error(&manager);
  manager.error_exit = write_failed;
  jpeg.client_data = &failure;
  if (setjmp(failure.jump)) {
    ADD_FAILURE() << "libjpeg failed writing " << v.name() << ": " << failure.message;
    jpeg_destroy_compress(&jpeg);
    std::fclose(out);
    return;
  }
  jpeg_create_compress(&jpeg);
  jpeg_stdio_dest(&jpeg, out);
  jpeg.image_width = JDIMENSION(v.width);
  jpeg.image_height = JDIMENSION(v.height);
  jpeg.input_components = v.components;
  jpeg.in_color_space = v.in;
  jpeg_set_defaults(&jpeg);
  jpeg_set_colorspace(&jpeg, v.stored);
  if (v.jfif >= 0) jpeg.write_JFIF_header = boolean(v.jfif);
  if (v.adobe >= 0) jpeg.write_Adobe_marker = boolean(v.adobe);
  jpeg.JFIF_major_version = UINT8(v.jfif_major);
  jpeg.comp_info[0].h_samp_factor = v.h;
  jpeg.comp_info[0].v_samp_factor = v.v;
  jpeg_set_quality(&jpeg, v.quality, TRUE);
  switch (v.coding) {
    case Coding::baseline: break;
    case Coding::optimized: jpeg.optimize_coding = TRUE; break;
    case Coding::progressive: jpeg_simple_progression(&jpeg); break;
    case Coding::arithmetic: jpeg.arith_code = TRUE; break;
    case Coding::arithmetic_progressive:
      jpeg.arith_code = TRUE;
      jpeg_simple_progression(&jpeg);
      break;
    case Coding::restart_mcus: jpeg.restart_interval = 1; break;
    case Coding::restart_rows: jpeg.restart_in_rows = 1; break;
  }
  if (!v.script.empty()) {
    jpeg.scan_info = v.script.data();
    jpeg.num_scans = int(v.script.size());
  }
  jpeg_start_compress(&jpeg, TRUE);
  if (v.exif_rotated) jpeg_write_marker(&jpeg, JPEG_APP0 + 1, kExif, sizeof kExif);
  if (v.icc) jpeg_write_icc_profile(&jpeg, icc.data(), unsigned(icc.size()));
  while (jpeg.next_scanline < jpeg.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(pixels.data()) + size_t(jpeg.next_scanline) * size_t(v.width) * size_t(v.components);
    jpeg_write_scanlines(&jpeg, &row, 1);
  }
  jpeg_finish_compress(&jpeg);
  jpeg_destroy_compress(&jpeg);
  std::fclose(out);
}

// The variant written to `name` in `dir`.
std::filesystem::path written(const TempDir& dir, const std::string& name, const Variant& v) {
  const std::filesystem::path file = dir.path() / name;
  write_variant(file.string(), v);
  return file;
}

// Opens `file` with pelt's reader and expects what OpenImageIO read.
void expect_read_alike(const std::string& file, const std::string& name) {
  ASSERT_EQ(encoded_kind(std::filesystem::path(file)), EncodedKind::jpeg) << name;
  EXPECT_FALSE(needs_image_module_to_read(file)) << name;
  std::string error;
  const auto ours = open_jpeg(file, error);
  ASSERT_TRUE(ours) << name << ": " << error;
  expect_read_as_by_oiio(*ours, file, name);
}

std::vector<Variant> variants() {
  const Variant grey{"grey", JCS_GRAYSCALE, 1, JCS_GRAYSCALE};
  const Variant ycc{"RGB as YCbCr (JFIF)", JCS_RGB, 3, JCS_YCbCr};
  const Variant ycc_bare{"RGB as YCbCr, no marker", JCS_RGB, 3, JCS_YCbCr, 0, 0};
  const Variant ycc_adobe{"RGB as YCbCr, Adobe transform 1", JCS_RGB, 3, JCS_YCbCr, 0, 1};
  const Variant rgb{"RGB as RGB, Adobe transform 0", JCS_RGB, 3, JCS_RGB};
  const Variant rgb_bare{"RGB as RGB, no marker", JCS_RGB, 3, JCS_RGB, 0, 0};
  const Variant cmyk{"CMYK, Adobe transform 0", JCS_CMYK, 4, JCS_CMYK};
  const Variant cmyk_bare{"CMYK, no marker", JCS_CMYK, 4, JCS_CMYK, 0, 0};
  const Variant ycck{"CMYK as YCCK, Adobe transform 2", JCS_CMYK, 4, JCS_YCCK};
  const Variant two{"2 components", JCS_UNKNOWN, 2, JCS_UNKNOWN};
  // 4:4:4, 4:2:2, 4:2:0, 4:4:0, 4:1:1, 4:1:0 (the last 11 blocks an MCU with four components,
  // over libjpeg's 10)
  static constexpr int kSampling[][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}, {4, 1}, {4, 2}};
  std::vector<Variant> colours;
  for (const Variant& c : {ycc, ycc_bare, ycc_adobe, rgb, rgb_bare, ycck})
    for (const auto& hv : kSampling) {
      if (c.components == 4 && hv[0] * hv[1] == 8) continue;
      Variant s = c;
      s.h = hv[0], s.v = hv[1];
      colours.push_back(s);
    }
  for (const Variant& c : {grey, cmyk, cmyk_bare, two}) colours.push_back(c);
  std::vector<Variant> out;
  for (const Variant& c : colours)
    for (int coding = 0; coding <= int(Coding::restart_rows); ++coding)
      for (const int quality : {50, 100})
        for (const auto& size : {std::pair{7, 5}, std::pair{17, 13}}) {
          Variant v = c;
          v.coding = Coding(coding);
          v.quality = quality;
          v.width = size.first, v.height = size.second;
          out.push_back(v);
        }
  Variant big = ycc;  // several MCU rows and columns of 4:2:0
  big.h = big.v = 2, big.width = 61, big.height = 47;
  out.push_back(big);
  Variant one = ycc;
  one.h = one.v = 2, one.width = one.height = 1;
  out.push_back(one);
  return out;
}

TEST(JpegReader, ReadsWhatOpenImageIoReadOnEveryKindOfJpeg) {
  TempDir dir;
  const std::vector<Variant> all = variants();
  EXPECT_GT(all.size(), 1000u);
  for (size_t i = 0; i < all.size(); ++i)
    expect_read_alike(written(dir, std::to_string(i) + ".jpg", all[i]).string(), all[i].name());
}

// The default scene's maps, as an encoder other than this libjpeg wrote them.
TEST(JpegReader, ReadsTheShippedMapsAsOpenImageIoDid) {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  const auto folder = std::filesystem::path(root ? root : ".") / "tools/data/LeePerrySmith";
  for (const char* map : {"Map-COL.jpg", "Infinite-Level_02_Tangent_SmoothUV.jpg"})
    expect_read_alike((folder / map).string(), map);
}

// OpenImageIO reported an Exif orientation, and pelt drew the pixels as stored; an ICC profile
// was not applied either. So the reader turns nothing and applies nothing.
TEST(JpegReader, IgnoresExifOrientationAndIccProfileAsPeltDid) {
  TempDir dir;
  Variant v{"RGB as YCbCr (JFIF)", JCS_RGB, 3, JCS_YCbCr};
  v.h = v.v = 2, v.width = 17, v.height = 13;
  v.exif_rotated = true;
  v.icc = true;
  const std::string file = written(dir, "rotated.jpg", v).string();
  EXPECT_EQ(oiio_view(file).orientation, 6);  // OpenImageIO saw it
  expect_read_alike(file, v.name());
  std::string error;
  const auto ours = open_jpeg(file, error);
  ASSERT_TRUE(ours) << error;
  EXPECT_EQ(ours->info().width, 17);
  EXPECT_EQ(ours->info().height, 13);
}

std::string contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A valid progressive script of `scans` scans (64 to 704) for one component: each coefficient in
// scans of its own, a first sending all but its Al low bits and one refining each of those, Al
// as large as makes the count (libjpeg writes at most 10 for 8-bit samples).
std::vector<jpeg_scan_info> progressive_script(int scans) {
  std::vector<jpeg_scan_info> script;
  int refinements = scans - 64;
  for (int k = 0; k < 64; ++k) {
    const int al = std::min(refinements, 10);
    refinements -= al;
    script.push_back(jpeg_scan_info{1, {0}, k, k, 0, al});
    for (int bit = al; bit > 0; --bit) script.push_back(jpeg_scan_info{1, {0}, k, k, bit, bit - 1});
  }
  return script;
}

// A sequential script of one scan a component, each whole.
std::vector<jpeg_scan_info> sequential_script(int components) {
  std::vector<jpeg_scan_info> script;
  for (int c = 0; c < components; ++c) script.push_back(jpeg_scan_info{1, {c}, 0, 63, 0, 0});
  return script;
}

// The SOS markers in a file: entropy-coded data stuffs a 0 after every FF, so each is a scan.
int scans_in(const std::string& bytes) {
  int scans = 0;
  for (size_t at = bytes.find("\xFF\xDA"); at != std::string::npos; at = bytes.find("\xFF\xDA", at + 2)) ++scans;
  return scans;
}

// `bytes` with its first scan (its SOS segment and entropy-coded data, up to the next marker that
// is neither a stuffed FF nor a restart) written `copies` more times after it.
std::string first_scan_repeated(const std::string& bytes, int copies) {
  const size_t sos = bytes.find("\xFF\xDA");
  if (sos == std::string::npos || sos + 4 > bytes.size()) return bytes;
  size_t end = sos + 2 + (size_t(uint8_t(bytes[sos + 2])) << 8 | uint8_t(bytes[sos + 3]));
  for (end = bytes.find('\xFF', end); end != std::string::npos && end + 1 < bytes.size();
       end = bytes.find('\xFF', end + 2)) {
    const auto next = uint8_t(bytes[end + 1]);
    if (next != 0 && (next < 0xD0 || next > 0xD7)) break;
  }
  if (end == std::string::npos) return bytes;
  std::string out = bytes.substr(0, end);
  for (int i = 0; i < copies; ++i) out += bytes.substr(sos, end - sos);
  return out + bytes.substr(end);
}

// Reads `path` through read_image_rgba, as a map is read, and returns the refusal's reason ("" when
// it was read); the refusal names the file, and libjpeg prints nothing.
std::string refusal(const std::filesystem::path& path) {
  std::string reason;
  ::testing::internal::CaptureStderr();
  try {
    (void)read_image_rgba(path);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, path.string());
    reason = e.reason;
    EXPECT_FALSE(reason.empty());
  }
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed, "") << path;
  return reason;
}

// A file cut short, corrupt or not a JPEG after its signature is an InputError naming the file,
// with libjpeg's message and without libjpeg's own line on stderr. A baseline and a progressive
// file cut to every fourth length and to each of its last eight is refused, as OpenImageIO's read
// left an error on each; a restart marker written over every third pair of their bytes is refused
// where it left one and read where it did not (in a table entry no block uses, say).
TEST(JpegReader, ACutOrCorruptFileIsAnErrorNamingIt) {
  TempDir dir;
  for (const Coding coding : {Coding::baseline, Coding::progressive}) {
    Variant v{"RGB as YCbCr (JFIF)", JCS_RGB, 3, JCS_YCbCr};
    v.h = v.v = 2, v.width = 40, v.height = 24, v.coding = coding;
    const std::filesystem::path good = written(dir, "good.jpg", v);
    const std::string all = contents(good);
    EXPECT_EQ(refusal(good), "");
    EXPECT_NE(refusal(dir.write("cut.jpg", all.substr(0, all.size() * 2 / 3))).find("Premature end of JPEG file"),
              std::string::npos);
    for (size_t length = 3; length < all.size(); length += length + 8 < all.size() ? 4 : 1) {
      // A name of its own: truncating a file on this machine's ext4 waited for the disk's discard.
      const std::filesystem::path cut = dir.write("cut_" + std::to_string(length) + ".jpg", all.substr(0, length));
      EXPECT_NE(refusal(cut), "") << v.name() << " cut to " << length << " of " << all.size();
      EXPECT_FALSE(oiio_view(cut.string()).read) << v.name() << " cut to " << length << " of " << all.size();
    }
    int refused = 0;
    for (size_t at = 2; at + 2 < all.size(); at += 3) {
      std::string corrupt = all;
      corrupt[at] = char(0xFF), corrupt[at + 1] = char(0xD5);  // a restart marker where none belongs
      const std::filesystem::path bad = dir.write("corrupt_" + std::to_string(at) + ".jpg", corrupt);
      const bool read = refusal(bad).empty();
      EXPECT_EQ(read, oiio_view(bad.string()).read) << v.name() << ", RST5 at " << at << " of " << all.size();
      refused += !read;
    }
    EXPECT_GT(refused, int(all.size()) / 6) << v.name();
  }
  const std::string garbage = std::string("\xFF\xD8\xFF", 3) + "this is not a JPEG's next marker at all";
  EXPECT_NE(refusal(dir.write("garbage.jpg", garbage)), "");
  EXPECT_NE(refusal(dir.write("signature.jpg", std::string("\xFF\xD8\xFF", 3))), "");
}

// Expects `file` refused with `reason` in the message, where OpenImageIO's open or read failed too.
void expect_refused_as_by_oiio(const std::filesystem::path& file, const std::string& reason) {
  EXPECT_FALSE(oiio_view(file.string()).read) << file;
  EXPECT_NE(refusal(file).find(reason), std::string::npos) << file;
}

// A header libjpeg warns about (a JFIF version 2 it does not know) left OpenImageIO's error, and
// pelt refused the file: still refused, with libjpeg's warning as the reason.
TEST(JpegReader, AHeaderLibjpegWarnsAboutIsRefused) {
  TempDir dir;
  Variant v{"RGB as YCbCr (JFIF)", JCS_RGB, 3, JCS_YCbCr};
  v.jfif_major = 2;
  expect_refused_as_by_oiio(written(dir, "jfif2.jpg", v), "JFIF revision number 2");
}

// A file of five components: this libjpeg's scans find none past the fourth, and OpenImageIO's
// open failed on it too.
TEST(JpegReader, AFileOfFiveComponentsIsRefusedAsOpenImageIoDid) {
  TempDir dir;
  Variant v{"5 components", JCS_UNKNOWN, 5, JCS_UNKNOWN};
  v.coding = Coding::progressive;  // one component a scan: libjpeg writes no interleaved scan of five
  expect_refused_as_by_oiio(written(dir, "five.jpg", v), "5 components");
}

// A 12-bit file (SOF1, precision 12): this libjpeg decodes 8-bit samples only, and OpenImageIO's
// open failed on it too. The header is made by hand: this libjpeg cannot write one.
TEST(JpegReader, ATwelveBitFileIsRefusedAsOpenImageIoDid) {
  TempDir dir;
  std::string bytes = contents(written(dir, "eight.jpg", Variant{"grey", JCS_GRAYSCALE, 1, JCS_GRAYSCALE}));
  const size_t sof = bytes.find("\xFF\xC0", 2);
  ASSERT_NE(sof, std::string::npos);
  bytes[sof + 1] = char(0xC1);  // extended sequential
  bytes[sof + 4] = 12;          // its precision
  expect_refused_as_by_oiio(dir.write("twelve.jpg", bytes), "precision 12");
}

// How a refusal for too many scans begins, the limit named.
std::string scan_limit_reason() {
  return "reading the pixels failed: a JPEG of more than " + std::to_string(kMaxJpegScans) + " scans";
}

// A progressive file of a valid script (libjpeg finds nothing wrong: OpenImageIO reads it) of
// more scans than the limit is refused, the limit in the reason: each scan walks every block,
// so such a file could be small and take seconds. One of the limit's scans is read as before.
TEST(JpegReader, AProgressiveFileOfMoreScansThanTheLimitIsRefused) {
  TempDir dir;
  for (const int scans : {kMaxJpegScans, kMaxJpegScans + 1, 704}) {
    Variant v{"grey", JCS_GRAYSCALE, 1, JCS_GRAYSCALE};
    v.coding = Coding::progressive;
    v.quality = 100;  // every refinement sends bits
    v.width = 61, v.height = 47;
    v.script = progressive_script(scans);
    const std::filesystem::path file = written(dir, std::to_string(scans) + ".jpg", v);
    ASSERT_EQ(scans_in(contents(file)), scans) << v.name();
    if (scans <= kMaxJpegScans) {
      expect_read_alike(file.string(), v.name());
      continue;
    }
    EXPECT_TRUE(oiio_view(file.string()).read) << v.name();
    EXPECT_EQ(refusal(file).substr(0, scan_limit_reason().size()), scan_limit_reason()) << v.name();
  }
}

// libjpeg never checks that a sequential file sends each component once: a file whose luma scan
// is repeated decodes, each copy walking the image again, and arithmetic-coded a copy of plain
// blocks takes a few bytes. Past the limit it is refused as a progressive file is; at the limit
// it reads as OpenImageIO read it (each copy writes the same coefficients).
TEST(JpegReader, ASequentialFileOfMoreScansThanTheLimitIsRefused) {
  TempDir dir;
  Variant v{"RGB as YCbCr (JFIF)", JCS_RGB, 3, JCS_YCbCr};
  v.coding = Coding::arithmetic;
  v.width = 40, v.height = 24;
  v.script = sequential_script(3);
  const std::string one_each = contents(written(dir, "sequential.jpg", v));
  ASSERT_EQ(scans_in(one_each), 3);
  const std::filesystem::path at_limit = dir.write("at_limit.jpg", first_scan_repeated(one_each, kMaxJpegScans - 3));
  const std::filesystem::path past = dir.write("past.jpg", first_scan_repeated(one_each, kMaxJpegScans - 2));
  ASSERT_EQ(scans_in(contents(at_limit)), kMaxJpegScans);
  ASSERT_EQ(scans_in(contents(past)), kMaxJpegScans + 1);
  expect_read_alike(at_limit.string(), "sequential, " + std::to_string(kMaxJpegScans) + " scans");
  EXPECT_TRUE(oiio_view(past.string()).read);
  EXPECT_EQ(refusal(past).substr(0, scan_limit_reason().size()), scan_limit_reason());
}

}  // namespace jpeg_reader_test
}  // namespace pelt::io
