// `pelt render` over frame ranges: frames are independent of how they are batched
// (alone, in a range, in shards, resumed), outputs read back with the right frame count
// and size, Ctrl-C stops cleanly, and every bad option is exit code 2 naming the option.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/cli/render_command_fixture.h"
#include "tests/tools/cli/run_pelt.h"
#include "tests/tools/render/two_quads_gltf.h"
#include "tools/io/image_io.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

TEST_F(RenderCommand, FrameAloneEqualsFrameInRange) {
  const Result range = pelt({"-o", (dir.path() / "seq/f_###.png").string(), "--frames", "0:7", "--threads", "2"});
  ASSERT_EQ(range.code, 0) << range.err;
  for (int k : {0, 3, 7}) {
    const fs::path alone = dir.path() / ("alone_" + std::to_string(k) + ".png");
    const Result r = pelt({"-o", alone.string(), "--frame", std::to_string(k), "--threads", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string a = read_text(alone);
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a, frame_file("seq", k)) << "frame " << k;
  }
  // `--frames K:K` is the same as `--frame K`.
  const Result one = pelt({"-o", (dir.path() / "one/f_###.png").string(), "--frames", "5:5", "-q"});
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_EQ(files("one"), std::vector<std::string>{"f_005.png"});
  EXPECT_EQ(frame_file("one", 5), frame_file("seq", 5));
}

TEST_F(RenderCommand, ShardsTogetherEqualTheWholeRange) {
  const Result whole = pelt({"-o", (dir.path() / "whole/f_###.png").string(), "--frames", "1:7", "-q"});
  ASSERT_EQ(whole.code, 0) << whole.err;
  for (int i = 0; i < 3; ++i) {
    const Result r = pelt({"-o", (dir.path() / "shards/f_###.png").string(), "--frames", "1:7", "--shard",
                           std::to_string(i) + "/3", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    // Shard i holds frames 1 + i, 4 + i, 7 + i (within 1..7) so far.
  }
  ASSERT_EQ(files("shards"), files("whole"));
  EXPECT_EQ(files("whole").size(), 7u);
  for (int k = 1; k <= 7; ++k) EXPECT_EQ(frame_file("shards", k), frame_file("whole", k)) << k;
  // A shard beyond the range's length has nothing to do and says so.
  const Result empty = pelt({"-o", (dir.path() / "none/f_###.png").string(), "--frames", "0:1", "--shard", "5/8"});
  EXPECT_EQ(empty.code, 0) << empty.err;
  EXPECT_NE(empty.err.find("nothing to render"), std::string::npos) << empty.err;
  EXPECT_FALSE(fs::exists(dir.path() / "none"));
}

// A shard with no frames in its range still answers --stats, with an empty frame list: a farm
// that collects every shard's statistics finds a file for each, as for -o's checked folder.
TEST_F(RenderCommand, StatsOfAShardWithNothingToRenderListNoFrame) {
  const fs::path stats = dir.path() / "st" / "empty.json";
  const Result r = pelt({"-o", (dir.path() / "none/f_###.png").string(), "--frames", "0:1", "--shard", "5/8",
                         "--stats", stats.string(), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(stats));
  const nlohmann::json j = nlohmann::json::parse(read_text(stats));
  ASSERT_TRUE(j["frames"].is_array()) << j.dump();
  EXPECT_EQ(j["frames"].size(), 0u);
  EXPECT_FALSE(fs::exists(dir.path() / "none"));
}

TEST_F(RenderCommand, ResumeRendersOnlyMissingFramesAndMatches) {
  const std::string out = (dir.path() / "run/f_###.png").string();
  const Result first = pelt({"-o", out, "-q"});  // default range: every frame
  ASSERT_EQ(first.code, 0) << first.err;
  ASSERT_EQ(files("run").size(), 8u);
  std::vector<std::string> reference;
  for (int k = 0; k < 8; ++k) reference.push_back(frame_file("run", k));
  // Simulate an interruption: two frames never made it.
  fs::remove(dir.path() / "run/f_002.png");
  fs::remove(dir.path() / "run/f_006.png");
  struct stat kept_before {};
  ASSERT_EQ(::stat((dir.path() / "run/f_004.png").c_str(), &kept_before), 0);

  const fs::path stats = dir.path() / "resume_stats.json";
  const Result resumed = pelt({"-o", out, "--resume", "--stats", stats.string()});
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  for (int k = 0; k < 8; ++k) EXPECT_EQ(frame_file("run", k), reference[k]) << k;
  // Existing frames were skipped, not rewritten (a rewrite renames a new file into place).
  struct stat kept_after {};
  ASSERT_EQ(::stat((dir.path() / "run/f_004.png").c_str(), &kept_after), 0);
  EXPECT_EQ(kept_after.st_ino, kept_before.st_ino);
  const nlohmann::json j = nlohmann::json::parse(read_text(stats));
  ASSERT_EQ(j["frames"].size(), 2u);
  EXPECT_EQ(j["frames"][0]["frame"], 2);
  EXPECT_EQ(j["frames"][1]["frame"], 6);
  // Plain progress lines (stderr is a file here), one per rendered frame.
  EXPECT_NE(resumed.err.find("frame 2 done (1/2)"), std::string::npos) << resumed.err;
  EXPECT_NE(resumed.err.find("frame 6 done (2/2)"), std::string::npos) << resumed.err;
  // Nothing left: a second resume renders nothing.
  const Result again = pelt({"-o", out, "--resume"});
  EXPECT_EQ(again.code, 0);
  EXPECT_NE(again.err.find("nothing to render"), std::string::npos) << again.err;
}

// A folder at a frame's name is no finished frame: refused as without --resume, not skipped (a
// farm's re-queued job reported success and never rendered it). An empty file is no frame pelt
// wrote (its writes are atomic): another tool's, cut short, rendered again.
TEST_F(RenderCommand, ResumeRefusesAFolderAndRendersAnEmptyFileAgain) {
  const std::string out = (dir.path() / "run/f_###.png").string();
  fs::create_directories(dir.path() / "run/f_002.png");
  const Result folder = pelt({"-o", out, "--frames", "0:3", "--resume", "-q"});
  EXPECT_EQ(folder.code, 2);
  EXPECT_NE(folder.err.find("f_002.png: -o: is a folder, not a file"), std::string::npos) << folder.err;
  EXPECT_EQ(files("run"), std::vector<std::string>{"f_002.png"});
  fs::remove(dir.path() / "run/f_002.png");
  std::ofstream(dir.path() / "run/f_001.png").close();
  const Result empty = pelt({"-o", out, "--frames", "0:3", "--resume", "-q"});
  ASSERT_EQ(empty.code, 0) << empty.err;
  const Result alone = pelt({"-o", (dir.path() / "alone.png").string(), "--frame", "1", "-q"});
  ASSERT_EQ(alone.code, 0) << alone.err;
  EXPECT_EQ(frame_file("run", 1), read_text(dir.path() / "alone.png"));
}

// --stats may replace no input and no frame of the range, also where this run renders nothing
// (a shard past the range, a finished sequence resumed) or skips the frame (--resume, another
// shard's): each of these once wrote the statistics over the scene or a finished frame.
TEST_F(RenderCommand, StatsNeverReplaceAnInputOrAFrameOfTheRange) {
  const std::string scene_text = read_text(scene);
  const std::string out = (dir.path() / "run/f_###.png").string();
  const Result empty_shard = pelt({"-o", out, "--frames", "0:3", "--shard", "7/8", "--stats", scene.string(), "-q"});
  EXPECT_EQ(empty_shard.code, 2);
  EXPECT_NE(empty_shard.err.find("--stats: is an input of this render"), std::string::npos) << empty_shard.err;
  EXPECT_EQ(read_text(scene), scene_text);
  ASSERT_EQ(pelt({"-o", out, "--frames", "0:1", "-q"}).code, 0);
  const std::string frame0 = frame_file("run", 0);
  const std::string skipped = (dir.path() / "run/f_000.png").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--frames", "0:2", "--resume"}, std::vector<std::string>{"--frames", "0:1", "--resume"},
        std::vector<std::string>{"--frames", "0:3", "--shard", "1/2"}}) {
    std::vector<std::string> all{"-o", out, "--stats", skipped, "-q"};
    all.insert(all.end(), args.begin(), args.end());
    const Result r = pelt(all);
    EXPECT_EQ(r.code, 2) << args[1];
    EXPECT_NE(r.err.find("--stats: is also where -o writes"), std::string::npos) << r.err;
    EXPECT_EQ(frame_file("run", 0), frame0) << args[1];
  }
  // A number in the name that is no frame of the range is no clash.
  const Result apart = pelt({"-o", out, "--frames", "0:1", "--resume", "--stats",
                             (dir.path() / "run/f_007.png").string(), "-q"});
  EXPECT_EQ(apart.code, 0) << apart.err;
}

// Starts a render of two slow frames to `out`/f_#.png and waits until frame 0's file is in place,
// so that a signal sent then comes while frame 1, the last, renders (half a second or more). False
// when pelt ended first.
bool in_the_last_frame(TempDir& dir, const fs::path& out, Child& c) {
  const fs::path slow = dir.write("slow.json", R"({"pelt": 1, "image": {"width": 640, "height": 480},
  "camera": {"eye": [2.5, 1.5, 3.5], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "intensity": 0.3}],
  "objects": [{"mesh": "box:2", "material": {"type": "lambert"}, "fur": {"shells": 4, "texture_size": 32, "length": 0.3}}],
  "animation": {"frames": 2, "fps": 12}})");
  c = start_pelt({"render", slow.string(), "-o", (out / "f_#.png").string(), "--spp", "16", "--sort", "exact",
                  "--threads", "1"},
                 dir.path());
  int status = 0;
  pid_t ended = 0;
  while (!fs::exists(out / "f_0.png") && (ended = ::waitpid(c.pid, &status, WNOHANG)) == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return ended == 0;
}

// A signal during the last frame: that frame is finished, as any frame in flight is, and the exit
// status still reports the signal (it was 0, so a script looping over renders ran on after a
// Ctrl-C, and a farm saw a pre-empted job succeed).
TEST_F(RenderCommand, ASignalDuringTheLastFrameIsReported) {
  const fs::path out = dir.path() / "last";
  Child c;
  ASSERT_TRUE(in_the_last_frame(dir, out, c)) << "pelt ended before its first frame was written: " << read_text(c.err);
  ::kill(c.pid, SIGINT);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("interrupted during the last frame (1): every frame was written"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "f_1.png"));
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temporary left behind: " << e.path();
}

