// The plot: the embedded script draws a PNG from a CSV with Debian's python3-matplotlib
// (a project dependency), and a missing interpreter or module is reported, not thrown,
// leaving no file behind.
#include "tools/tradeoff/plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/tools/io/temp_dir.h"
#include "tools/io/output_file.h"
#include "tools/tradeoff/plot_script.h"
#include "tools/tradeoff/report.h"

namespace pelt::tradeoff {
namespace {

namespace fs = std::filesystem;

// A CSV like pelt tradeoff's: a reference with rmse 0, a knob row equal to the default,
// presets, and points sharing a position.
std::string sample_csv() {
  std::ostringstream s;
  s << kCsvHeader << "\n"
    << "reference,reference,900.5,0,inf,0,0\n"
    << "default,scene,10.2,0.02,33.98,0.3,0.2\n"
    << "sort,none,8.1,0.05,26.02,0.6,0.4\n"
    << "sort,tile,10.2,0.02,33.98,0.3,0.2\n"
    << "spp,16,150.0,0.004,47.96,0.1,0.02\n"
    << "preset,fast,5.0,0.08,21.94,0.7,0.5\n";
  return s.str();
}

// A stand-in "python3" in `dir` running the shell script `body` (its arguments: -c SCRIPT CSV PNG
// TITLE INDICES), for the paths the real interpreter rarely takes.
fs::path fake_python(const io::TempDir& dir, const std::string& body) {
  const fs::path fake = dir.write("python3", "#!/bin/sh\n" + body);
  ::chmod(fake.c_str(), 0755);
  return fake;
}

size_t files_in(const fs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(TradeoffPlot, ScriptIsEmbeddedByteForByte) {
  const char* src = std::getenv("PELT_SOURCE_DIR");
  ASSERT_NE(src, nullptr);
  std::ifstream f(fs::path(src) / "tools" / "tradeoff" / "plot_tradeoff.py", std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  EXPECT_EQ(io::embedded::plot_tradeoff_py(), s.str());
}

TEST(TradeoffPlot, DrawsAPngFromTheCsv) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  const fs::path png = dir.path() / "tradeoff.png";
  const PlotOutcome r = make_plot(csv, png, "test plot", {true, false, false, false, true, true});
  ASSERT_TRUE(r.made) << r.problem;
  auto in = OIIO::ImageInput::open(png.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(std::string(in->format_name()), "png");
  EXPECT_GT(in->spec().width, 300);
  EXPECT_GT(in->spec().height, 200);
  EXPECT_EQ(files_in(dir.path()), 2u);  // the CSV and the PNG: no temporary left
}

// A sweep whose settings leave the image unchanged puts many points at one error within a
// few milliseconds: every label must still land where no other label is (the script
// reports where its texts were drawn, in display pixels, when asked).
TEST(TradeoffPlot, LabelsOfACrowdedSweepDoNotOverlap) {
  io::TempDir dir;
  std::ostringstream s;
  s << kCsvHeader << "\n"
    << "reference,reference,900.5,0,inf,0,0\n"
    << "default,scene,10.2,0.02,33.98,0.3,0.2\n";
  const int crowd = 30;
  for (int i = 0; i < crowd; ++i) s << "knob" << i << ",setting_" << i << "," << 10.0 + 0.15 * i << ",0.02,33.98,0.3,0.2\n";
  const fs::path csv = dir.write("tradeoff.csv", s.str());
  const fs::path boxes_file = dir.path() / "boxes.txt";
  std::vector<bool> front(size_t(crowd) + 2, false);
  front[0] = front[1] = true;
  ::setenv("PELT_PLOT_LABEL_BOXES", boxes_file.c_str(), 1);
  const PlotOutcome r = make_plot(csv, dir.path() / "tradeoff.png", "crowd", front);
  ::unsetenv("PELT_PLOT_LABEL_BOXES");
  ASSERT_TRUE(r.made) << r.problem;

  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  std::ifstream in(boxes_file);
  for (Box b; in >> b.x0 >> b.y0 >> b.x1 >> b.y1;) boxes.push_back(b);
  ASSERT_EQ(boxes.size(), size_t(crowd) + 2);  // one label per position
  for (size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_GT(boxes[i].x1 - boxes[i].x0, 10.0) << i;  // a real text, not an empty box
    for (size_t j = 0; j < i; ++j) {
      const Box &a = boxes[i], &b = boxes[j];
      const bool apart = a.x1 <= b.x0 || a.x0 >= b.x1 || a.y1 <= b.y0 || a.y0 >= b.y1;
      EXPECT_TRUE(apart) << "labels " << i << " and " << j << " overlap";
    }
  }
}

TEST(TradeoffPlot, MissingInterpreterIsReportedAndLeavesNoFile) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  const fs::path png = dir.path() / "tradeoff.png";
  const PlotOutcome r = make_plot(csv, png, "t", {true}, (dir.path() / "no-such-python3").string());
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.problem.find("no-such-python3"), std::string::npos) << r.problem;
  EXPECT_EQ(files_in(dir.path()), 1u);
}

// The temporary exists before the script runs (io::TempFile creates it): a script that ends well
// without plotting must not put an empty file in place.
TEST(TradeoffPlot, AScriptThatWritesNothingIsReportedAndLeavesNoFile) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  const fs::path fake = fake_python(dir, "exit 0\n");
  const PlotOutcome r = make_plot(csv, dir.path() / "tradeoff.png", "t", {true}, fake.string());
  EXPECT_FALSE(r.made);
  EXPECT_EQ(r.problem, "the plot script wrote no image");
  EXPECT_EQ(files_in(dir.path()), 2u);  // the CSV and the script
}

// The script is spawned while SIGINT and SIGTERM are blocked on pelt's thread (so that a signal
// cannot fall between its start and its listing for the handler); it must start with the
// caller's mask, or a Ctrl-C would never reach it.
TEST(TradeoffPlot, TheScriptStartsWithTheCallersSignalMask) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  // Builtins only: a shell blocks its signals while it forks and waits for a command.
  const fs::path fake = fake_python(dir, "while read -r k v; do [ \"$k\" = SigBlk: ] && echo \"$v\" > \"${4%/*}/mask\"; "
                                         "done < /proc/self/status\necho plot > \"$4\"\n");
  const PlotOutcome r = make_plot(csv, dir.path() / "tradeoff.png", "t", {true}, fake.string());
  EXPECT_TRUE(r.made) << r.problem;
  std::ifstream mask(dir.path() / "mask");
  std::string script_mask;
  std::getline(mask, script_mask);
  // This thread's own mask, as /proc prints it (the test may start with signals blocked).
  std::ifstream status("/proc/thread-self/status");
  std::string key, own;
  while (status >> key && key != "SigBlk:") status.ignore(1 << 20, '\n');
  status >> own;
  ASSERT_FALSE(own.empty());
  EXPECT_EQ(script_mask, own);
}

