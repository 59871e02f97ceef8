// `pelt bench skin`: the skin paper's Table 1 (render time of its skin shader against
// Blinn and Lambert on a face and two bodies) measured with our renderer.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "tools/bench/skin_meshes.h"
#include "tools/cli/commands.h"
#include "tools/cli/simd_option.h"
#include "tools/cli/budget_options.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/io/scene.h"
#include "tools/render/frame_timing.h"
#include "tools/render/scene_renderer.h"
#include "tools/render/interrupt.h"

namespace pelt::cli {
namespace {

struct SkinBenchOptions {
  int width = 1024, height = 768;
  int threads = 2;
  int frames = 30;
  int warmup = 5;
  std::string json;
  std::string head;  // empty: find_head_scan
};

// The paper compares its shader with Maya's Blinn and Lambert; these are ours, in the
// order of its columns.
struct ShaderColumn {
  const char* name;
  io::MaterialType type;
};
constexpr ShaderColumn kShaders[] = {
    {"skin", io::MaterialType::skin},
    {"blinn", io::MaterialType::blinn},
    {"lambert", io::MaterialType::lambert},
};

struct Measurement {
  std::string mesh;
  uint64_t triangles = 0;
  std::string shader;
  double ms_median = 0, ms_min = 0, ms_max = 0;
  double front_median = 0, tiles_median = 0;  // the rasterizer's own split of the frame
  raster::RasterStats raster;  // the last frame's counters
};

void check_options(const SkinBenchOptions& o) {
  const auto range = [](const char* opt, int v, int lo, int hi) {
    if (v < lo || v > hi)
      throw io::InputError("", opt, std::to_string(v) + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  };
  range("--width", o.width, 1, io::kMaxImageSide);
  range("--height", o.height, 1, io::kMaxImageSide);
  range("--threads", o.threads, 1, 256);
  range("--frames", o.frames, 1, 100000);
  range("--warmup", o.warmup, 0, 100000);
}

// One object framed by bench::skin_bench_view; a key and a fill light and an ambient term.
io::Scene bench_scene(const Mesh& mesh, const ShaderColumn& shader, int width, int height) {
  const bench::SkinBenchView view = bench::skin_bench_view(mesh, width, height);
  io::Scene s;
  s.file = "pelt bench skin";
  s.image.width = width;
  s.image.height = height;
  s.image.background = {0.0f, 0.0f, 0.0f, 1.0f};
  s.camera.eye = {0.0f, 0.0f, view.distance};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 1.0f, 0.0f};
  s.camera.fovy_deg = view.fovy_deg;
  s.camera.near = view.near;
  s.camera.far = view.far;

  io::Light key;
  key.type = io::LightType::directional;
  key.direction = glm::normalize(glm::vec3(-0.5f, 0.6f, 0.8f));
  key.intensity = 1.0f;
  io::Light fill;
  fill.type = io::LightType::directional;
  fill.direction = glm::normalize(glm::vec3(0.7f, 0.1f, 0.6f));
  fill.intensity = 0.35f;
  io::Light ambient;
  ambient.type = io::LightType::ambient;
  ambient.intensity = 0.1f;
  s.lights = {key, fill, ambient};

  io::SceneObject obj;
  obj.name = "bench";
  obj.mesh = "bench mesh";
  obj.transform.translate = -view.centre;
  obj.material.type = shader.type;
  // Lambert and Blinn take the skin's dermis colour, so the three columns show one skin.
  const shading::SkinParams skin_defaults;
  obj.material.color = {skin_defaults.SkinColor[0], skin_defaults.SkinColor[1], skin_defaults.SkinColor[2]};
  s.objects.push_back(std::move(obj));
  return s;
}

// One mesh under every shader column. The columns' frames are interleaved (skin, Blinn,
// Lambert, skin, ...) rather than run one column after the other: on a shared machine the
// background load changes over seconds, and interleaving gives every column the same share
// of it, so the ratios between columns are measured side by side.
std::vector<Measurement> measure_mesh(const bench::SkinBenchMesh& m, const SkinBenchOptions& o) {
  struct Column {
    std::unique_ptr<render::SceneRenderer> renderer;
    std::vector<double> ms, front, tiles;
    render::FrameStats stats;
  };
  std::vector<Column> columns(std::size(kShaders));
  for (size_t c = 0; c < columns.size(); ++c) {
    const io::Scene scene = bench_scene(m.mesh, kShaders[c], o.width, o.height);
    std::vector<io::SceneMesh> meshes(1);
    meshes[0].loaded.mesh = m.mesh;
    meshes[0].model = scene.objects[0].transform.matrix();
    render::RenderSettings rs;
    rs.width = o.width;
    rs.height = o.height;
    rs.threads = o.threads;
    rs.aov = render::Aov::color;
    columns[c].renderer = std::make_unique<render::SceneRenderer>(scene, std::move(meshes), rs);
    columns[c].ms.reserve(o.frames);
  }
  render::FrameImage img;
  for (int i = 0; i < o.warmup; ++i)
    for (Column& col : columns) col.renderer->render(0, img, col.stats);
  for (int i = 0; i < o.frames; ++i)
    for (Column& col : columns) {
      col.ms.push_back(render::time_ms([&] { col.renderer->render(0, img, col.stats); }));
      col.front.push_back(col.stats.stage("raster_front").ms);
      col.tiles.push_back(col.stats.stage("raster_tiles").ms);
    }
  std::vector<Measurement> out;
  for (size_t c = 0; c < columns.size(); ++c) {
    const Column& col = columns[c];
    Measurement r;
    r.mesh = std::string(m.row->name);
    r.triangles = m.mesh.triangle_count();
    r.shader = kShaders[c].name;
    r.ms_median = render::quantile(col.ms, 0.5);
    r.ms_min = *std::min_element(col.ms.begin(), col.ms.end());
    r.ms_max = *std::max_element(col.ms.begin(), col.ms.end());
    r.front_median = render::quantile(col.front, 0.5);
    r.tiles_median = render::quantile(col.tiles, 0.5);
    r.raster = col.stats.raster;
    out.push_back(std::move(r));
  }
  return out;
}

std::string thousands(uint64_t n) {
  const std::string digits = std::to_string(n);
  std::string s;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
    s += digits[i];
  }
  return s;
}

void print_table(const std::vector<bench::SkinBenchMesh>& meshes, const std::vector<Measurement>& ms,
                 const SkinBenchOptions& o) {
  std::printf("pelt bench skin: %dx%d, %d thread%s, SIMD %s, median of %d frames after %d warm-up, a mesh's columns "
              "interleaved frame by frame\n(ours in ms, [min-max]; the paper's Table 1 in s)\n\n",
              o.width, o.height, o.threads, o.threads == 1 ? "" : "s", simd_in_use().c_str(), o.frames, o.warmup);
  std::printf("%-12s | %-19s | %-30s | %-30s | %-30s | %s\n", "Model Name", "No. of triangle",
              "Rendering Time: skin", "Blinn", "Lambert", "skin/Lambert");
  std::printf("%-12s | %-19s | %-30s | %-30s | %-30s | %s\n", "", "ours (paper)", "ours ms [min-max] (paper)",
              "ours ms [min-max] (paper)", "ours ms [min-max] (paper)", "ours (paper)");
  std::printf("%s\n", std::string(12 + 19 + 30 * 3 + 5 * 3 + 14, '-').c_str());
  const size_t ns = std::size(kShaders);
  for (size_t i = 0; i < meshes.size(); ++i) {
    const bench::SkinBenchRow& row = *meshes[i].row;
    const std::string tris = thousands(meshes[i].mesh.triangle_count()) + " (" + thousands(row.paper_triangles) + ")";
    std::printf("%-12s | %-19s", std::string(row.name).c_str(), tris.c_str());
    const double paper_s[] = {row.paper_skin_s, row.paper_blinn_lambert_s, row.paper_blinn_lambert_s};
    for (size_t s = 0; s < ns; ++s) {
      const Measurement& m = ms[i * ns + s];
      char cell[64];
      std::snprintf(cell, sizeof cell, "%.2f [%.2f-%.2f] (%g s)", m.ms_median, m.ms_min, m.ms_max, paper_s[s]);
      std::printf(" | %-30s", cell);
    }
    const double ratio = ms[i * ns + 0].ms_median / ms[i * ns + 2].ms_median;
    std::printf(" | %.2fx (%.2fx)\n", ratio, row.paper_skin_s / row.paper_blinn_lambert_s);
  }
  std::printf("\nFace is the LeePerrySmith head scan as is (the paper's Face had 17,244 triangles); the "
              "bodies are that head\nLoop-subdivided twice and decimated with meshoptimizer to the paper's "
              "counts. The paper's Blinn and\nLambert share one column; its Stam skin shader took %g / %g / "
              "%g s.\n",
              bench::skin_bench_rows()[0].paper_stam_s, bench::skin_bench_rows()[1].paper_stam_s,
              bench::skin_bench_rows()[2].paper_stam_s);
  std::printf("Frame split (median ms, rasterizer front end / tiles):");
  for (size_t i = 0; i < ms.size(); ++i)
    std::printf("%s %s %s %.2f/%.2f", i % ns == 0 ? "\n " : ",", i % ns == 0 ? ms[i].mesh.c_str() : "",
                ms[i].shader.c_str(), ms[i].front_median, ms[i].tiles_median);
  std::printf("\nShading work (visible pixels / lanes the shader computed, whole 4x4 blocks):");
  for (size_t i = 0; i < ms.size(); ++i)
    std::printf("%s %s %s %s/%s", i % ns == 0 ? "\n " : ",", i % ns == 0 ? ms[i].mesh.c_str() : "",
                ms[i].shader.c_str(), thousands(ms[i].raster.pixels_shaded).c_str(), thousands(ms[i].raster.lanes_shaded).c_str());
  std::printf("\n");
}

void write_json_atomic(const std::string& path, const std::vector<Measurement>& ms, const SkinBenchOptions& o) {
  nlohmann::json list = nlohmann::json::array();
  for (const Measurement& m : ms)
    list.push_back({{"mesh", m.mesh},
                    {"triangles", m.triangles},
                    {"shader", m.shader},
                    {"pixels_shaded", m.raster.pixels_shaded},
                    {"lanes_shaded", m.raster.lanes_shaded},
                    {"triangles_culled", m.raster.triangles_culled},
                    {"triangles_setup", m.raster.triangles_setup},
                    {"bin_items", m.raster.bin_items},
                    {"width", o.width},
                    {"height", o.height},
                    {"threads", o.threads},
                    {"simd", simd_in_use()},
                    {"ms_median", m.ms_median},
                    {"ms_min", m.ms_min},
                    {"ms_max", m.ms_max},
                    {"frames", o.frames},
                    {"warmup", o.warmup},
                    {"ms_raster_front_median", m.front_median},
                    {"ms_raster_tiles_median", m.tiles_median},
                    {"fragments", m.raster.fragments_visible + m.raster.fragments_blended}});
  io::write_text_atomic(path, list.dump(2) + "\n", "--json");
}

int run_bench_skin(const SkinBenchOptions& o) {
  check_options(o);
  check_default_pixel_budget(o.width, o.height);
  const std::filesystem::path head = o.head.empty() ? bench::find_head_scan("--head") : std::filesystem::path(o.head);
  // As in pelt render, no output replaces an input: --json naming the scan would destroy it.
  if (!o.json.empty()) io::OutputNames({head}, "benchmark").add(o.json, "--json");
  const std::vector<bench::SkinBenchMesh> meshes = bench::make_skin_bench_meshes(head);
  // Before the probe's temporary: a signal ends the run at once, temporaries removed (render/interrupt.h).
  const render::InterruptGuard interrupt(render::InterruptGuard::Stop::now);
  if (!o.json.empty()) io::prepare_output(o.json, "--json");  // before minutes of frames, not after
  std::vector<Measurement> ms;
  for (const bench::SkinBenchMesh& m : meshes)
    for (Measurement& r : measure_mesh(m, o)) ms.push_back(std::move(r));
  print_table(meshes, ms, o);
  if (!o.json.empty()) write_json_atomic(o.json, ms, o);
  return 0;
}

}  // namespace

Run add_bench_skin(CLI::App& bench) {
  auto o = std::make_shared<SkinBenchOptions>();
  CLI::App* sub = bench.add_subcommand("skin", "The skin paper's Table 1: skin vs Blinn vs Lambert render time");
  sub->add_option("--width", o->width, "Image width (default 1024)");
  sub->add_option("--height", o->height, "Image height (default 768)");
  sub->add_option("--threads", o->threads, "Worker threads (default 2)");
  sub->add_option("--frames", o->frames, "Timed frames per mesh and shader (default 30)");
  sub->add_option("--warmup", o->warmup, "Untimed frames before them (default 5)");
  sub->add_option("--json", o->json, "Also write the measurements as a JSON list to FILE");
  sub->add_option("--head", o->head,
                  "The head scan LeePerrySmith.glb (default: found under tools/data/ of the checkout)");
  add_simd_option(*sub);
  return [o] { return run_bench_skin(*o); };
}

}  // namespace pelt::cli