// A signal pelt was started ignoring stays ignored (a shell starts a background job with SIGINT
// ignored): a SIGINT while the last frame renders changes nothing, and every frame is written.
// Not ignored, the same SIGINT stops it (ASignalDuringTheLastFrameIsReported).
TEST_F(RenderCommand, ASignalIgnoredAtStartStaysIgnored) {
  const fs::path out = dir.path() / "ignored";
  struct sigaction ignore {}, previous {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  ::sigaction(SIGINT, &ignore, &previous);  // inherited through fork and exec
  Child c;
  const bool running = in_the_last_frame(dir, out, c);
  ::sigaction(SIGINT, &previous, nullptr);
  ASSERT_TRUE(running) << "pelt ended before its first frame was written: " << read_text(c.err);
  ::kill(c.pid, SIGINT);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("interrupted"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "f_1.png"));
}

// Whether process `pid` catches `sig` now (its SigCgt mask in /proc): its handler is installed.
bool catches(pid_t pid, int sig) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1u;
  return false;
}

// A signal during the scene's set-up (here the strand textures of 32 shells of 1024 x 1024
// texels: two seconds on one thread) ends pelt at once, saying so, with nothing written: it was
// ended by the signal's default action, silent in a farm's log. The signal is sent once pelt
// catches it (a fixed 0.3 s wait lost the race to a sanitized start on a loaded machine).
TEST_F(RenderCommand, ASignalDuringTheSetUpIsReported) {
  const fs::path slow = dir.write("slow_setup.json", R"({"pelt": 1, "image": {"width": 64, "height": 48},
  "camera": {"eye": [2.5, 1.5, 3.5], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "intensity": 0.3}],
  "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
               "fur": {"shells": 32, "texture_size": 1024, "length": 0.3}}]})");
  const fs::path out = dir.path() / "setup";
  Child c = start_pelt({"render", slow.string(), "-o", (out / "f.png").string(), "--stats", (out / "s.json").string(),
                        "--threads", "1"},
                       dir.path());
  int status = 0;
  pid_t ended = 0;
  while (!catches(c.pid, SIGTERM) && (ended = ::waitpid(c.pid, &status, WNOHANG)) == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_EQ(ended, 0) << "pelt ended before it caught SIGTERM: " << read_text(c.err);
  ::kill(c.pid, SIGTERM);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 143) << r.err;
  EXPECT_NE(r.err.find("pelt: interrupted (SIGTERM): stopped at once; nothing more is written"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("scene set up in"), std::string::npos) << "the signal came after the set-up: " << r.err;
  EXPECT_FALSE(fs::exists(out)) << "the set-up writes nothing";
}

TEST_F(RenderCommand, CtrlCStopsAfterTheFrameInFlight) {
  const int frames = 20000;
  const fs::path out = dir.path() / "int";
  Child c;
  ASSERT_TRUE(start_long_render(out / "f_#####.png", [&] { return fs::exists(out / "f_00000.png"); }, c))
      << "pelt ended before its first frame: " << read_text(c.err);
  ::kill(c.pid, SIGINT);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("interrupted after frame"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
  size_t count = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << "temporary left behind: " << name;
    EXPECT_GT(fs::file_size(e.path()), 0u) << name;
    ++count;
  }
  EXPECT_GE(count, 1u);
  EXPECT_LT(count, size_t(frames));
  // Frames done are contiguous from the start: the render stopped, it did not skip.
  for (size_t k = 0; k < count; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "f_%05zu.png", k);
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
}

// A farm's scheduler pre-empts a job with SIGTERM: it stops like Ctrl-C, after the frame in flight,
// with the shell's status for that signal.
TEST_F(RenderCommand, SigtermStopsAfterTheFrameInFlight) {
  const fs::path out = dir.path() / "term";
  Child c;
  ASSERT_TRUE(start_long_render(out / "f_#####.png", [&] { return fs::exists(out / "f_00000.png"); }, c))
      << "pelt ended before its first frame: " << read_text(c.err);
  ::kill(c.pid, SIGTERM);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 128 + SIGTERM) << r.err;
  EXPECT_NE(r.err.find("interrupted after frame"), std::string::npos) << r.err;
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temporary left behind: " << e.path();
}

// A second signal ends the process at once, but not before the temporaries of writes in flight
// are gone: a GIF's temporary exists for the whole render, so two signals always find one. The
// handler is installed before the temporary is created, so no wait is needed once it exists (a
// 50 ms wait here once lost that race on a loaded CI machine: the process died of the signal).
TEST_F(RenderCommand, ASecondSignalLeavesNoTemporaryBehind) {
  const fs::path out = dir.path() / "twice";
  fs::create_directories(out);
  auto temp_exists = [&] {
    for (const auto& e : fs::directory_iterator(out))
      if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
    return false;
  };
  Child c;
  ASSERT_TRUE(start_long_render(out / "a.gif", temp_exists, c)) << "pelt ended before it began the GIF: " << read_text(c.err);
  ::kill(c.pid, SIGINT);
  ::kill(c.pid, SIGINT);
  const Result r = wait_child(c);
  EXPECT_EQ(r.code, 128 + SIGINT) << r.err;
  EXPECT_FALSE(temp_exists());
  EXPECT_FALSE(fs::exists(out / "a.gif"));
}

// A run that fails, or that a signal ends, before writing into the folders it made for its
// outputs takes them back (until 2026-11-28 they stayed, empty); folders that were there stay.
TEST_F(RenderCommand, ARunThatFailsTakesBackTheFoldersItMade) {
  dir.write("afile", "");
  const fs::path blocked = dir.path() / "afile" / "f.png";  // its folder is a regular file
  const Result r = pelt({"-o", blocked.string(), "--frame", "0", "--stats", (dir.path() / "st/deep/s.json").string(), "-q"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("-o: cannot create folder"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "st")) << "the --stats folder made for the run stayed";
  fs::create_directories(dir.path() / "kept");
  const Result k = pelt({"-o", blocked.string(), "--frame", "0", "--stats", (dir.path() / "kept/s.json").string(), "-q"});
  EXPECT_EQ(k.code, 2) << k.err;
  EXPECT_TRUE(fs::is_directory(dir.path() / "kept"));

  // A benchmark stops at once on a signal: its --json folder, made before the frames, goes too.
  const fs::path json = dir.path() / "bench/deep/fps.json";
  Child c = start_pelt({"bench", "fps", "--scenes", "box", "--threads", "1", "--width", "64", "--height", "48",
                        "--frames", "100000", "--json", json.string()},
                       dir.path());
  int status = 0;
  pid_t ended = 0;
  while (!fs::exists(json.parent_path()) && (ended = ::waitpid(c.pid, &status, WNOHANG)) == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_EQ(ended, 0) << "pelt ended before it made the folder: " << read_text(c.err);
  ::kill(c.pid, SIGINT);
  const Result b = wait_child(c);
  EXPECT_EQ(b.code, 128 + SIGINT) << b.err;
  EXPECT_FALSE(fs::exists(dir.path() / "bench")) << "the --json folder made for the run stayed";
}

// A furry box in wind, still (no animation block) or animated at `fps`.
std::string windy_box(const std::string& wind, const std::string& animation) {
  return R"({"pelt": 1, "image": {"width": 40, "height": 30},
  "camera": {"eye": [2.5, 1.5, 3.5], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "intensity": 0.3}],
  "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
               "fur": {"shells": 4, "texture_size": 32, "length": 0.3)" + wind + R"(}}])" + animation + "}";
}

