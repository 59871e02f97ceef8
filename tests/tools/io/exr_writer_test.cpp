// EXR files written with OpenEXR's library (tools/io/exr_writer.h), without OpenImageIO's module:
// what OpenImageIO reads back is, bit for bit, what the module's own EXR writer (the old path, still
// in the module) stored for the same floats, NaN, infinities and denormals included, in the same
// compressed blocks under the same header less its empty capDate; write_image_atomic keeps its
// alpha convention and its atomic temporaries, and a failure is an InputError that leaves no file.
#include "tools/io/exr_writer.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfThreading.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/io/fresh_process.h"
#include "tests/tools/io/oiio_view.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/image_backend.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace exr_writer_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// Floats of every kind a render or a caller may hand over, spread over the channels (alpha too):
// a ramp, then negative, huge, denormal, signed zero, infinite and NaN values.
std::vector<float> awkward_floats(int width, int height, int channels) {
  const float nan_payload = [] {
    const uint32_t bits = 0x7fc01234u;  // a quiet NaN with a payload of its own
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }();
  const float specials[] = {-0.75f,
                            3.0e38f,
                            std::numeric_limits<float>::denorm_min(),
                            1.0e-40f,
                            -0.0f,
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            nan_payload,
                            65504.0f,
                            1.0e-8f};
  std::vector<float> v(size_t(width) * size_t(height) * size_t(channels));
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = i % 3 == 1 ? specials[(i / 3) % std::size(specials)] : float((i * 37) % 101) / 100.0f;
  return v;
}

std::vector<uint8_t> bytes_of(const std::vector<float>& v) {
  std::vector<uint8_t> b(v.size() * sizeof(float));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

// The old path: the module's OpenImageIO writer, as write_image_atomic called it for an EXR.
std::string write_with_module(const std::string& file, int width, int height, int channels, const float* px) {
  ImageWriteRequest r;
  r.target = r.temp = file;
  r.width = width, r.height = height, r.channels = channels;
  r.type = StoredType::f32;
  r.exr_grey_names = true;
  r.pixels = px;
  return image_backend().write(r);
}

// A file as OpenEXR's reader sees it: its header's attribute names, and each block of rows as
// stored (compressed).
struct ExrBlocks {
  std::set<std::string> attributes;
  std::vector<std::string> blocks;
};
ExrBlocks exr_blocks(const std::string& file) {
  ExrBlocks out;
  Imf::InputFile in(file.c_str(), 0);
  for (auto it = in.header().begin(); it != in.header().end(); ++it) out.attributes.insert(it.name());
  const Imath::Box2i window = in.header().dataWindow();
  for (int y = window.min.y; y <= window.max.y; y += 16) {  // ZIP's blocks of 16 rows
    const char* data = nullptr;
    int size = 0;
    in.rawPixelData(y, data, size);
    out.blocks.emplace_back(data, size_t(size));
  }
  return out;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

size_t files_in(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

// write_image_atomic's failure on `path`: InputError naming it, its reason holding `reason_part`.
void expect_exr_write_error(const std::filesystem::path& path, const std::vector<float>& px, int width, int height,
                            const std::string& reason_part) {
  try {
    write_image_atomic(path, width, height, 4, PixelType::f32, px.data());
    ADD_FAILURE() << path << " was written";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, path.string());
    EXPECT_EQ(e.field, "");
    EXPECT_NE(e.reason.find(reason_part), std::string::npos) << e.what();
  }
}

TEST(ExrWriter, EveryChannelCountAndSizeIsWhatTheModuleWrote) {
  TempDir dir;
  const char* names[] = {"Y", "Y, A", "R, G, B", "R, G, B, A"};
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{7, 3}, std::pair{33, 21}}) {  // 21 rows: two blocks
    for (int channels = 1; channels <= 4; ++channels) {
      const std::string label = std::to_string(channels) + " channel(s), " + std::to_string(w) + "x" + std::to_string(h);
      std::string stem = std::to_string(channels);  // appended: `"c" + string` trips GCC 12's -Wstringop-overflow
      stem += "_" + std::to_string(w) + "x" + std::to_string(h);
      const std::string ours = (dir.path() / (stem + ".exr")).string();
      const std::string theirs = (dir.path() / (stem + "_module.exr")).string();
      const std::vector<float> px = awkward_floats(w, h, channels);
      ASSERT_EQ(write_exr_f32(ours, w, h, channels, px.data()), "") << label;
      ASSERT_EQ(write_with_module(theirs, w, h, channels, px.data()), "") << label;

      // OpenImageIO reads each value's bits back as given, and as it read the module's file.
      const OiioView a = oiio_view(ours), b = oiio_view(theirs);
      ASSERT_TRUE(a.read && b.read) << label;
      EXPECT_EQ(a.width, w);
      EXPECT_EQ(a.height, h);
      EXPECT_EQ(a.channels, channels);
      EXPECT_EQ(a.type, StoredType::f32);
      EXPECT_EQ(a.names, names[channels - 1]) << label;
      EXPECT_EQ(a.names, b.names) << label;
      EXPECT_EQ(a.alpha, b.alpha) << label;
      EXPECT_EQ(a.bytes, bytes_of(px)) << label;
      EXPECT_EQ(a.bytes, b.bytes) << label;

      // The same header but the module's empty capDate, and the same compressed blocks.
      const ExrBlocks x = exr_blocks(ours), y = exr_blocks(theirs);
      std::set<std::string> module_less_date = y.attributes;
      EXPECT_EQ(module_less_date.erase("capDate"), 1u) << label;
      EXPECT_EQ(x.attributes, module_less_date) << label;
      EXPECT_EQ(x.blocks.size(), size_t((h + 15) / 16)) << label;
      EXPECT_TRUE(x.blocks == y.blocks) << label;

      const Imf::Header header = Imf::InputFile(ours.c_str(), 0).header();
      EXPECT_EQ(header.compression(), Imf::ZIP_COMPRESSION) << label;
      EXPECT_EQ(header.lineOrder(), Imf::INCREASING_Y) << label;
      EXPECT_EQ(header.dataWindow(), Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(w - 1, h - 1))) << label;
      EXPECT_EQ(header.displayWindow(), header.dataWindow()) << label;
      EXPECT_EQ(header.pixelAspectRatio(), 1.0f);
      EXPECT_EQ(header.screenWindowCenter(), Imath::V2f(0, 0));
      EXPECT_EQ(header.screenWindowWidth(), 1.0f);
      int n = 0;
      for (auto it = header.channels().begin(); it != header.channels().end(); ++it, ++n)
        EXPECT_EQ(it.channel().type, Imf::FLOAT) << label << " " << it.name();
      EXPECT_EQ(n, channels) << label;
    }
  }
}

