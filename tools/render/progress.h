// Progress of a multi-frame render on stderr: a redrawn bar on a terminal, one plain line
// per frame otherwise (logs, farm job output), nothing with --quiet.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace pelt::render {

enum class ProgressMode { bar, lines, quiet };

// bar when `fd` is a terminal, lines otherwise; quiet wins.
ProgressMode progress_mode(bool quiet, int fd);

// "1.5 s", "2:05", "1:02:03": a duration for people.
std::string format_duration(double seconds);
// `[#####.....]  3/48 frames  2.10 frames/s  0:22 left` for a bar `width` cells wide.
std::string progress_bar(int done, int total, double elapsed_seconds, int width);
// `frame 12 done (3/48): 0.41 s, 2.10 frames/s, 0:22 left`.
std::string progress_line(int frame, int done, int total, double frame_seconds, double elapsed_seconds);

class Progress {
 public:
  // `total` frames will be rendered; `out` is where the report goes (stderr).
  Progress(ProgressMode mode, int total, std::FILE* out);
  // Called once per finished (written) frame.
  void frame_done(int frame, double frame_seconds);
  // Ends the bar's line; called once after the last frame or an interruption.
  void finish();
  int done() const { return done_; }

 private:
  ProgressMode mode_;
  int total_;
  int done_ = 0;
  std::FILE* out_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pelt::render