// A still shows the wind it names (the wind pose); the swing between the gravity and wind poses
// runs on the scene's clock in seconds, so the same instant looks the same at any fps. Before,
// a still showed no wind at all and the swing counted frames.
TEST_F(RenderCommand, WindShowsInAStillAndSwingsOnTheSceneClock) {
  const std::string wind = R"(, "wind": {"direction": [1, 0, 0], "strength": 3, "gust_frequency": 0.7, "gust_scale": 0.5})";
  auto render = [&](const std::string& name, const std::string& text, int frame) {
    const fs::path file = dir.write(name + ".json", text);
    const fs::path out = dir.path() / "wind" / (name + ".png");
    const Result r = run_pelt({"render", file.string(), "-o", out.string(), "--frame", std::to_string(frame), "-q"},
                              dir.path());
    EXPECT_EQ(r.code, 0) << r.err;
    return read_text(out);
  };
  const std::string calm = render("calm", windy_box("", ""), 0);
  const std::string windy = render("windy", windy_box(wind, ""), 0);
  // Compared as booleans: a failure prints the files' names, not their bytes.
  EXPECT_FALSE(windy.empty());
  EXPECT_TRUE(windy != calm) << "the still shows no wind";
  const std::string at24 = render("fps24", windy_box(wind, R"(, "animation": {"frames": 30, "fps": 24})"), 5);
  const std::string at48 = render("fps48", windy_box(wind, R"(, "animation": {"frames": 30, "fps": 48})"), 10);
  EXPECT_TRUE(at24 == at48) << "fps24.png (frame 5) and fps48.png (frame 10) show different instants";
  EXPECT_TRUE(at24 != render("fps48_early", windy_box(wind, R"(, "animation": {"frames": 30, "fps": 48})"), 5));
}

// The scene's set-up is reported before the frames, whose lines count their own time only (a
// farm's log showed a 0.03 s frame for a run of a second).
TEST_F(RenderCommand, TheSetUpIsReportedBeforeTheFrames) {
  const Result r = pelt({"-o", (dir.path() / "s/a.png").string(), "--frame", "0"});
  ASSERT_EQ(r.code, 0) << r.err;
  const size_t setup = r.err.find("pelt: scene set up in ");
  const size_t frame = r.err.find("frame 0 done (1/1)");
  ASSERT_NE(setup, std::string::npos) << r.err;
  ASSERT_NE(frame, std::string::npos) << r.err;
  EXPECT_LT(setup, frame) << r.err;
  const Result quiet = pelt({"-o", (dir.path() / "s/b.png").string(), "--frame", "0", "-q"});
  EXPECT_EQ(quiet.err, "");
}

// A mistyped command is named, with the nearest one (CLI11 said "A subcommand is required"
// to a user who had typed one), as is a missing one.
TEST_F(RenderCommand, AMistypedCommandIsNamed) {
  const Result typo = run_pelt({"rendr", scene.string(), "-o", (dir.path() / "out/a.png").string()}, dir.path());
  EXPECT_EQ(typo.code, 2);
  EXPECT_EQ(typo.err, "pelt: error: unknown command `rendr` for `pelt` (did you mean `render`?); the commands are "
                      "render, info, bench, tradeoff\n");
  const Result sub = run_pelt({"bench", "fsp"}, dir.path());
  EXPECT_EQ(sub.code, 2);
  EXPECT_NE(sub.err.find("pelt: error: unknown command `fsp` for `pelt bench` (did you mean `fps`?)"), std::string::npos)
      << sub.err;
  const Result none = run_pelt({}, dir.path());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("pelt: error: `pelt` needs a command: render, info, bench, tradeoff"), std::string::npos)
      << none.err;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

// GIF counts a frame's delay in whole hundredths of a second in 16 bits: a slower animation
// is refused up front rather than written with a wrapped delay, a faster one rather than with
// delay 0 (OIIO's int(100 / fps)), which viewers play at their own pace.
TEST_F(RenderCommand, AGifOutsideItsDelayFieldIsRefused) {
  auto gif_at = [&](const std::string& fps) {
    std::string text = animated_scene(2);
    const std::string key = R"("fps": 12)";
    text.replace(text.find(key), key.size(), R"("fps": )" + fps);
    const fs::path scene_file = dir.write("fps.json", text);
    return run_pelt({"render", scene_file.string(), "-o", (dir.path() / "g/a.gif").string()}, dir.path());
  };
  const Result slow = gif_at("0.001");
  EXPECT_EQ(slow.code, 2) << slow.err;
  EXPECT_NE(slow.err.find("fps.json: animation.fps: a GIF frame lasts at most 655.35 s"), std::string::npos)
      << slow.err;
  const Result fast = gif_at("200");
  EXPECT_EQ(fast.code, 2) << fast.err;
  EXPECT_NE(fast.err.find("fps.json: animation.fps: a GIF frame lasts at least 1/100 s"), std::string::npos)
      << fast.err;
  EXPECT_FALSE(fs::exists(dir.path() / "g"));
  // 100 fps, a delay of 1/100 s, is written, with a note that browsers slow it down.
  const Result ok = gif_at("100");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.err.find("most web browsers play as 1/10 s"), std::string::npos) << ok.err;
}

// A background of alpha below 1 is for compositing: a translucent pixel's file colour is the
// surface's own (PNG straight, EXR premultiplied), never tinted by the background's colour
// (the planes used to start from the straight background, which src-over then mixed in),
// and a supersampled edge averages coverage, not the invisible background's colour.
TEST_F(RenderCommand, ATransparentBackgroundAddsNoColour) {
  auto scene_with = [&](const std::string& name, const std::string& background, const std::string& material,
                        double scale) {
    return dir.write(name, R"({"pelt": 1, "image": {"width": 8, "height": 8, "background": )" + background + R"(},
      "camera": {"eye": [0, 0, 5], "target": [0, 0, 0]}, "lights": [{"type": "ambient"}],
      "objects": [{"mesh": "plane:1", "transform": {"rotate_deg": [90, 0, 0], "scale": )" + std::to_string(scale) +
                                  R"(}, "material": )" + material + "}]}");
  };
  const std::string half_skin = R"({"type": "skin", "skin": {"Opacity": 0.5}})";
  const fs::path red = scene_with("red.json", "[1, 0, 0, 0]", half_skin, 3.0);
  const fs::path black = scene_with("black.json", "[0, 0, 0, 0]", half_skin, 3.0);
  const fs::path opaque = scene_with("opaque.json", "[0, 0, 0, 1]", R"({"type": "skin"})", 3.0);
  for (const fs::path& s : {red, black, opaque})
    for (const char* ext : {".png", ".exr"}) {
      const Result r = run_pelt({"render", s.string(), "-o", fs::path(s).replace_extension(ext).string(), "-q"},
                                dir.path());
      ASSERT_EQ(r.code, 0) << r.err;
    }
  const io::ImageRGBA want_png = io::read_image_rgba(dir.path() / "opaque.png");
  const io::ImageRGBA want_exr = io::read_image_rgba(dir.path() / "opaque.exr");
  for (const char* name : {"red", "black"}) {
    const io::ImageRGBA png = io::read_image_rgba(dir.path() / (std::string(name) + ".png"));
    const io::ImageRGBA exr = io::read_image_rgba(dir.path() / (std::string(name) + ".exr"));
    const float* p = png.pixel(4, 4);
    const float* q = want_png.pixel(4, 4);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], q[c], 0.006f) << name << " PNG channel " << c;
    EXPECT_NEAR(p[3], 128.0f / 255.0f, 1e-6f) << name;
    const float* e = exr.pixel(4, 4);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], 0.5f * want_exr.pixel(4, 4)[c], 1e-5f) << name << " EXR " << c;
    EXPECT_EQ(e[3], 0.5f) << name;
  }
  // A green square's edges at 4 samples a pixel over transparent red: green, at the coverage.
  const fs::path square = scene_with("square.json", "[1, 0, 0, 0]", R"({"type": "unlit", "color": [0, 1, 0]})", 0.78);
  const Result r = run_pelt({"render", square.string(), "-o", (dir.path() / "square.png").string(), "--spp", "4", "-q"},
                            dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const io::ImageRGBA img = io::read_image_rgba(dir.path() / "square.png");
  int edges = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const float* p = img.pixel(x, y);
      if (p[3] == 0.0f) continue;
      EXPECT_EQ(p[0], 0.0f) << x << "," << y << " alpha " << p[3];
      EXPECT_EQ(p[1], 1.0f) << x << "," << y << " alpha " << p[3];
      edges += p[3] < 1.0f;
    }
  EXPECT_GT(edges, 8);
}

// A normal_blur skin whose radius reaches too many vertex pairs is refused with exit 2, naming
// the object's radius and --max-blur-pairs, and no image is written; the flag raises the budget.
TEST_F(RenderCommand, BlurPairsOverTheBudgetAreRefusedNamingTheRadius) {
  const fs::path skin = dir.write("skin.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "sphere:16", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur",
                   "normal_blur_radius": [1e6, 1e6, 1e6]}}}]})");
  const auto render = [&](const std::string& budget) {
    return run_pelt({"render", skin.string(), "-o", (dir.path() / "b/a.png").string(), "--max-blur-pairs", budget},
                    dir.path());
  };
  const Result over = render("12995");  // sphere:16: 114 positions, each reaching all 114
  EXPECT_EQ(over.code, 2) << over.err;
  EXPECT_NE(over.err.find("skin.json: objects[0].material.skin.normal_blur_radius: reaches about 12996 "),
            std::string::npos)
      << over.err;
  EXPECT_NE(over.err.find("(raise it with --max-blur-pairs)"), std::string::npos) << over.err;
  EXPECT_FALSE(fs::exists(dir.path() / "b/a.png"));
  const Result at = render("12996");
  EXPECT_EQ(at.code, 0) << at.err;
  EXPECT_TRUE(fs::exists(dir.path() / "b/a.png"));
}