// Through write_image_atomic: EXR holds associated alpha, so straight colour is multiplied by its
// alpha (image_io.cpp, as before: NaN and infinities multiply as floats do) and premultiplied
// colour goes in as given; grey and RGB are stored as given. No temporary stays.
TEST(ExrWriter, WriteImageAtomicStoresPremultipliedColour) {
  TempDir dir;
  constexpr int kW = 7, kH = 3;
  for (int channels = 1; channels <= 4; ++channels) {
    const std::vector<float> px = awkward_floats(kW, kH, channels);
    std::vector<float> associated = px;
    if (channels == 2 || channels == 4)
      for (size_t p = 0; p < associated.size(); p += size_t(channels))
        for (int c = 0; c + 1 < channels; ++c) associated[p + size_t(c)] *= associated[p + size_t(channels) - 1];
    for (const Alpha alpha : {Alpha::straight, Alpha::premultiplied}) {
      const bool straight = alpha == Alpha::straight;
      std::string name = std::to_string(channels);
      name += straight ? "s.exr" : "p.exr";
      ImageWriteOptions options;
      options.alpha = alpha;
      write_image_atomic(dir.path() / name, kW, kH, channels, PixelType::f32, px.data(), options);
      const OiioView v = oiio_view((dir.path() / name).string());
      ASSERT_TRUE(v.read) << name;
      EXPECT_EQ(v.bytes, bytes_of(straight ? associated : px)) << name;
    }
  }
  EXPECT_EQ(files_in(dir.path()), 8u);  // the files alone, no temporary
}

TEST(ExrWriter, FailuresAreInputErrorsThatLeaveNoFile) {
  TempDir dir;
  const std::vector<float> px = awkward_floats(64, 64, 4);
  // A folder that does not exist, and one that is a regular file: no temporary can be made there.
  expect_exr_write_error(dir.path() / "missing" / "out.exr", px, 2, 2, "cannot create the image file");
  EXPECT_EQ(files_in(dir.path()), 0u);
  dir.write("plain", "a file");
  expect_exr_write_error(dir.path() / "plain" / "out.exr", px, 2, 2, "cannot create the image file");
  EXPECT_EQ(files_in(dir.path()), 1u);
  // The target is a folder: the temporary is written and removed once the rename fails.
  std::filesystem::create_directories(dir.path() / "taken.exr" / "inside");
  expect_exr_write_error(dir.path() / "taken.exr", px, 2, 2, "cannot move");
  EXPECT_TRUE(std::filesystem::is_directory(dir.path() / "taken.exr" / "inside"));
  EXPECT_EQ(files_in(dir.path()), 2u);
  // A disk that fills up mid-file (root ignores a read-only folder, so a file-size limit stands in
  // for it): the system's reason, and neither the temporary nor the target stays.
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  rlimit small = before;
  small.rlim_cur = 1000;  // bytes: inside the first block of 16 rows
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  try {
    write_image_atomic(dir.path() / "big.exr", 64, 64, 4, PixelType::f32, px.data());
    ADD_FAILURE() << "a file over the size limit was written";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, (dir.path() / "big.exr").string());
    EXPECT_NE(e.reason.find("writing the image failed: File too large"), std::string::npos) << e.what();
    EXPECT_EQ(e.reason.find("/proc/self/fd"), std::string::npos) << e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, previous);
  EXPECT_EQ(files_in(dir.path()), 2u);
}

