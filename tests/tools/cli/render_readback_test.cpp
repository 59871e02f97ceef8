// `pelt render`'s files read back with OpenImageIO itself: a PNG sequence's and a GIF's frames,
// sizes and rate, and the overdraw AOV as integers, floats and a heat map. In a binary of its
// own: linking OpenImageIO adds most of a second to the start of every test process under the
// sanitizers, which the other render tests do not pay.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/cli/render_command_fixture.h"
#include "tests/tools/cli/run_pelt.h"
#include "tools/render/overdraw_heatmap.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

TEST_F(RenderCommand, PngSequenceAndGifReadBack) {
  const Result seq = pelt({"-o", (dir.path() / "seq/f_###.png").string(), "--frames", "2:6", "--width", "40",
                           "--height", "30", "-q"});
  ASSERT_EQ(seq.code, 0) << seq.err;
  const std::vector<std::string> names = files("seq");
  EXPECT_EQ(names, (std::vector<std::string>{"f_002.png", "f_003.png", "f_004.png", "f_005.png", "f_006.png"}));
  for (const std::string& n : names) {
    auto in = OIIO::ImageInput::open((dir.path() / "seq" / n).string());
    ASSERT_TRUE(in) << n;
    EXPECT_EQ(in->spec().width, 40);
    EXPECT_EQ(in->spec().height, 30);
  }

  const fs::path gif = dir.path() / "anim/shot.gif";
  const Result g = pelt({"-o", gif.string(), "-q"});
  ASSERT_EQ(g.code, 0) << g.err;
  auto in = OIIO::ImageInput::open(gif.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  int subimages = 0;
  while (in->seek_subimage(subimages, 0)) {
    EXPECT_EQ(in->spec().width, 48);
    EXPECT_EQ(in->spec().height, 36);
    // 12 fps: a delay of 8 centiseconds per frame.
    int rational[2] = {0, 0};
    EXPECT_TRUE(in->spec().getattribute("FramesPerSecond", OIIO::TypeRational, rational));
    EXPECT_EQ(rational[0], 100);
    EXPECT_EQ(rational[1], 8);
    ++subimages;
  }
  EXPECT_EQ(subimages, 8);
  for (const auto& e : fs::directory_iterator(gif.parent_path()))
    EXPECT_EQ(e.path().filename(), "shot.gif");  // no temporary left
}

// --aov overdraw: per pixel, the translucent fragments that passed the depth test, as 32-bit
// unsigned TIFF or float EXR (over the frame they add up to the stats' fragments_blended), or as
// a heat map in a PNG.
TEST_F(RenderCommand, OverdrawCountsTheBlendedFragments) {
  const fs::path fur = dir.write("fur.json", R"({"pelt": 1,
  "image": {"width": 96, "height": 72},
  "camera": {"eye": [3.5, 2.5, 5.0], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}],
  "objects": [{"mesh": "box:3", "material": {"type": "lambert"},
               "fur": {"shells": 8, "texture_size": 32, "fins": "all"}}]})");
  auto read = [&](const fs::path& p, OIIO::TypeDesc type, auto& pixels) {
    auto in = OIIO::ImageInput::open(p.string());
    ASSERT_TRUE(in) << p << ": " << OIIO::geterror();
    ASSERT_EQ(in->spec().nchannels, 1) << p;
    pixels.resize(size_t(in->spec().width) * in->spec().height);
    ASSERT_TRUE(in->read_image(0, 0, 0, 1, type, pixels.data())) << p;
  };
  const fs::path stats = dir.path() / "od.json";
  Result r = run_pelt({"render", fur.string(), "-o", (dir.path() / "od.tif").string(), "--aov", "overdraw",
                       "--stats", stats.string(), "-q"},
                      dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_pelt({"render", fur.string(), "-o", (dir.path() / "od.exr").string(), "--aov", "overdraw", "-q"}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<uint32_t> counts;
  std::vector<float> floats;
  read(dir.path() / "od.tif", OIIO::TypeDesc::UINT32, counts);
  read(dir.path() / "od.exr", OIIO::TypeDesc::FLOAT, floats);
  ASSERT_EQ(counts.size(), size_t(96 * 72));
  ASSERT_EQ(floats.size(), counts.size());
  uint64_t sum = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    EXPECT_EQ(float(counts[i]), floats[i]) << i;
    sum += counts[i];
  }
  const nlohmann::json j = nlohmann::json::parse(read_text(stats));
  EXPECT_EQ(sum, j["frames"][0]["raster"]["fragments_blended"].get<uint64_t>());
  EXPECT_EQ(j["frames"][0]["raster"]["exact_passes"].get<uint64_t>(), 0u);  // the tile sort
  EXPECT_GT(*std::max_element(counts.begin(), counts.end()), 8u);  // shells and fins pile up
  EXPECT_GT(std::count(counts.begin(), counts.end(), 0u), 0);       // the background has none
  // Under the exact sort: a pass a tile that holds anything (of 2 x 2 tiles of 64), each holding
  // at most the fragments blended.
  const fs::path exact_stats = dir.path() / "exact.json";
  r = run_pelt({"render", fur.string(), "-o", (dir.path() / "exact.png").string(), "--sort", "exact", "--stats",
                exact_stats.string(), "-q"},
               dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json e = nlohmann::json::parse(read_text(exact_stats))["frames"][0]["raster"];
  EXPECT_GE(e["exact_passes"].get<uint64_t>(), 1u);
  EXPECT_LE(e["exact_passes"].get<uint64_t>(), 4u);
  EXPECT_GT(e["exact_fragments_peak"].get<uint64_t>(), 0u);
  EXPECT_LE(e["exact_fragments_peak"].get<uint64_t>(), e["fragments_blended"].get<uint64_t>());

  // A PNG is the counts' picture (render::heatmap_rgb8), pixel for pixel.
  r = run_pelt({"render", fur.string(), "-o", (dir.path() / "od.png").string(), "--aov", "overdraw", "-q"}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  auto in = OIIO::ImageInput::open((dir.path() / "od.png").string());
  ASSERT_TRUE(in) << OIIO::geterror();
  ASSERT_EQ(in->spec().nchannels, 3);
  std::vector<uint8_t> picture(counts.size() * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, picture.data()));
  EXPECT_EQ(picture, render::heatmap_rgb8(counts));
}

}  // namespace
}  // namespace pelt::cli_test
