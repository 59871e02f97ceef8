// `pelt tradeoff` end to end on a tiny furry scene: the files it writes, a reference row
// with zero error, one row per setting in sweep order, and bad options refused with exit
// code 2 before anything is written. No test here looks at a time.
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/tools/cli/run_pelt.h"
#include "tools/tradeoff/report.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

const char* kTinyFurScene = R"({
  "pelt": 1,
  "image": {"width": 48, "height": 32, "background": [0.1, 0.1, 0.1]},
  "camera": {"eye": [2.5, 2.0, 3.5], "target": [0, 0, 0], "fovy_deg": 45, "near": 0.5, "far": 20},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5], "intensity": 0.7},
             {"type": "ambient", "intensity": 0.3}],
  "objects": [{"mesh": "box:2", "material": {"type": "lambert", "color": [0.8, 0.6, 0.4]},
               "fur": {"shells": 8, "length": 0.15, "texture_size": 32}}]
})";

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(p));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    for (std::string c; std::getline(l, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.push_back("");  // an empty last field
    rows.push_back(cells);
  }
  return rows;
}

TEST(TradeoffCommand, SweepsSortAndSppAgainstTheReference) {
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path out = dir.path() / "report";
  const Result r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--runs", "5", "--threads", "2",
                             "--knobs", "sort,spp", "--no-plot", "--images"},
                            dir.path());
  ASSERT_EQ(r.code, 0) << r.err;

  const auto csv = read_csv(out / "tradeoff.csv");
  ASSERT_FALSE(csv.empty());
  std::string header;
  for (size_t i = 0; i < csv[0].size(); ++i) header += (i ? "," : "") + csv[0][i];
  EXPECT_EQ(header, tradeoff::kCsvHeader);
  const std::vector<std::string> expected = {"reference=reference", "default=scene", "sort=none", "sort=layer",
                                             "sort=tile", "sort=surface", "sort=exact", "spp=1", "spp=4", "spp=16",
                                             "preset=fast", "preset=balanced", "preset=high"};
  ASSERT_EQ(csv.size(), 1 + expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const auto& row = csv[i + 1];
    ASSERT_EQ(row.size(), 8u) << i;
    EXPECT_EQ(row[0] + "=" + row[1], expected[i]);
    EXPECT_GT(std::stod(row[2]), 0.0) << expected[i];  // a frame time was measured
    const double rmse = std::stod(row[3]);
    EXPECT_GE(rmse, 0.0);
    EXPECT_EQ(rmse == 0.0, row[4] == "inf") << expected[i];  // PSNR is infinite exactly at zero error
  }
  EXPECT_EQ(csv[1][3], "0");  // the reference against itself
  EXPECT_EQ(csv[1][4], "inf");
  EXPECT_EQ(csv[1][6], "0");
  // The default (tile sort, 1 sample, simd) is not the reference (exact, 64 samples, double).
  EXPECT_GT(std::stod(csv[2][3]), 0.0);
  // sort=tile and spp=1 are the scene's own settings: the default row's measurement, reused.
  EXPECT_EQ(csv[5][2], csv[2][2]);
  EXPECT_EQ(csv[5][3], csv[2][3]);
  EXPECT_EQ(csv[8][3], csv[2][3]);
  // Paired with the default frame by frame: the reference is not, the default and its copies
  // are the baseline, every other row has a ratio.
  EXPECT_EQ(csv[1][7], "");
  for (size_t i : {2u, 5u, 8u}) EXPECT_EQ(csv[i][7], "1") << expected[i - 1];
  for (size_t i : {3u, 4u, 6u, 7u, 9u, 10u, 11u, 12u, 13u}) EXPECT_GT(std::stod(csv[i][7]), 0.0) << expected[i - 1];

  // The markdown file holds the table printed on stdout, with the Pareto column.
  const std::string md = read_text(out / "tradeoff.md");
  EXPECT_NE(md.find(r.out), std::string::npos);
  EXPECT_NE(r.out.find("| knob | setting | ms_median | vs default, paired |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| default | scene | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" | 1x | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| reference | reference |"), std::string::npos);
  EXPECT_NE(r.out.find("same settings as default=scene"), std::string::npos);
  // Every row but the reference was timed on the way through the sweep and on the way back.
  EXPECT_NE(r.out.find("| default | scene |"), std::string::npos);
  EXPECT_NE(r.out.find("| 2 x 5 runs ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| 1 run, no warm-up |"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("[way back 1/"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "tradeoff.png"));  // --no-plot

  // --images: one PNG per row.
  for (const std::string& label : expected) {
    std::string file = label;
    file[file.find('=')] = '_';
    EXPECT_TRUE(fs::exists(out / "images" / (file + ".png"))) << file;
  }
}

struct BadRun {
  const char* name;
  std::vector<std::string> args;  // after `tradeoff SCENE -o OUT`
  const char* message;
};

void PrintTo(const BadRun& b, std::ostream* os) { *os << b.name; }

class TradeoffBadOption : public ::testing::TestWithParam<BadRun> {};

TEST_P(TradeoffBadOption, ExitCode2NamingTheOptionAndNoOutput) {
  const BadRun& b = GetParam();
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path out = dir.path() / "report";
  std::vector<std::string> args = {"tradeoff", scene.string(), "-o", out.string()};
  args.insert(args.end(), b.args.begin(), b.args.end());
  const Result r = run_pelt(args, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(r.out.empty()) << r.out;
}

INSTANTIATE_TEST_SUITE_P(
    Options, TradeoffBadOption,
    ::testing::Values(BadRun{"UnknownKnob", {"--knobs", "sort,blur"}, "--knobs: unknown knob `blur`"},
                      BadRun{"EmptyKnobs", {"--knobs", ""}, "--knobs: needs a value, got an empty one"},
                      BadRun{"TooFewRuns", {"--runs", "3"}, "--runs"},
                      BadRun{"ZeroThreads", {"--threads", "0"}, "--threads"},
                      BadRun{"ZeroWidth", {"--width", "0"}, "--width"}),
    [](const ::testing::TestParamInfo<BadRun>& info) { return std::string(info.param.name); });

// --no-plot writes no plot, and removes none: an earlier run's plot left in the folder is
// named as not showing this sweep, so nobody reads the new CSV off the old picture; so are row
// images an earlier --images left.
TEST(TradeoffCommand, NoPlotNamesAnEarlierRunsPlot) {
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path out = dir.path() / "report";
  fs::create_directories(out);
  const std::string old_plot = "an earlier run's picture";
  dir.write("report/tradeoff.png", old_plot);
  dir.write("report/images/filter_bilinear.png", old_plot);
  const Result r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--runs", "5", "--knobs", "fins",
                             "--no-plot"},
                            dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("tradeoff.png is an earlier run's plot and does not show this sweep"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("images holds 1 row image of an earlier sweep (filter_bilinear.png) that this one did not draw"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(read_text(out / "tradeoff.png"), old_plot);
  fs::remove(out / "tradeoff.png");
  fs::remove_all(out / "images");
  const Result again = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--runs", "5", "--knobs", "fins",
                                 "--no-plot"},
                                dir.path());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(again.err.find("earlier run's plot"), std::string::npos) << again.err;
}

TEST(TradeoffCommand, BadSceneExits2NamingTheFieldAndWritesNothing) {
  TempDir dir;
  const fs::path scene =
      dir.write("shot.json", R"({"pelt": 1, "objects": [{"mesh": "box:2", "material": {"type": "lambert"},
                                   "fur": {"shells": 1}}]})");
  const fs::path out = dir.path() / "report";
  const Result r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--no-plot"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("shot.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("objects[0].fur.shells"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// A budget refusal names where the refused value came from: --width, or the sweep's own
// reference (64 shells), which the scene never asked for; not the scene's fields.
TEST(TradeoffCommand, BudgetRefusalsNameTheFlagOrTheSweepRowNotTheScene) {
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path out = dir.path() / "report";
  Result r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--no-plot", "--width", "16384", "--height",
                       "16384"},
                      dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("pelt: error: --width: the image is 16384 x 16384"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("image.width"), std::string::npos) << r.err;

  r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--no-plot", "--max-shells", "8"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("pelt: error: the sweep's reference=reference row: 64 fur shells"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("quality.shells"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "tradeoff.csv"));

  // A row past the reference, refused before the reference renders (minutes on a real scene),
  // naming the row: the scene's skin uses the paper's model, the sweep's normal_blur row asks for
  // the blur. No folder is made.
  const fs::path skin = dir.write("skin.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
  "camera": {"eye": [0, 0, 4], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.6, 0.5, 0.7]}],
  "objects": [{"mesh": "sphere:16", "material": {"type": "skin", "skin": {"multiple_scattering": "paper"}}}]})");
  r = run_pelt({"tradeoff", skin.string(), "-o", out.string(), "--no-plot", "--knobs", "multiple_scattering",
                "--max-blur-pairs", "10"},
               dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("pelt: error: the sweep's multiple_scattering=normal_blur row: reaches about"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("[1/"), std::string::npos) << "rendered before refusing: " << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(TradeoffCommand, OutputPathThatIsAFileIsRefused) {
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path file = dir.write("taken", "not a folder");
  const Result r = run_pelt({"tradeoff", scene.string(), "-o", file.string(), "--no-plot"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("-o: exists and is not a folder"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(file), "not a folder");
}

// A folder that cannot be made is refused before the reference renders (which takes minutes
// on a real scene), not after every row was measured.
TEST(TradeoffCommand, AnOutputFolderThatCannotBeMadeIsRefusedBeforeRendering) {
  TempDir dir;
  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  const fs::path file = dir.write("taken", "not a folder");
  const Result r = run_pelt({"tradeoff", scene.string(), "-o", (file / "report").string(), "--no-plot"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("-o: cannot create folder " + (file / "report").string()), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("[1/"), std::string::npos) << "rendered before refusing: " << r.err;
  EXPECT_EQ(read_text(file), "not a folder");
}

// Every file the sweep writes is checked before the reference renders: an input at an output's
// name (the scene named tradeoff.csv, a colour map named tradeoff.png) was overwritten, and a
// plot or image that could not be written failed only after the whole sweep, leaving the CSV.
TEST(TradeoffCommand, EveryOutputIsCheckedBeforeRendering) {
  TempDir dir;
  const fs::path out = dir.path() / "report";
  const fs::path scene_as_csv = dir.write("report/tradeoff.csv", kTinyFurScene);
  Result r = run_pelt({"tradeoff", scene_as_csv.string(), "-o", out.string(), "--knobs", "fins", "--no-plot"}, dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("tradeoff.csv: -o: is an input of this tradeoff"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(scene_as_csv), kTinyFurScene);
  fs::remove(scene_as_csv);

  const fs::path scene = dir.write("tiny.json", kTinyFurScene);
  for (const auto& [blocker, option] : {std::pair<std::string, std::string>{"tradeoff.png", "-o"},
                                        std::pair<std::string, std::string>{"images/fins_off.png", "--images"}}) {
    fs::create_directories(out / blocker);
    r = run_pelt({"tradeoff", scene.string(), "-o", out.string(), "--knobs", "fins", "--images"}, dir.path());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(blocker + ": " + option + ": is a folder, not a file"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("[1/"), std::string::npos) << "rendered before refusing: " << r.err;
    EXPECT_FALSE(fs::exists(out / "tradeoff.csv"));
    fs::remove_all(out);
  }
}

}  // namespace
}  // namespace pelt::cli_test