// `pelt info` names the maps each object draws, whose they are, and where the mesh file places
// them, in the file's own uvs (an OBJ's MTL options as written, though pelt flips OBJ's v).
TEST_F(RenderCommand, InfoNamesTheMapsAndWhereTheMeshFilePlacesThem) {
  const uint8_t px[3] = {200, 100, 50};
  io::write_image_atomic(dir.path() / "tex.png", 1, 1, 3, io::PixelType::u8, px);
  dir.write("m.mtl", "newmtl m\nmap_Kd -s 2 3 -o 0.25 0.5 -clamp on tex.png\nnorm tex.png\n");
  dir.write("q.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n");
  const fs::path scene = dir.write("maps.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "q.obj", "material": {"type": "lambert"}},
                  {"mesh": "q.obj", "material": {"type": "lambert", "color_map": "tex.png"}},
                  {"mesh": "sphere:8", "material": {"type": "lambert"}}]})");
  const Result r = run_pelt({"info", scene.string()}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  [0] objects[0]: mesh q.obj, material lambert\n       maps: colour (the mesh file's: clamp u, "
                       "clamp v; u' = 2 u + 0.25, v' = 3 v + 0.5), normal (the mesh file's: as the uvs say)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("       maps: colour (the scene's), normal (the mesh file's: as the uvs say)\n"), std::string::npos)
      << r.out;
  const size_t third = r.out.find("  [2] ");
  ASSERT_NE(third, std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("maps:", third), std::string::npos) << r.out;
}

// An OBJ's map_d is named where `pelt info` says what blends the faces: beside map_Kd, the colour
// map's alpha carries both; alone, map_d's dissolve is the alpha of a white colour map. With MTL
// `d`, its factor. Until 2026-11-28 info named only "the colour map's alpha".
TEST_F(RenderCommand, InfoNamesAnObjDissolveMap) {
  const uint8_t px[3] = {200, 100, 50};
  io::write_image_atomic(dir.path() / "c.png", 1, 1, 3, io::PixelType::u8, px);
  io::write_image_atomic(dir.path() / "d.png", 1, 1, 1, io::PixelType::u8, px);
  dir.write("m.mtl", "newmtl pair\nmap_Kd c.png\nmap_d d.png\nnewmtl alone\nd 0.5\nmap_d d.png\n");
  dir.write("q.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl pair\nf 1/1 2/2 3/3\n"
                     "usemtl alone\nf 1/1 3/3 2/2\n");
  const fs::path scene = dir.write("d.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "q.obj", "material": {"type": "lambert"}}]})");
  const Result r = run_pelt({"info", scene.string()}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("         `pair`, 1 triangle: colour (the mesh file's: as the uvs say); blended by the colour "
                       "map's alpha with its map_d d.png\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("         `alone`, 1 triangle: colour (the mesh file's: as the uvs say); blended by map_d "
                       "d.png x 0.5\n"),
            std::string::npos)
      << r.out;
}

// A mesh file whose materials name several maps: `pelt info` lists each set, by its first
// material, with its triangles and maps; faces of no material and of a material without maps
// draw alike.
TEST_F(RenderCommand, InfoListsTheMapsOfEachMaterial) {
  const uint8_t px[3] = {200, 100, 50};
  io::write_image_atomic(dir.path() / "tex.png", 1, 1, 3, io::PixelType::u8, px);
  dir.write("m.mtl", "newmtl skin\nmap_Kd tex.png\nnewmtl eyes\nmap_Kd -s 2 2 tex.png\nnorm tex.png\nnewmtl bare\n");
  dir.write("q.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 3/3 2/2\nusemtl skin\nf 1/1 2/2 3/3\nusemtl eyes\nf 1/1 3/3 4/4\nusemtl bare\n"
                     "f 2/2 3/3 4/4\nusemtl skin\nf 1/1 2/2 4/4\n");
  const fs::path scene = dir.write("sets.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "q.obj", "material": {"type": "lambert"}}]})");
  const Result r = run_pelt({"info", scene.string()}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  // The face before any `usemtl` and `bare`'s draw alike (no map): one set.
  EXPECT_NE(r.out.find("       maps by material (3 parts):\n"
                       "         (no material), 2 triangles: none\n"
                       "         `skin`, 2 triangles: colour (the mesh file's: as the uvs say)\n"
                       "         `eyes`, 1 triangle: colour (the mesh file's: u' = 2 u, v' = 2 v), normal (the mesh "
                       "file's: as the uvs say)\n"),
            std::string::npos)
      << r.out;
}

// `pelt info` prints a normal blur's estimated pairs beside the budget: the figure the budget check
// refuses with once the budget is one pair lower. sphere:64 has 1986 welded vertices, more than the
// 64 the estimate samples, so the figure is an estimate.
TEST_F(RenderCommand, InfoPrintsTheBlurPairsTheBudgetChecks) {
  const fs::path skin = dir.write("blur.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "sphere:64", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur",
                   "normal_blur_radius": [0.2, 0.1, 0.05]}}}]})");
  const auto info = [&](const std::vector<std::string>& flags) {
    std::vector<std::string> args = {"info", skin.string()};
    args.insert(args.end(), flags.begin(), flags.end());
    return run_pelt(args, dir.path());
  };
  const Result plain = info({});
  ASSERT_EQ(plain.code, 0) << plain.err;
  const std::string head = "       normal blur: radius 0.2, 0.1, 0.05 reaches about ";
  const size_t at = plain.out.find(head);
  ASSERT_NE(at, std::string::npos) << plain.out;
  const uint64_t pairs = std::stoull(plain.out.substr(at + head.size()));
  ASSERT_GT(pairs, 1986u);  // each source settles itself and some neighbours
  EXPECT_NE(plain.out.find(std::to_string(pairs) + " (source, neighbour) vertex pairs, "), std::string::npos) << plain.out;
  EXPECT_NE(plain.out.find(" % of the budget of 4294967296 (--max-blur-pairs)\n"), std::string::npos) << plain.out;
  const Result over = info({"--max-blur-pairs", std::to_string(pairs - 1)});
  EXPECT_EQ(over.code, 2) << over.err;
  EXPECT_NE(over.err.find("blur.json: objects[0].material.skin.normal_blur_radius: reaches about " +
                          std::to_string(pairs) + " (source, neighbour) vertex pairs, more than the budget of " +
                          std::to_string(pairs - 1) + " pairs (raise it with --max-blur-pairs)"),
            std::string::npos)
      << over.err;
  EXPECT_EQ(over.out.find("normal blur"), std::string::npos) << over.out;
  // info runs only the sampled searches (describe_only), never the blur: at a budget of exactly
  // the estimate it describes the scene, where a render's own searches find the sphere denser at
  // its poles than the samples say and refuse it.
  const Result at_estimate = info({"--max-blur-pairs", std::to_string(pairs)});
  ASSERT_EQ(at_estimate.code, 0) << at_estimate.err;
  const Result render = run_pelt({"render", skin.string(), "-o", (dir.path() / "blur.png").string(),
                                  "--max-blur-pairs", std::to_string(pairs)},
                                 dir.path());
  EXPECT_EQ(render.code, 2) << render.err;
  EXPECT_NE(render.err.find("than the estimate from sampled vertices said"), std::string::npos) << render.err;
  EXPECT_FALSE(fs::exists(dir.path() / "blur.png"));
  const Result under = info({"--max-blur-pairs", std::to_string(2 * pairs)});
  ASSERT_EQ(under.code, 0) << under.err;
  EXPECT_NE(under.out.find("about " + std::to_string(pairs) + " (source, neighbour) vertex pairs, 50 % of the " +
                           "budget of " + std::to_string(2 * pairs) + " (--max-blur-pairs)\n"),
            std::string::npos)
      << under.out;
  // Radius 0 everywhere searches nothing: said so, not "about 0 pairs".
  const fs::path zero = dir.write("zero.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "sphere:64", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur",
                   "normal_blur_radius": [0, 0, 0]}}}]})");
  const Result none_searched = run_pelt({"info", zero.string()}, dir.path());
  ASSERT_EQ(none_searched.code, 0) << none_searched.err;
  EXPECT_NE(none_searched.out.find("       normal blur: radius 0, 0, 0, no search: the normals as they are\n"),
            std::string::npos)
      << none_searched.out;
  // Without a blur there is no line.
  const fs::path lambert = dir.write("lambert.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": "sphere:64", "material": {"type": "lambert"}}]})");
  const Result none = run_pelt({"info", lambert.string()}, dir.path());
  ASSERT_EQ(none.code, 0) << none.err;
  EXPECT_EQ(none.out.find("normal blur"), std::string::npos) << none.out;
}

