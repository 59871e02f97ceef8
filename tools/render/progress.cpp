#include "tools/render/progress.h"

#include <cmath>

#include <unistd.h>

namespace pelt::render {
namespace {

std::string printf_string(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

double frames_per_second(int done, double elapsed) { return elapsed > 0.0 ? done / elapsed : 0.0; }

std::string time_left(int done, int total, double elapsed) {
  if (done <= 0 || elapsed <= 0.0) return "? left";
  return format_duration(elapsed / done * (total - done)) + " left";
}

}  // namespace

ProgressMode progress_mode(bool quiet, int fd) {
  if (quiet) return ProgressMode::quiet;
  return ::isatty(fd) ? ProgressMode::bar : ProgressMode::lines;
}

std::string format_duration(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return "?";
  if (seconds < 60.0) return printf_string("%.1f s", seconds);
  const long long s = std::llround(seconds);
  char buf[48];
  if (s < 3600)
    std::snprintf(buf, sizeof buf, "%lld:%02lld", s / 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

std::string progress_bar(int done, int total, double elapsed_seconds, int width) {
  const int filled = total > 0 ? static_cast<int>(static_cast<long long>(width) * done / total) : width;
  std::string bar = "[";
  bar.append(size_t(filled), '#').append(size_t(width - filled), '.') += ']';
  bar += "  " + std::to_string(done) + "/" + std::to_string(total) + " frames  ";
  bar += printf_string("%.2f frames/s  ", frames_per_second(done, elapsed_seconds));
  bar += done == total ? format_duration(elapsed_seconds) + " total" : time_left(done, total, elapsed_seconds);
  return bar;
}

std::string progress_line(int frame, int done, int total, double frame_seconds, double elapsed_seconds) {
  std::string line = "frame " + std::to_string(frame) + " done (" + std::to_string(done) + "/" +
                     std::to_string(total) + "): ";
  line += printf_string("%.2f s, %.2f frames/s, ", frame_seconds, frames_per_second(done, elapsed_seconds));
  line += time_left(done, total, elapsed_seconds);
  return line;
}

Progress::Progress(ProgressMode mode, int total, std::FILE* out)
    : mode_(mode), total_(total), out_(out), start_(std::chrono::steady_clock::now()) {}

void Progress::frame_done(int frame, double frame_seconds) {
  ++done_;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  switch (mode_) {
    case ProgressMode::quiet: return;
    case ProgressMode::lines:
      std::fprintf(out_, "pelt: %s\n", progress_line(frame, done_, total_, frame_seconds, elapsed).c_str());
      break;
    case ProgressMode::bar:
      // \r and clear-to-end-of-line redraw the bar in place.
      std::fprintf(out_, "\r%s\033[K", progress_bar(done_, total_, elapsed, 30).c_str());
      drawn_ = true;
      break;
  }
  std::fflush(out_);
}

void Progress::finish() {
  if (mode_ == ProgressMode::bar && drawn_) {
    std::fputc('\n', out_);
    std::fflush(out_);
    drawn_ = false;
  }
}

}  // namespace pelt::render