// A command's --threads bounds OpenEXR's pool (`pelt render` calls set_exr_threads before the
// set-up): the size set stands when the first write starts the pool, which would otherwise make
// one thread per core, and 0 codes every block on the calling thread, the same file. In fresh
// processes: the pool is started once a process.
TEST(ExrWriter, TheThreadCountSetBeforeTheFirstWriteStands) {
  for (const int threads : {1, 0}) {
    in_fresh_process([threads]() -> std::string {
      TempDir dir;
      const std::vector<float> px = awkward_floats(40, 70, 4);
      set_exr_threads(threads);
      if (!write_exr_f32((dir.path() / "a.exr").string(), 40, 70, 4, px.data()).empty()) return "the write failed";
      if (Imf::globalThreadCount() != threads)
        return "the pool holds " + std::to_string(Imf::globalThreadCount()) + " threads, not " + std::to_string(threads);
      return {};
    });
  }
}

// OpenEXR compresses on a pool of one thread per core, started by the first write (exr_writer.cpp),
// and the file does not depend on how many threads compressed it (frames are byte-identical on
// any thread count, README).
TEST(ExrWriter, TheFileIsTheSameOnAnyThreadCount) {
  TempDir dir;
  const std::vector<float> px = awkward_floats(40, 70, 4);  // 5 blocks of rows
  const std::string first = (dir.path() / "first.exr").string();
  ASSERT_EQ(write_exr_f32(first, 40, 70, 4, px.data()), "");
  EXPECT_EQ(Imf::globalThreadCount(), int(std::thread::hardware_concurrency()));
  const std::string bytes = read_file(first);
  for (const int threads : {0, 1, 3}) {
    Imf::setGlobalThreadCount(threads);
    std::string name = std::to_string(threads);
    name += ".exr";
    ASSERT_EQ(write_exr_f32((dir.path() / name).string(), 40, 70, 4, px.data()), "") << threads;
    EXPECT_TRUE(read_file(dir.path() / name) == bytes) << threads << " threads";
  }
  Imf::setGlobalThreadCount(int(std::thread::hardware_concurrency()));
}

// /dev/full takes the file but no byte of it: the write fails, with the system's reason.
TEST(ExrWriter, ADiskThatRefusesTheBytesIsAnError) {
  const std::vector<float> px = awkward_floats(64, 64, 4);
  EXPECT_NE(write_exr_f32("/dev/full", 64, 64, 4, px.data()).find("No space left on device"), std::string::npos);
  EXPECT_NE(write_exr_f32("/dev/full", 1, 1, 1, px.data()).find("No space left on device"), std::string::npos);
  EXPECT_EQ(write_exr_f32("/nonexistent-folder/a.exr", 2, 2, 4, px.data()).find("cannot create the image file"), 0u);
  EXPECT_NE(write_exr_f32((TempDir().path() / "a.exr").string(), 2, 2, 5, px.data()), "");  // no such EXR
}

// A FIFO is written in place (output_file.h) and cannot seek back to the offset table, which
// OpenEXR fills in last: the reader gets the same whole file a regular one holds (OpenImageIO's
// writer sent it with its offsets zero, which no reader can open).
TEST(ExrWriter, APipeGetsAWholeFile) {
  TempDir dir;
  const std::filesystem::path fifo = dir.path() / "p.exr";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::vector<float> px = awkward_floats(33, 21, 4);
  std::string got;
  std::thread reader([&] { got = read_file(fifo); });
  try {
    write_image_atomic(fifo, 33, 21, 4, PixelType::f32, px.data());
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    ::close(::open(fifo.c_str(), O_RDWR));  // a writer for the reader's open, which then ends
  }
  reader.join();
  write_image_atomic(dir.path() / "f.exr", 33, 21, 4, PixelType::f32, px.data());
  const std::string file = read_file(dir.path() / "f.exr");
  EXPECT_GT(file.size(), 1000u);
  EXPECT_TRUE(got == file) << got.size() << " bytes through the pipe, " << file.size() << " in the file";
}

}  // namespace exr_writer_test
}  // namespace pelt::io