// `pelt info` reports the estimate --max-memory is checked against: a budget a little under its
// figure refuses the render, one a little over lets it run.
// ... at the render's own size and threads, which info takes as render does (until 2026-11-27 it
// estimated the scene's size on every core only).
// Of an animation, info gives the figure for its frames as files and for one GIF; a still (one
// frame) holds one float image less, 16 bytes a pixel.
TEST_F(RenderCommand, InfoReportsTheEstimateTheBudgetChecks) {
  for (const auto& [size, pixels] :
       {std::pair{std::vector<std::string>{}, 48LL * 36},
        std::pair{std::vector<std::string>{"--width", "300", "--height", "200", "--threads", "1"}, 300LL * 200}}) {
    std::vector<std::string> args = {"info", scene.string()};
    args.insert(args.end(), size.begin(), size.end());
    const Result info = run_pelt(args, dir.path());
    ASSERT_EQ(info.code, 0) << info.err;
    const size_t at = info.out.find("memory     about ");
    ASSERT_NE(at, std::string::npos) << info.out;
    const long long bytes = std::stoll(info.out.substr(at + std::string("memory     about ").size()));  // "N bytes (..)"
    ASSERT_GT(bytes, 1000);
    const size_t gif_at = info.out.find(") written as one GIF");
    ASSERT_NE(gif_at, std::string::npos) << info.out;
    const size_t gif_from = info.out.rfind("           ", gif_at) + 11;
    const long long gif = std::stoll(info.out.substr(gif_from));
    EXPECT_EQ(gif - bytes, pixels * 44) << info.out;  // render::kGifBytesPerPixel
    // Exact: info's figures are the render's budget checks to the byte.
    auto render_with = [&](const std::vector<std::string>& output, long long budget) {
      std::vector<std::string> r = output;
      r.insert(r.end(), {"--max-memory", std::to_string(budget)});
      r.insert(r.end(), size.begin(), size.end());
      return pelt(r);
    };
    const std::vector<std::string> frames = {"-o", (dir.path() / "m/a_#.png").string(), "--frames", "0:1"};
    const std::vector<std::string> one_gif = {"-o", (dir.path() / "m/a.gif").string(), "--frames", "0:1"};
    const std::vector<std::string> still = {"-o", (dir.path() / "m/a.png").string(), "--frame", "0"};
    for (const auto& [output, need] : {std::pair{frames, bytes}, std::pair{one_gif, gif},
                                       std::pair{still, bytes - pixels * 16}}) {
      const Result under = render_with(output, need - 1);
      EXPECT_EQ(under.code, 2) << output[1] << " " << under.err;
      EXPECT_NE(under.err.find("this render needs an estimated " + std::to_string(need) + " bytes"), std::string::npos)
          << under.err;
      const Result over = render_with(output, need);
      EXPECT_EQ(over.code, 0) << output[1] << " " << over.err;
    }
  }
}

// `pelt info` says in how many frames gravity and wind are computed, and a render's stats agree:
// a wind or gravity of strength 0 is none, a keyed wind strength changes the wind every frame
// but frame 0 (at rest in the swing).
TEST_F(RenderCommand, InfoCountsTheFramesThatComputeEachForceAsTheRenderDoes) {
  struct Case {
    const char* fur;
    const char* tracks;
    const char* line;
    int gravity, wind;
  };
  const Case cases[] = {
      {R"("gravity": {"strength": 0}, "wind": {"strength": 0})", "",
       "gravity computed in 0 of 4 frames, wind computed in 0 of 4 frames", 0, 0},
      {R"("gravity": {}, "wind": {"gust_scale": 0})", "", "gravity computed in 1 of 4 frames, wind computed in 1 of 4 frames",
       1, 1},
      {R"("wind": {"gust_scale": 0})",
       R"(, "fur": [{"object": 0, "wind": {"strength": {"keys": [{"frame": 0, "value": 0.5}, {"frame": 3, "value": 2}]}}}])",
       "gravity off, wind computed in 3 of 4 frames", 0, 3},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    const fs::path file = dir.write("forces.json", std::string(R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "animation": {"frames": 4)") + c.tracks + R"(},
      "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
                   "fur": {"shells": 4, "texture_size": 16, )" + c.fur + "}}]}");
    const Result info = run_pelt({"info", file.string()}, dir.path());
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find(c.line), std::string::npos) << info.out;
    const fs::path stats = dir.path() / "forces_stats.json";
    const Result r = run_pelt({"render", file.string(), "-o", (dir.path() / "forces_#.png").string(), "-q", "--stats",
                               stats.string()},
                              dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(read_text(stats));
    int gravity = 0, wind = 0;
    for (const nlohmann::json& f : j["frames"])
      for (const nlohmann::json& st : f["stages"]) {
        gravity += st["name"] == "gravity" && st["ran"] == true;
        wind += st["name"] == "wind" && st["ran"] == true;
      }
    EXPECT_EQ(gravity, c.gravity);
    EXPECT_EQ(wind, c.wind);
  }
}

// `pelt info` says where a MASK part cuts everything, so that neither it nor the fur over it is
// drawn, and what that leaves of the fur: the faces that grow none, or, every part cut away,
// nothing computed in any frame (the render agrees: no gravity or wind stage runs), where it
// counted the frames that would compute gravity and wind.
TEST_F(RenderCommand, InfoSaysWhatAPartCutAwayWholeLeavesOfTheFur) {
  const std::string back = R"({"name":"back","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0]}})";
  for (const uint8_t front_alpha : {255, 0}) {
    SCOPED_TRACE(int(front_alpha));
    const uint8_t px[4] = {0, 255, 0, front_alpha};
    io::write_image_atomic(dir.path() / "front.png", 1, 1, 4, io::PixelType::u8, px);
    std::string gltf =
        render::test::two_quads_gltf(R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})");
    const std::string from = R"("materials":[{"name":"back"},)";
    gltf.replace(gltf.find(from), from.size(), R"("materials":[)" + back + ",");
    dir.write("quads.gltf", gltf);
    const fs::path file = dir.write("cut.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]}, "animation": {"frames": 3},
      "objects": [{"mesh": "quads.gltf", "material": {"type": "lambert"},
                   "fur": {"shells": 4, "texture_size": 16, "gravity": {}, "wind": {}}}]})");
    const Result info = run_pelt({"info", file.string()}, dir.path());
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("`back`, 2 triangles: cut out where the factor's alpha 0 is below 0.5, which is "
                            "everywhere: neither the part nor fur over it is drawn\n"),
              std::string::npos)
        << info.out;
    const bool whole = front_alpha == 0;
    EXPECT_EQ(info.out.find("fur: 4 shells, fins silhouette, cut away whole with the surface: nothing computed or "
                            "drawn\n") != std::string::npos,
              whole)
        << info.out;
    EXPECT_EQ(info.out.find("       cut away 2 of 4 base faces grow none (their parts cut everywhere)\n") !=
                  std::string::npos,
              !whole)
        << info.out;
    EXPECT_EQ(info.out.find("gravity computed in") == std::string::npos, whole) << info.out;
    const fs::path stats = dir.path() / "cut_stats.json";
    const Result r = run_pelt(
        {"render", file.string(), "-o", (dir.path() / "cut_#.png").string(), "-q", "--stats", stats.string()},
        dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(read_text(stats));
    int forces = 0;
    for (const nlohmann::json& f : j["frames"])
      for (const nlohmann::json& st : f["stages"])
        forces += (st["name"] == "gravity" || st["name"] == "wind") && st["ran"] == true;
    EXPECT_EQ(forces == 0, whole);
  }
}

// A budget refusal names what set the value: the --shells flag, the --quality preset that changed
// it, or the scene's own fur block, in render and in info alike.
TEST_F(RenderCommand, ABudgetRefusalNamesTheFlagThatSetTheValue) {
  const fs::path furry = dir.write("furry.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "objects": [{"mesh": "box:2", "material": {"type": "lambert"}, "fur": {"shells": 16, "texture_size": 16}}]})");
  struct Case {
    std::vector<std::string> flags;
    const char* message;
  };
  const Case cases[] = {
      {{"--shells", "8", "--max-shells", "4"}, "pelt: error: --shells: 8 fur shells, more than the budget of 4"},
      {{"--quality", "reference", "--max-shells", "16"}, "pelt: error: --quality: 64 fur shells, more than the budget of 16"},
      {{"--max-shells", "4"}, "furry.json: objects[0].fur.shells: 16 fur shells, more than the budget of 4"},
  };
  for (const Case& c : cases)
    for (const char* command : {"render", "info"}) {
      std::vector<std::string> args = {command, furry.string()};
      if (std::string(command) == "render") args.insert(args.end(), {"-o", (dir.path() / "b/a.png").string()});
      args.insert(args.end(), c.flags.begin(), c.flags.end());
      const Result r = run_pelt(args, dir.path());
      EXPECT_EQ(r.code, 2) << command << ": " << r.err;
      EXPECT_NE(r.err.find(c.message), std::string::npos) << command << ": " << r.err;
    }
  EXPECT_FALSE(fs::exists(dir.path() / "b"));
}

