#include "tools/io/exr_writer.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <Iex.h>
#include <sys/types.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

namespace pelt::io {
namespace {

// OpenEXR writes the chunks, then seeks back to fill in their offset table, in OutputFile's
// destructor, which swallows any failure there: every failure is kept here, sticky, for the caller
// to check once the OutputFile is gone, as well as thrown to stop the writing at once.
class FileStream final : public Imf::OStream {
 public:
  FileStream(std::FILE* file, const std::string& name) : Imf::OStream(name.c_str()), file_(file) {
    // A pipe or FIFO (an output written in place, output_file.h) cannot seek back to the offset
    // table: its bytes gather in memory and go out in order at the end. OpenImageIO's writer sent
    // such a file out with its offset table zero, incomplete, and exit code 0.
    seekable_ = fseeko(file_, 0, SEEK_CUR) == 0;
  }

  void write(const char c[], int n) override {
    if (error_ != 0) throw Iex::IoExc(std::strerror(error_));
    const size_t count = size_t(n);
    if (seekable_) {
      if (std::fwrite(c, 1, count, file_) != count) fail(errno);
    } else {
      if (held_.size() < pos_ + count) held_.resize(pos_ + count);
      std::copy(c, c + count, held_.begin() + std::ptrdiff_t(pos_));
    }
    pos_ += count;
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override {
    if (error_ != 0) throw Iex::IoExc(std::strerror(error_));
    if (seekable_ && fseeko(file_, off_t(pos), SEEK_SET) != 0) fail(errno);
    pos_ = pos;
  }

  // Sends the bytes held for a pipe, once the file is whole; the first failure's errno (0: none).
  int finish() {
    if (error_ == 0 && !held_.empty() && std::fwrite(held_.data(), 1, held_.size(), file_) != held_.size())
      error_ = errno != 0 ? errno : EIO;
    return error_;
  }
  int error() const { return error_; }

 private:
  [[noreturn]] void fail(int error) {
    error_ = error != 0 ? error : EIO;
    throw Iex::IoExc(std::strerror(error_));
  }

  std::FILE* file_;
  bool seekable_ = true;
  uint64_t pos_ = 0;
  std::string held_;
  int error_ = 0;
};

// The OpenEXR calls, with its exceptions turned into the reason; "" on success.
std::string encode(FileStream& stream, int width, int height, int channels, const float* pixels) {
  static constexpr const char* kNames[4][4] = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  try {
    start_exr_threads();  // inside: a thread that cannot be made fails this write, not pelt
    Imf::Header header(width, height);  // ZIP, increasing y, windows at 0, 0: OpenImageIO's header
    Imf::FrameBuffer frame;
    const size_t x_stride = sizeof(float) * size_t(channels), y_stride = x_stride * size_t(width);
    for (int c = 0; c < channels; ++c) {
      header.channels().insert(kNames[channels - 1][c], Imf::Channel(Imf::FLOAT));
      // Slice takes a mutable base for reading and writing alike; an OutputFile only reads it.
      frame.insert(kNames[channels - 1][c],
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(pixels + c)), x_stride, y_stride));
    }
    Imf::OutputFile out(stream, header, Imf::globalThreadCount());
    out.setFrameBuffer(frame);
    out.writePixels(height);
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

}  // namespace

// OpenEXR compresses blocks of rows on a process-wide pool of threads, made on the first write or EXR
// map read: one per core, the count OpenImageIO set when it wrote pelt's EXR files (its module, loaded
// for a map, sets that count again, which changes nothing). The file is the same on any count. Without the
// pool, 24 frames of box_fur at 1024 x 768 took 2.3 s against 1.75 s on 2 cores: the writes, 90
// against 65 ms a frame, set the pace while the next frame renders. The pool's threads only
// compress (or decompress a map's blocks, exr_reader.cpp): OpenEXR does the file's I/O on the
// calling thread, which made the temporary (output_file.h), so none of them creates a file a
// signal's clean-up could miss.
namespace {
std::atomic<bool> g_threads_set{false};  // set_exr_threads ran: its count stands
}  // namespace

void set_exr_threads(int threads) {
  Imf::setGlobalThreadCount(std::max(0, threads));
  g_threads_set = true;
}

void start_exr_threads() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!g_threads_set) Imf::setGlobalThreadCount(int(std::thread::hardware_concurrency()));
  });
}

std::string write_exr_f32(const std::string& file, int width, int height, int channels, const float* pixels) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || !pixels)
    return "cannot write this EXR (size or channels out of range)";
  std::FILE* out = std::fopen(file.c_str(), "wb");
  if (!out) return "cannot create the image file: " + std::string(std::strerror(errno));
  std::string failure;
  int error = 0;
  {
    FileStream stream(out, file);
    failure = encode(stream, width, height, channels, pixels);
    error = failure.empty() ? stream.finish() : stream.error();
  }
  // A short write shows at the latest here, where the buffered bytes reach the file.
  if (error == 0 && std::fflush(out) != 0) error = errno;
  if (std::fclose(out) != 0 && error == 0) error = errno;
  // The system's reason where there is one: OpenEXR's message around it names the descriptor the
  // temporary was opened through.
  if (error != 0) return "writing the image failed: " + std::string(std::strerror(error));
  if (!failure.empty()) return "writing the image failed: " + failure;
  return {};
}

}  // namespace pelt::io
