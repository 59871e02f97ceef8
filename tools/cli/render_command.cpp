// `pelt render SCENE.json -o OUT`: renders a frame of a scene to an image file.
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "tools/cli/commands.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string output;
  int width = 0, height = 0;
  int threads = 0;
  std::string stats;
  std::string aov = "color";
  std::string sort = "tile";
  int frame = 0;
};

render::Aov parse_aov(const std::string& s) {
  if (s == "color") return render::Aov::color;
  if (s == "depth") return render::Aov::depth;
  if (s == "id") return render::Aov::id;
  if (s == "sebum") return render::Aov::sebum;
  if (s == "epidermis") return render::Aov::epidermis;
  if (s == "dermis") return render::Aov::dermis;
  throw io::InputError("", "--aov", "unknown AOV `" + s + "` (color, depth, id, sebum, epidermis, dermis)");
}

raster::SortMode parse_sort(const std::string& s) {
  if (s == "none") return raster::SortMode::None;
  if (s == "tile") return raster::SortMode::Tile;
  throw io::InputError("", "--sort", "unknown sort mode `" + s + "` (none, tile)");
}

void write_frame(const std::string& path, const render::FrameImage& img, render::Aov aov) {
  switch (aov) {
    case render::Aov::depth:
      io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::f32, img.depth.data());
      break;
    case render::Aov::id: {
      const std::string ext = std::filesystem::path(path).extension().string();
      if (ext == ".exr") {
        std::vector<float> f(img.id.begin(), img.id.end());
        io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::f32, f.data());
      } else {
        io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::u32, img.id.data());
      }
      break;
    }
    default:
      io::write_image_atomic(path, img.width, img.height, 4, io::PixelType::f32, img.color.data());
      break;
  }
}

void write_json_atomic(const std::string& path, const nlohmann::json& j) {
  const std::filesystem::path p(path);
  const std::filesystem::path tmp = p.parent_path() / ("." + p.filename().string() + ".tmp");
  {
    std::ofstream f(tmp);
    if (!f) throw io::InputError(path, "--stats", "cannot open for writing");
    f << j.dump(2) << "\n";
    if (!f) throw io::InputError(path, "--stats", "write failed");
  }
  std::filesystem::rename(tmp, p);
}

int run_render(const RenderOptions& o) {
  const render::Aov aov = parse_aov(o.aov);
  const io::Scene scene = io::load_scene(o.scene);
  render::RenderSettings rs;
  rs.width = o.width;
  rs.height = o.height;
  rs.threads = o.threads > 0 ? o.threads : int(std::thread::hardware_concurrency());
  rs.sort = parse_sort(o.sort);
  rs.aov = aov;
  render::SceneRenderer r(scene, rs);
  if (o.frame < 0 || o.frame >= r.frame_count())
    throw io::InputError(o.scene, "--frame", "frame " + std::to_string(o.frame) + " outside 0.." +
                                                 std::to_string(r.frame_count() - 1));
  render::FrameImage img;
  render::FrameStats st;
  r.render(o.frame, img, st);
  const std::filesystem::path out_dir = std::filesystem::path(o.output).parent_path();
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) throw io::InputError(o.output, "-o", "cannot create folder " + out_dir.string() + ": " + ec.message());
  }
  {
    render::StageTimer t(st, "write");
    write_frame(o.output, img, aov);
  }
  if (!o.stats.empty()) write_json_atomic(o.stats, {{"frames", nlohmann::json::array({st.to_json()})}});
  return 0;
}

}  // namespace

Run add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* sub = app.add_subcommand("render", "Render a scene to an image");
  sub->add_option("scene", o->scene, "Scene file (JSON, version 1)")->required();
  sub->add_option("-o,--output", o->output, "Output image: .png, .exr, .tif")->required();
  sub->add_option("--width", o->width, "Image width (default: the scene's)")->check(CLI::Range(1, 16384));
  sub->add_option("--height", o->height, "Image height (default: the scene's)")->check(CLI::Range(1, 16384));
  sub->add_option("--threads", o->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 256));
  sub->add_option("--stats", o->stats, "Write per-frame stage statistics as JSON");
  sub->add_option("--aov", o->aov, "color | depth | id | sebum | epidermis | dermis");
  sub->add_option("--sort", o->sort, "Translucent order: none | tile");
  sub->add_option("--frame", o->frame, "Frame of the animation to render (0-based)");
  return [o] { return run_render(*o); };
}

}  // namespace pelt::cli