// `pelt info` lists the fur's edges (one fin quad each per pair of layers) and, where a mesh is
// split at texture seams or hard edges, how many vertex copies were joined: the fin count is not
// 2 E (S - 1) of the file's own edges there. The built-in sphere is split at its seam (7 copies
// on sphere:16) and poles (15 beyond the first at each); the box is welded.
TEST_F(RenderCommand, InfoCountsTheFurEdgesAndTheJoinedCopies) {
  const fs::path sphere = dir.write("sphere.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "sphere:16", "material": {"type": "lambert"}, "fur": {"shells": 4}}]})");
  const Result split = run_pelt({"info", sphere.string()}, dir.path());
  ASSERT_EQ(split.code, 0) << split.err;
  EXPECT_NE(split.out.find("edges    336 (a fin quad each per pair of layers), 37 vertex copies (texture seams, hard "
                           "edges, box mapping) joined to the vertex they copy\n"),
            std::string::npos)
      << split.out;
  const Result welded = run_pelt({"info", (source_dir() / "tools/scenes/box_fur.json").string()}, dir.path());
  ASSERT_EQ(welded.code, 0) << welded.err;
  EXPECT_NE(welded.out.find("edges    882 (a fin quad each per pair of layers)\n"), std::string::npos) << welded.out;
}

