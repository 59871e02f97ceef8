// Every scene shipped in tools/scenes renders (small), without loading OpenImageIO's module, and
// `pelt info` describes it.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/cli/run_pelt.h"
#include "tools/io/image_io.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> shipped_scenes() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(source_dir() / "tools" / "scenes"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ShippedScenes, TheExpectedOnesAreThere) {
  std::vector<std::string> names;
  for (const fs::path& p : shipped_scenes()) names.push_back(p.filename().string());
  for (const char* want : {"default.json", "box_fur.json", "teapot_fur.json", "teapot2_fur.json", "head_skin.json",
                           "bunny_wind.json"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
}

TEST(ShippedScenes, EachRendersAndInfoExits0) {
  TempDir dir;
  for (const fs::path& scene : shipped_scenes()) {
    SCOPED_TRACE(scene.filename().string());
    const fs::path out = dir.path() / (scene.stem().string() + ".png");
    const fs::path stats = dir.path() / (scene.stem().string() + ".json");
    const Result r = run_pelt({"render", scene.string(), "-o", out.string(), "--frame", "0", "--width", "160",
                               "--height", "120", "-q", "--stats", stats.string()},
                              dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    // Their maps are PNG and JPEG files (or a glTF's embedded images), which pelt reads itself: a
    // PNG of any of them never loads the module's 260 libraries (0.4 s; the default scene's two
    // JPEG maps did until 2026-11-28).
    EXPECT_FALSE(nlohmann::json::parse(read_text(stats)).at("image_module").get<bool>());
    const io::ImageRGBA img = io::read_image_rgba(out);
    ASSERT_EQ(img.width, 160);
    ASSERT_EQ(img.height, 120);
    // Not a blank frame: some pixel differs from the first one (the background corner).
    bool varied = false;
    for (size_t k = 4; k < img.rgba.size() && !varied; ++k) varied = img.rgba[k] != img.rgba[k % 4];
    EXPECT_TRUE(varied) << "every pixel is the background colour";

    const Result info = run_pelt({"info", scene.string()}, dir.path());
    EXPECT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("triangles"), std::string::npos) << info.out;
  }
}

}  // namespace
}  // namespace pelt::cli_test