TEST(TradeoffPlot, MissingMatplotlibIsNamed) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  // An "interpreter" that behaves like the script does when `import matplotlib` fails.
  const fs::path fake = fake_python(dir, "exit 3\n");
  const PlotOutcome r = make_plot(csv, dir.path() / "tradeoff.png", "t", {true}, fake.string());
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.problem.find("matplotlib is missing"), std::string::npos) << r.problem;
  EXPECT_NE(r.problem.find("python3-matplotlib"), std::string::npos) << r.problem;
  EXPECT_FALSE(fs::exists(dir.path() / "tradeoff.png"));
}

TEST(TradeoffPlot, ABadCsvFailsTheScriptWithoutAFile) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", "knob,setting,ms_median\nsort,none,fast\n");
  const PlotOutcome r = make_plot(csv, dir.path() / "tradeoff.png", "t", {true});
  EXPECT_FALSE(r.made);
  EXPECT_NE(r.problem.find("exit code 4"), std::string::npos) << r.problem;
  EXPECT_FALSE(fs::exists(dir.path() / "tradeoff.png"));
}

// A signal while the script plots: the handler about to end the process (as render/interrupt.h's
// does) kills and reaps the script, then removes the temporary it was writing, so nothing is left
// and no script outlives pelt. Run in a forked child, whose handler ends it.
TEST(TradeoffPlot, ASignalWhileThePlotIsDrawnLeavesNoFileAndNoScript) {
  io::TempDir dir;
  const fs::path csv = dir.write("tradeoff.csv", sample_csv());
  // An "interpreter" that starts writing its output (argument 4) and then takes its time.
  const fs::path fake =
      fake_python(dir, "echo $$ > \"$(dirname \"$4\")/script.pid\"\necho partial > \"$4\"\nexec sleep 30\n");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    struct sigaction sa {};
    sa.sa_handler = [](int sig) {
      io::remove_temp_files_in_signal_handler();
      ::_exit(128 + sig);
    };
    ::sigaction(SIGTERM, &sa, nullptr);
    make_plot(csv, dir.path() / "tradeoff.png", "t", {true}, fake.string());
    ::_exit(0);
  }
  auto temporaries = [&] {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir.path()))
      n += e.path().filename().string().find(".tmp-") != std::string::npos;
    return n;
  };
  for (int waited = 0; waited < 20000 && (temporaries() == 0 || !fs::exists(dir.path() / "script.pid")); ++waited)
    ::usleep(1000);
  ASSERT_EQ(temporaries(), 1u) << "the script never began its plot";
  ::usleep(20000);  // the pid file is written before the temporary; let both be complete
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_EQ(temporaries(), 0u);
  EXPECT_FALSE(fs::exists(dir.path() / "tradeoff.png"));
  std::ifstream pid_file(dir.path() / "script.pid");
  pid_t script = 0;
  pid_file >> script;
  ASSERT_GT(script, 0);
  EXPECT_NE(::kill(script, 0), 0) << "the plot script outlived pelt";
}

}  // namespace
}  // namespace pelt::tradeoff