// Fur coloured by the object's colour map, from the command line: info says so, the render draws;
// without a map the render is refused naming the field, exit 2, no image.
TEST_F(RenderCommand, FurTakesTheColourMapOnlyWhereThereIsOne) {
  ASSERT_EQ(pelt({"-o", (dir.path() / "map.png").string(), "--frame", "0", "-q"}).code, 0);
  const std::string fur = R"("fur": {"shells": 4, "texture_size": 32, "use_color_map": true})";
  const fs::path with = dir.write("with_map.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [3, 2, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "box:3", "material": {"type": "lambert", "color_map": "map.png"}, )" + fur + "}]}");
  const Result info = run_pelt({"info", with.string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("colour   root_color to tip_color x each face's colour map at the mesh's uvs (none: x 1)"), std::string::npos)
      << info.out;
  Result r = run_pelt({"render", with.string(), "-o", (dir.path() / "with.png").string(), "-q"}, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir.path() / "with.png"));
  const fs::path without = dir.write("without_map.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [3, 2, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "box:3", "material": {"type": "lambert"}, )" + fur + "}]}");
  r = run_pelt({"render", without.string(), "-o", (dir.path() / "without.png").string(), "-q"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(without.string() + ": objects[0].fur.use_color_map: true needs a colour map"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "without.png"));
}

// A length map from the command line: info names it and counts the faces it leaves bare (all of
// them for a black map, none for a white one); a map with a value out of range ends the render
// with exit 2 and no image.
TEST_F(RenderCommand, InfoCountsTheFacesALengthMapLeavesBare) {
  const uint8_t black[4] = {0, 0, 0, 0}, white[4] = {255, 255, 255, 255};
  io::write_image_atomic(dir.path() / "map.png", 2, 2, 1, io::PixelType::u8, black);
  io::write_image_atomic(dir.path() / "white.png", 2, 2, 1, io::PixelType::u8, white);
  const std::string head = R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [3, 2, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "box:3", "material": {"type": "lambert"}, "fur": {"shells": 4, "texture_size": 32, )";
  const fs::path scene_file = dir.write("length.json", head + R"("length_map": "map.png"}}]})");
  const Result info = run_pelt({"info", scene_file.string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("length   x the first channel of map.png at the mesh's uvs; "), std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("map.png at the mesh's uvs; 108 of 108 base faces grow none\n"), std::string::npos)
      << info.out;
  const fs::path whole = dir.write("white.json", head + R"("length_map": "white.png"}}]})");
  const Result white_info = run_pelt({"info", whole.string()}, dir.path());
  ASSERT_EQ(white_info.code, 0) << white_info.err;
  EXPECT_NE(white_info.out.find("; 0 of 108 base faces grow none\n"), std::string::npos) << white_info.out;
  const float over[4] = {0.5f, 1.5f, 0.5f, 0.5f};
  io::write_image_atomic(dir.path() / "over.exr", 2, 2, 1, io::PixelType::f32, over);
  const fs::path bad = dir.write("over.json", head + R"("length_map": "over.exr"}}]})");
  const Result r = run_pelt({"render", bad.string(), "-o", (dir.path() / "over.png").string(), "-q"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("over.exr: texel (1, 0) of the first channel is 1.5"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "over.png"));
}

// Where the strands lie and at what scale: on a uv-mapped mesh the factor its uvs were scaled by
// (the sphere's uvs span its whole surface once), on a mesh without uvs the projection's.
TEST_F(RenderCommand, InfoShowsWhereTheStrandsLie) {
  const fs::path sphere = dir.write("sphere2.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "sphere:16", "material": {"type": "lambert"}, "fur": {"shells": 4, "texture_repeat": 2}}]})");
  const Result mesh = run_pelt({"info", sphere.string()}, dir.path());
  ASSERT_EQ(mesh.code, 0) << mesh.err;
  EXPECT_NE(mesh.out.find("strands  on the mesh's uvs x "), std::string::npos) << mesh.out;
  // sqrt(A_p / A_uv) = 11.18 for the sphere's [0, 1] layout, times the repeat.
  EXPECT_NE(mesh.out.find("x 22.37 (texture_repeat 2)\n"), std::string::npos) << mesh.out;
  // The built-in box's uvs are the projection: kept as they are.
  const Result box = run_pelt({"info", (source_dir() / "tools/scenes/box_fur.json").string()}, dir.path());
  ASSERT_EQ(box.code, 0) << box.err;
  EXPECT_NE(box.out.find("strands  on the mesh's uvs x 1 (texture_repeat 1)\n"), std::string::npos) << box.out;
  // The bunny has no uvs: the box mapping, at the scale that lays as much texture on it as the
  // projection would.
  const Result bunny = run_pelt({"info", (source_dir() / "tools/scenes/bunny_wind.json").string()}, dir.path());
  ASSERT_EQ(bunny.code, 0) << bunny.err;
  EXPECT_NE(bunny.out.find("strands  box, "), std::string::npos) << bunny.out;
  EXPECT_NE(bunny.out.find(" texture repeats per scene unit (texture_repeat 1)\n"), std::string::npos) << bunny.out;
  // Asked for, the harness's projection: k = 2.449490 sqrt(3) / R texture units per scene unit, R = 1.
  const fs::path projected = dir.write("sphere3.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
    "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]}, "lights": [{"type": "ambient", "intensity": 0.5}],
    "objects": [{"mesh": "sphere:16", "material": {"type": "lambert"},
                 "fur": {"shells": 4, "texture_repeat": 2, "texture_coordinates": "projected"}}]})");
  const Result proj = run_pelt({"info", projected.string()}, dir.path());
  ASSERT_EQ(proj.code, 0) << proj.err;
  EXPECT_NE(proj.out.find("strands  projected, 8.485 texture repeats per scene unit (texture_repeat 2)\n"),
            std::string::npos)
      << proj.out;
}

// No output may overwrite what the render reads: the scene, a map, or another output. The
// refusal comes before any work and leaves every file as it was.
TEST_F(RenderCommand, OutputsNeverOverwriteInputsOrEachOther) {
  const std::string before = read_text(scene);
  Result r = pelt({"-o", (dir.path() / "c/a.png").string(), "--frame", "0", "--stats", scene.string()});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(scene.string() + ": --stats: is an input of this render"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(scene), before);
  EXPECT_FALSE(fs::exists(dir.path() / "c"));

  // A colour map named through another spelling of its folder is still the same file.
  ASSERT_EQ(pelt({"-o", (dir.path() / "maps/map.png").string(), "--frame", "0", "-q"}).code, 0);
  const std::string map = read_text(dir.path() / "maps/map.png");
  std::string textured = animated_scene(8);
  const std::string lambert = R"("material": {"type": "lambert", "color": [0.8, 0.5, 0.3]})";
  ASSERT_NE(textured.find(lambert), std::string::npos);
  textured.replace(textured.find(lambert), lambert.size(),
                   R"("material": {"type": "lambert", "color_map": "maps/../maps/map.png"})");
  const fs::path textured_scene = dir.write("textured.json", textured);
  r = run_pelt({"render", textured_scene.string(), "-o", (dir.path() / "maps/map.png").string(), "--frame", "0"},
               dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("-o: is an input of this render"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(dir.path() / "maps/map.png"), map);
}

// OpenImageIO is a module loaded on first use (tools/io/image_backend.h): a pelt without it
// still starts, and fails the first read or write that needs it like any bad output, naming the
// paths it tried. A PNG of a scene without maps needs none (libpng writes it, io/png_writer.h).
// Four OBJ triangles for the image module's tests: q.obj names no map, p.obj a PNG map (map.png),
// j.obj a JPEG map (map.jpg, the default scene's colour map), m.obj a TIFF map (map.tif), the PNG
// and the TIFF written here (the TIFF through the module).
void write_map_meshes(TempDir& dir) {
  dir.write("q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n");
  const std::string mapped = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n";
  dir.write("p.obj", "mtllib p.mtl\n" + mapped);
  dir.write("p.mtl", "newmtl m\nmap_Kd map.png\n");
  dir.write("m.obj", "mtllib m.mtl\n" + mapped);
  dir.write("m.mtl", "newmtl m\nmap_Kd map.tif\n");
  dir.write("j.obj", "mtllib j.mtl\n" + mapped);
  dir.write("j.mtl", "newmtl m\nmap_Kd map.jpg\n");
  dir.write("x.obj", "mtllib x.mtl\n" + mapped);
  dir.write("x.mtl", "newmtl m\nmap_Kd map.exr\n");
  fs::copy_file(source_dir() / "tools/data/LeePerrySmith/Map-COL.jpg", dir.path() / "map.jpg");
  const uint8_t px[3] = {200, 100, 50};
  io::write_image_atomic(dir.path() / "map.png", 1, 1, 3, io::PixelType::u8, px);
  io::write_image_atomic(dir.path() / "map.tif", 1, 1, 3, io::PixelType::u8, px);
  const float linear[3] = {0.6f, 0.2f, 0.05f};
  io::write_image_atomic(dir.path() / "map.exr", 1, 1, 3, io::PixelType::f32, linear);
}

// Renders a 16 x 16 scene of `mesh` (a lambert material, with `map` as its colour map where
// given) to `out` in `dir`, with `extra` options.
Result render_mesh(TempDir& dir, const std::string& mesh, const std::string& out, const std::string& map = "",
                   const std::vector<std::string>& extra = {}) {
  const std::string material = map.empty() ? "" : R"(, "color_map": ")" + map + "\"";
  const fs::path s = dir.write("s.json", R"({"pelt": 1, "image": {"width": 16, "height": 16},
      "objects": [{"mesh": ")" + mesh + R"(", "material": {"type": "lambert")" + material + "}}]}");
  std::vector<std::string> args = {"render", s.string(), "-o", (dir.path() / out).string(), "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_pelt(args, dir.path());
}

TEST_F(RenderCommand, WithoutItsImageModuleExitsWith2AndWritesNothing) {
  write_map_meshes(dir);  // before the module goes
  const std::string missing = (dir.path() / "nowhere" / "libpelt_oiio.so").string();
  ::setenv("PELT_IMAGE_MODULE", missing.c_str(), 1);
  const Result r = pelt({"-o", (dir.path() / "out/f.tif").string(), "--frame", "0", "-q"});
  const Result gif = pelt({"-o", (dir.path() / "out/a.gif").string(), "-q"});
  const Result png = pelt({"-o", (dir.path() / "png/f.png").string(), "--frame", "0", "-q"});
  // OpenEXR's library writes an EXR (io/exr_writer.h), the depth AOV's too.
  const Result exr = pelt({"-o", (dir.path() / "exr/f.exr").string(), "--frame", "0", "-q"});
  const Result depth = pelt({"-o", (dir.path() / "exr/d.exr").string(), "--frame", "0", "--aov", "depth", "-q"});
  // Nor does a mesh file that names no map, a PNG map (libpng reads it, io/png_reader.h), a JPEG
  // map (libjpeg reads it, io/jpeg_reader.h) or an EXR map (OpenEXR's library reads it,
  // io/exr_reader.h); a TIFF map needs the module.
  const auto mesh_render = [&](const std::string& mesh) { return render_mesh(dir, mesh, "mesh/" + mesh + ".png"); };
  const Result plain = mesh_render("q.obj"), png_map = mesh_render("p.obj"), jpeg_map = mesh_render("j.obj"),
               exr_map = mesh_render("x.obj"), mapped = mesh_render("m.obj");
  ::unsetenv("PELT_IMAGE_MODULE");
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(png_map.code, 0) << png_map.err;
  EXPECT_EQ(jpeg_map.code, 0) << jpeg_map.err;
  EXPECT_EQ(exr_map.code, 0) << exr_map.err;
  EXPECT_EQ(mapped.code, 2) << mapped.err;
  EXPECT_NE(mapped.err.find(missing), std::string::npos) << mapped.err;
  EXPECT_NE(mapped.err.find("map.tif"), std::string::npos) << mapped.err;
  EXPECT_EQ(files("mesh"), (std::vector<std::string>{"j.obj.png", "p.obj.png", "q.obj.png", "x.obj.png"}));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("f.tif"), std::string::npos) << r.err;
  EXPECT_EQ(gif.code, 2) << gif.err;
  EXPECT_TRUE(!fs::exists(dir.path() / "out") || files("out").empty());
  EXPECT_EQ(png.code, 0) << png.err;
  EXPECT_TRUE(fs::exists(dir.path() / "png/f.png"));
  EXPECT_EQ(exr.code, 0) << exr.err;
  EXPECT_EQ(depth.code, 0) << depth.err;
  EXPECT_TRUE(fs::exists(dir.path() / "exr/f.exr"));
  EXPECT_TRUE(fs::exists(dir.path() / "exr/d.exr"));
}

// OpenImageIO's module loads (0.4 s) only where the render needs it, and --stats says whether it
// did: not for a PNG of built-in meshes (libpng writes it), of a mesh file naming no map, a PNG
// map (libpng reads it), a JPEG map (libjpeg reads it) or an EXR map (OpenEXR's library reads it),
// nor for an EXR of any of those (OpenEXR's library writes it), but for a TIFF, and for a TIFF map (a mesh file's loads it when the set-up
// reaches it, the scene's ahead). The shipped scenes load it for none of their maps (scenes_test.cpp).
TEST_F(RenderCommand, StatsSayWhetherTheImageModuleWasLoaded) {
  write_map_meshes(dir);
  const auto loaded = [&](const std::string& mesh, const std::string& out, const std::string& map = "") {
    const fs::path stats = dir.path() / "stats.json";
    const Result r = render_mesh(dir, mesh, out, map, {"--stats", stats.string()});
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(read_text(stats)).at("image_module").get<bool>();
  };
  EXPECT_FALSE(loaded("sphere:8", "a.png"));
  EXPECT_FALSE(loaded("q.obj", "b.png"));
  EXPECT_FALSE(loaded("p.obj", "c.png"));
  EXPECT_FALSE(loaded("sphere:8", "d.exr"));
  EXPECT_FALSE(loaded("p.obj", "k.exr"));
  EXPECT_FALSE(loaded("j.obj", "l.exr"));
  EXPECT_FALSE(loaded("q.obj", "m.exr", "map.jpg"));
  EXPECT_TRUE(loaded("sphere:8", "n.tif"));
  EXPECT_TRUE(loaded("m.obj", "o.exr"));  // a TIFF map still loads it
  EXPECT_TRUE(loaded("m.obj", "e.png"));
  EXPECT_FALSE(loaded("j.obj", "h.png"));
  EXPECT_FALSE(loaded("q.obj", "f.png", "map.png"));  // the scene's own maps: PNG or JPEG, or not
  EXPECT_FALSE(loaded("q.obj", "i.png", "map.jpg"));
  EXPECT_FALSE(loaded("q.obj", "p.png", "map.exr"));
  EXPECT_FALSE(loaded("x.obj", "r.png"));
  EXPECT_FALSE(loaded("x.obj", "s.exr"));
  EXPECT_TRUE(loaded("q.obj", "g.png", "map.tif"));
}

TEST_F(RenderCommand, StatsListEveryRenderedFrame) {
  const fs::path stats = dir.path() / "logs" / "shot" / "stats.json";  // folders made for it, as for -o
  const Result r = pelt({"-o", (dir.path() / "s/f_#.exr").string(), "--frames", "3:5", "--stats", stats.string(), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "--quiet printed: " << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_text(stats));
  ASSERT_EQ(j["frames"].size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const nlohmann::json& f = j["frames"][k];
    EXPECT_EQ(f["frame"], 3 + k);
    EXPECT_GT(f["triangles"].get<uint64_t>(), 0u);
    bool wrote = false;
    for (const auto& s : f["stages"])
      if (s["name"] == "write") wrote = s["ran"].get<bool>();
    EXPECT_TRUE(wrote) << f.dump();
  }
  EXPECT_TRUE(fs::exists(dir.path() / "s/f_5.exr"));
}

// A --stats path that cannot be written is refused before the first frame, not after the
// whole sequence: no frame, no folder for the frames.
TEST_F(RenderCommand, AnUnwritableStatsPathFailsBeforeTheFirstFrame) {
  const fs::path stats = scene / "stats.json";  // under the scene file, a regular file
  const Result r = pelt({"-o", (dir.path() / "u/f_#.png").string(), "--frames", "0:2", "--stats", stats.string(), "-q"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(stats.string() + ": --stats: cannot create folder " + scene.string()), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "u"));
}

// A frame is written on a second thread while the next one renders; a write that fails there still
// ends the render with exit code 2 naming the file, after the frames before it were written (and
// their statistics) and before any frame after it is. Frame 1's folder is taken by a regular file, so its write fails.
TEST_F(RenderCommand, AFailedWriteStopsTheSequenceWithExitCode2) {
  const fs::path out = dir.path() / "w";
  fs::create_directories(out);
  std::ofstream(out / "d1") << "not a folder";
  const Result r = pelt({"-o", (out / "d#/f.png").string(), "--frames", "0:4", "-q", "--stats",
                         (dir.path() / "w_stats.json").string()});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find((out / "d1").string()), std::string::npos) << r.err;
  // The frame written before the error keeps its statistics, as after an interrupt.
  const nlohmann::json stats = nlohmann::json::parse(read_text(dir.path() / "w_stats.json"));
  ASSERT_EQ(stats["frames"].size(), 1u);
  EXPECT_EQ(stats["frames"][0]["frame"], 0);
  EXPECT_NE(r.err.find("cannot create folder"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "d0/f.png"));
  for (const char* later : {"d2", "d3", "d4"}) EXPECT_FALSE(fs::exists(out / later)) << later;
  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temporary left behind: " << e.path();
}

// The quality flags reach the image: a preset, then a knob on top of it, change the pixels, and the
// same flags give the same bytes.
TEST_F(RenderCommand, QualityFlagsChangeTheImage) {
  const Result plain_run = pelt({"-o", (dir.path() / "q/plain.png").string(), "--frame", "3"});
  ASSERT_EQ(plain_run.code, 0) << plain_run.err;
  const Result ss_run = pelt({"-o", (dir.path() / "q/ss.png").string(), "--frame", "3", "--spp", "4"});
  ASSERT_EQ(ss_run.code, 0) << ss_run.err;
  const Result ss2_run =
      pelt({"-o", (dir.path() / "q/ss2.png").string(), "--frame", "3", "--quality", "default", "--spp", "4"});
  ASSERT_EQ(ss2_run.code, 0) << ss2_run.err;
  const std::string plain = read_text(dir.path() / "q/plain.png");
  const std::string ss = read_text(dir.path() / "q/ss.png");
  EXPECT_FALSE(plain.empty());
  EXPECT_NE(plain, ss);  // supersampled edges
  EXPECT_EQ(ss, read_text(dir.path() / "q/ss2.png"));
}

struct BadOption {
  const char* name;
  std::vector<std::string> args;  // after `render SCENE`
  const char* message;            // expected in stderr
};

// Test names in ctest show the case's name, not its bytes.
void PrintTo(const BadOption& b, std::ostream* os) { *os << b.name; }

class RenderBadOption : public RenderCommand, public ::testing::WithParamInterface<BadOption> {};

TEST_P(RenderBadOption, ExitCode2NamingTheOptionAndNoOutput) {
  const BadOption& b = GetParam();
  std::vector<std::string> args = b.args;
  for (auto& a : args)
    if (a.rfind("OUT/", 0) == 0) a = (dir.path() / "out" / a.substr(4)).string();
  const Result r = pelt(args);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

INSTANTIATE_TEST_SUITE_P(
    Options, RenderBadOption,
    ::testing::Values(
        BadOption{"RangeReversed", {"-o", "OUT/f_#.png", "--frames", "5:2"}, "--frames: first frame 5 is after last frame 2"},
        BadOption{"RangeOutOfScene", {"-o", "OUT/f_#.png", "--frames", "0:8"}, "--frames: frame 8 is out of range"},
        BadOption{"RangeMalformed", {"-o", "OUT/f_#.png", "--frames", "2-5"}, "--frames: expected FIRST:LAST"},
        BadOption{"FrameOutOfScene", {"-o", "OUT/a.png", "--frame", "9"}, "--frame: frame 9 is out of range"},
        BadOption{"FrameMalformed", {"-o", "OUT/a.png", "--frame", "two"}, "--frame: expected a frame number (a whole number >= 0), got `two`"},
        BadOption{"FrameAndFrames", {"-o", "OUT/a.png", "--frame", "1", "--frames", "1:2"}, "--frame"},
        BadOption{"ShardMalformed", {"-o", "OUT/f_#.png", "--shard", "1-4"}, "--shard: expected INDEX/COUNT"},
        BadOption{"ShardIndexTooBig", {"-o", "OUT/f_#.png", "--shard", "4/4"}, "--shard: shard index 4"},
        BadOption{"RangeWithoutPattern", {"-o", "OUT/a.png", "--frames", "0:3"}, "-o: 4 frames need a `#` run"},
        BadOption{"WholeShotWithoutPattern", {"-o", "OUT/a.exr"}, "-o: 8 frames need a `#` run"},
        BadOption{"TwoHashRuns", {"-o", "OUT/a_#_#.png"}, "-o: holds more than one run of `#`"},
        BadOption{"BadExtension", {"-o", "OUT/a.jpg", "--frame", "0"}, "-o: unsupported output extension `.jpg`"},
        BadOption{"GifDepth", {"-o", "OUT/a.gif", "--aov", "depth"}, "--aov: a GIF holds colour only"},
        BadOption{"GifId", {"-o", "OUT/a.gif", "--aov", "id"}, "--aov: a GIF holds colour only"},
        BadOption{"GifOverdraw", {"-o", "OUT/a.gif", "--aov", "overdraw"}, "--aov: a GIF holds colour only"},
        BadOption{"GifShard", {"-o", "OUT/a.gif", "--shard", "1/2"}, "--shard: a GIF is one file"},
        BadOption{"GifResume", {"-o", "OUT/a.gif", "--resume"}, "--resume: a GIF is written whole"},
        BadOption{"GifPattern", {"-o", "OUT/a_##.gif"}, "-o: a GIF holds every frame in one file"},
        BadOption{"UnknownAov", {"-o", "OUT/f_#.png", "--aov", "normals"}, "--aov: unknown AOV"},
        BadOption{"PngCompression", {"-o", "OUT/a.png", "--frame", "0", "--png-compression", "10"},
                  "pelt: error: --png-compression: Value 10 not in range 0 to 9"},
        // CLI11's "The following arguments were not expected: 160 --widht", without `pelt: error`.
        BadOption{"MistypedOption", {"-o", "OUT/a.png", "--frame", "0", "--widht", "160"},
                  "pelt: error: unknown option `--widht` for `pelt render` (did you mean `--width`?)"},
        // CLI11's own refusal, not a word after `--` taken for an unknown option.
        BadOption{"RangeBeforeSeparator", {"-o", "OUT/a.png", "--frame", "0", "--width", "0", "--", "--x"},
                  "pelt: error: --width: Value 0 not in range 1 to 16384"},
        BadOption{"UnknownPreset", {"-o", "OUT/a.png", "--frame", "0", "--quality", "ultra"}, "--quality: unknown preset `ultra`"},
        BadOption{"SppNotSquare", {"-o", "OUT/a.png", "--frame", "0", "--spp", "3"}, "--spp: must be a square number"},
        BadOption{"UnknownSort", {"-o", "OUT/a.png", "--frame", "0", "--sort", "depth"}, "--sort: unknown value `depth`"},
        BadOption{"BadScattering", {"-o", "OUT/a.png", "--frame", "0", "--multiple-scattering", "dipole"},
                  "--multiple-scattering: unknown value `dipole` (paper, normal_blur, reference)"},
        BadOption{"SupersampledDepth", {"-o", "OUT/a.exr", "--frame", "0", "--aov", "depth", "--spp", "4"},
                  "--spp: the depth, id and overdraw AOVs are point-sampled"},
        BadOption{"SupersampledOverdraw", {"-o", "OUT/a.exr", "--frame", "0", "--aov", "overdraw", "--spp", "4"},
                  "--spp: the depth, id and overdraw AOVs are point-sampled"},
        BadOption{"SupersampledByPreset", {"-o", "OUT/a.exr", "--frame", "0", "--aov", "id", "--quality", "high"},
                  "--quality: the depth, id and overdraw AOVs are point-sampled"},
        BadOption{"FrameGivenARange", {"-o", "OUT/f_#.png", "--frame", "2:5"}, "--frame: takes one frame number"},
        BadOption{"DepthAsPng", {"-o", "OUT/a.png", "--frame", "0", "--aov", "depth"},
                  "--aov: the depth AOV holds float depths, which a PNG cannot store"},
        BadOption{"IdAsPng", {"-o", "OUT/a.png", "--frame", "0", "--aov", "id"},
                  "--aov: the id AOV holds 32-bit triangle ids, which a PNG cannot store"},
        BadOption{"SkinLayerWithoutSkin", {"-o", "OUT/a.png", "--frame", "0", "--aov", "dermis"},
                  "--aov: the dermis AOV is a layer of the skin shader, and no object of"},
        BadOption{"StatsOverTheImage", {"-o", "OUT/a.png", "--frame", "0", "--stats", "OUT/a.png"},
                  "--stats: is also where -o writes"},
        BadOption{"StatsOverAFrame", {"-o", "OUT/f_#.png", "--frames", "0:3", "--stats", "OUT/f_2.png"},
                  "--stats: is also where -o writes"},
        // A value a flag gave is named by the flag, not by the scene's field.
        BadOption{"WidthFlagOverBudget", {"-o", "OUT/a.png", "--frame", "0", "--width", "16384", "--height", "8193"},
                  "pelt: error: --width: the image is 16384 x 8193"},
        // An empty value (an unset shell variable) is not "not given": it would render every frame.
        BadOption{"EmptyFrame", {"-o", "OUT/f_#.png", "--frame", ""}, "--frame: needs a value, got an empty one"},
        BadOption{"EmptyShard", {"-o", "OUT/f_#.png", "--shard", ""}, "--shard: needs a value, got an empty one"},
        BadOption{"EmptyStats", {"-o", "OUT/f_#.png", "--frames", "0:1", "--stats", ""},
                  "--stats: needs a value, got an empty one"},
        BadOption{"EmptyKnob", {"-o", "OUT/f_#.png", "--frames", "0:1", "--spp", ""},
                  "--spp: needs a value, got an empty one"},
        BadOption{"EmptyPreset", {"-o", "OUT/f_#.png", "--frames", "0:1", "--quality", ""},
                  "--quality: needs a value, got an empty one"}),
    [](const ::testing::TestParamInfo<BadOption>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace pelt::cli_test
