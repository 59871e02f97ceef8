// `pelt tradeoff SCENE.json`: what each quality knob costs in time and buys in accuracy.
// Renders the reference once, then every knob's settings one at a time on top of the
// scene's own quality, then the presets; times each frame (every setting twice, on the way
// through the sweep and back), measures its error against the reference and writes a CSV, a
// markdown table and a plot of error against time.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "tools/cli/budget_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/simd_option.h"
#include "tools/cli/quality_options.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/io/scene.h"
#include "tools/render/frame_timing.h"
#include "tools/render/scene_renderer.h"
#include "tools/tradeoff/image_compare.h"
#include "tools/tradeoff/pareto.h"
#include "tools/tradeoff/plot.h"
#include "tools/tradeoff/report.h"
#include "tools/tradeoff/sweep.h"
#include "tools/render/interrupt.h"

namespace pelt::cli {
namespace {

namespace fs = std::filesystem;

struct TradeoffOptions {
  std::string scene;
  std::string output;  // empty: out/tradeoff/<scene file stem>
  int runs = 5;
  int threads = 0;
  int width = 0, height = 0;
  std::string knobs;  // --knobs
  bool knobs_given = false;  // false: every knob of io::kKnobs
  bool no_plot = false;
  bool images = false;
  io::Budget budget;
};

// One setting's measurement: its timed runs (ms), with a baseline each run's time over the
// baseline's frame drawn beside it, and the image it made.
struct Measured {
  std::vector<double> ms, ratios;
  tradeoff::DisplayImage image;
};

render::RenderSettings settings(const io::Quality& q, const io::Budget& budget, int threads, int width, int height) {
  render::RenderSettings rs;
  rs.budget = budget;
  rs.width = width;
  rs.height = height;
  rs.threads = threads;
  rs.quality = q;
  return rs;
}

// Frame 0 of `renderer` into `img`.
void draw(render::SceneRenderer& renderer, render::FrameImage& img) {
  render::FrameStats stats;
  renderer.render(0, img, stats);
}

// The reference is slow (64 samples a pixel in double precision): one timed frame, the
// first, is enough to place it on the plot. With `baseline` (the default's renderer), each
// timed frame is drawn right beside one of the baseline's (render::time_side_by_side).
Measured measure(const io::Scene& scene, const render::RenderSettings& rs, int runs, bool warm_up,
                 render::SceneRenderer* baseline = nullptr) {
  render::SceneRenderer renderer(scene, rs);
  render::FrameImage img, baseline_img;
  if (warm_up) draw(renderer, img);
  // The baseline's own warm-up after this renderer's: the first baseline frame after another
  // setting's frames finds its data evicted (in a first sweep one such frame took three times as long).
  if (baseline) draw(*baseline, baseline_img);
  Measured m;
  for (int i = 0; i < runs; ++i) {
    auto frame = [&] { draw(renderer, img); };
    if (!baseline) {
      m.ms.push_back(render::time_ms(frame));
      continue;
    }
    const auto [ms, base_ms] = render::time_side_by_side(i, frame, [&] { draw(*baseline, baseline_img); });
    m.ms.push_back(ms);
    m.ratios.push_back(ms / base_ms);
  }
  m.image = tradeoff::to_display(img.width, img.height, img.color);
  return m;
}

size_t image_hash(const tradeoff::DisplayImage& image) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(image.rgba.data()), image.rgba.size()));
}

std::string label(const tradeoff::Setting& s) { return s.knob + "=" + s.setting; }

// Where --images writes a row's image.
fs::path image_path(const fs::path& dir, const tradeoff::Setting& s) {
  return dir / "images" / (s.knob + "_" + s.setting + ".png");
}

// SceneRenderer names the scene's fields in a budget refusal (`image.width`, `quality.shells`,
// `quality.spp`), but a size from --width or --height, or shells and samples that the sweep
// chose (the reference's 64), are not in the scene: the message names where they came from.
io::InputError name_origin(const io::InputError& e, const io::Scene& scene, const tradeoff::Setting& s, int width,
                           int height) {
  const io::InputError flagged = name_flag_origin(e, scene, QualityFlags{}, width, height);
  if (flagged.file != e.file) return flagged;
  // The blur's pair budget names the material's radius; a row that set the model asked for it.
  const bool blur_of_the_row = e.field.ends_with("normal_blur_radius") && s.quality.multiple_scattering.has_value();
  if (e.file == scene.file.string() &&
      ((e.field == "quality.shells" && s.quality.shells != scene.quality.shells) ||
       (e.field == "quality.spp" && s.quality.spp != scene.quality.spp) || blur_of_the_row))
    return io::InputError("", "the sweep's " + label(s) + " row", e.reason);
  return e;
}

int run_tradeoff(const TradeoffOptions& o) {
  // Everything that can be refused is checked before the first render and the first file.
  const std::vector<std::string> knobs = o.knobs_given ? tradeoff::parse_knob_list(o.knobs)
                                                       : std::vector<std::string>(std::begin(io::kKnobs),
                                                                                  std::end(io::kKnobs));
  const io::Scene scene = io::load_scene(o.scene);
  const fs::path dir = o.output.empty() ? fs::path("out") / "tradeoff" / fs::path(o.scene).stem() : fs::path(o.output);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw io::InputError(dir.string(), "-o", "exists and is not a folder");
  const int threads = worker_threads(o.threads);
  const std::vector<tradeoff::Setting> plan = tradeoff::plan_sweep(scene.quality, knobs);
  // Before the probe's temporary: a signal ends the run at once, temporaries removed (render/interrupt.h).
  const render::InterruptGuard interrupt(render::InterruptGuard::Stop::now);
  // With --images, each row's image, in the plan's order.
  std::vector<fs::path> row_images;
  if (o.images)
    for (const tradeoff::Setting& s : plan) row_images.push_back(image_path(dir, s));
  // Every row's budget (pixels, shells, memory, the normal blur's pairs) and every file the
  // sweep writes are checked before the reference, which can take minutes: a row refused when the
  // sweep reached it, or a plot or image that could not be written, failed after it. Each row is
  // described, not drawn, from the meshes loaded once; the description also finds the inputs (the
  // scene, a mesh, a map a mesh names), which no output may be. Folders are made last, so a
  // refusal leaves none.
  {
    const std::vector<io::SceneMesh> meshes = io::load_scene_meshes(scene, o.budget);
    std::vector<fs::path> inputs;
    for (const tradeoff::Setting& s : plan) {
      if (s.same_as) continue;
      render::RenderSettings row = settings(s.quality, o.budget, threads, o.width, o.height);
      row.describe_only = true;
      try {
        const render::SceneRenderer described(scene, meshes, row);
        if (inputs.empty()) inputs = described.input_files();
      } catch (const io::InputError& e) {
        throw name_origin(e, scene, s, o.width, o.height);
      }
    }
    std::vector<std::pair<fs::path, std::string>> outputs{{dir / "tradeoff.csv", "-o"}, {dir / "tradeoff.md", "-o"}};
    if (!o.no_plot) outputs.push_back({dir / "tradeoff.png", "-o"});
    for (const fs::path& image : row_images) outputs.push_back({image, "--images"});
    io::OutputNames names(inputs, "tradeoff");
    for (const auto& [path, option] : outputs) names.add(path, option);
    for (const auto& [path, option] : outputs) io::prepare_output(path, option);
  }

  std::vector<tradeoff::Row> rows;
  std::vector<tradeoff::DisplayImage> images;  // per row, kept only with --images
  struct FirstPass {
    std::vector<double> ms;  // timed runs
    size_t image_hash = 0;   // what the way back must render again
  };
  std::vector<FirstPass> first(plan.size());  // per rendered row
  tradeoff::DisplayImage reference;
  int rendered = 0;
  const int to_render = int(std::count_if(plan.begin(), plan.end(), [](const auto& s) { return !s.same_as; }));
  for (size_t i = 0; i < plan.size(); ++i) {
    const tradeoff::Setting& s = plan[i];
    tradeoff::Row row;
    row.knob = s.knob;
    row.setting = s.setting;
    row.preset = s.knob == tradeoff::kPresetKnob;
    if (s.same_as) {  // its measurement is copied from the earlier row once both passes are done
      const tradeoff::Row& earlier = rows[*s.same_as];
      row.same_as = earlier.knob + "=" + earlier.setting;
      std::fprintf(stderr, "pelt tradeoff: %s: same settings as %s, measurement reused\n", label(s).c_str(),
                   row.same_as.c_str());
      if (o.images) images.push_back(images[*s.same_as]);
    } else {
      const bool is_reference = i == 0;
      std::fprintf(stderr, "pelt tradeoff: [%d/%d] %s (%s)...\n", ++rendered, to_render, label(s).c_str(),
                   io::describe(s.quality).c_str());
      Measured m = [&] {
        try {
          return measure(scene, settings(s.quality, o.budget, threads, o.width, o.height), is_reference ? 1 : o.runs,
                         !is_reference);
        } catch (const io::InputError& e) {
          throw name_origin(e, scene, s, o.width, o.height);
        }
      }();
      if (is_reference) reference = m.image;
      row.time = tradeoff::summarize(m.ms, !is_reference);
      row.error = tradeoff::compare(m.image, reference);
      first[i] = {std::move(m.ms), image_hash(m.image)};
      std::fprintf(stderr, "pelt tradeoff:        %s ms median, rmse %s, psnr %s dB\n",
                   tradeoff::format_ms(row.time.median, true).c_str(),
                   tradeoff::format_number(row.error.rmse, 4).c_str(),
                   tradeoff::format_number(row.error.psnr_db, 4).c_str());
      if (o.images) images.push_back(std::move(m.image));
    }
    rows.push_back(std::move(row));
  }

  // The way back: every row timed again in reverse order (tradeoff::second_pass_order), its
  // time the faster pass's median, and each of its frames drawn beside one of the default's
  // for the paired ratio. The image must come out the same, bit for bit.
  const std::vector<size_t> back = tradeoff::second_pass_order(plan);
  const size_t default_row = size_t(std::find_if(plan.begin(), plan.end(), [&](const tradeoff::Setting& s) {
                                      return s.knob == tradeoff::kDefaultKnob;
                                    }) - plan.begin());
  render::SceneRenderer baseline(scene, settings(plan.at(default_row).quality, o.budget, threads, o.width, o.height));
  rows.at(default_row).baseline = true;
  for (size_t k = 0; k < back.size(); ++k) {
    const size_t i = back[k];
    std::fprintf(stderr, "pelt tradeoff: [way back %zu/%zu] %s...\n", k + 1, back.size(), label(plan[i]).c_str());
    Measured m = measure(scene, settings(plan[i].quality, o.budget, threads, o.width, o.height), o.runs, true,
                         i == default_row ? nullptr : &baseline);
    if (!m.ratios.empty()) rows[i].vs_default = tradeoff::summarize_ratios(m.ratios);
    if (image_hash(m.image) != first[i].image_hash)
      throw std::logic_error("tradeoff: " + label(plan[i]) + " rendered a different image on the way back (a " +
                             "render that is not deterministic is a bug)");
    const double first_median = rows[i].time.median;
    rows[i].time = tradeoff::combine_passes(first[i].ms, m.ms);
    std::fprintf(stderr, "pelt tradeoff:        %s ms median (first pass %s)\n",
                 tradeoff::format_ms(tradeoff::summarize(m.ms).median, true).c_str(),
                 tradeoff::format_ms(first_median, true).c_str());
  }
  for (size_t i = 0; i < plan.size(); ++i)
    if (plan[i].same_as) tradeoff::reuse_measurement(rows[i], rows[*plan[i].same_as]);

  std::vector<tradeoff::CostPoint> points;
  for (const tradeoff::Row& r : rows) points.push_back({r.time.median, r.error.rmse});
  const std::vector<bool> front = tradeoff::pareto_front(points);

  std::ostringstream csv;
  tradeoff::write_csv(csv, rows);
  const std::string table = tradeoff::markdown_table(rows, front);
  // What every row ran at, for the table's text and the plot's title.
  const std::string scene_name = fs::path(o.scene).filename().string();
  const std::string ran_at = std::to_string(reference.width) + "x" + std::to_string(reference.height) + ", " +
                             std::to_string(threads) + " thread(s), SIMD " + simd_in_use();
  // Composed as a string: a fixed buffer would cut the text short without a word as it grows.
  const std::string about =
      "`pelt tradeoff " + scene_name + "`: " + ran_at +
      ". Every row but the reference is timed twice, on the way through the sweep and again on the way "
      "back, each time " + std::to_string(o.runs) +
      " frames after one warm-up frame; its time is the faster pass's median, its range covers both. On the way back "
      "each of a row's frames is drawn right beside one of the default's, taking turns at going first: `vs default, "
      "paired` is the median (and range) of those frames' time ratios, steadier than the milliseconds on a shared "
      "machine. The reference: one timed frame, its first, no warm-up. Error against the reference on the 8-bit sRGB "
      "RGB image `pelt render` writes. `pareto` = no other row is both faster and closer.\n\n";
  const std::string markdown = about + table;

  io::write_text_atomic(dir / "tradeoff.csv", csv.str(), "-o");
  io::write_text_atomic(dir / "tradeoff.md", markdown, "-o");
  if (o.images) {
    for (size_t i = 0; i < rows.size(); ++i)
      io::write_image_atomic(row_images[i], images[i].width, images[i].height, 4, io::PixelType::u8,
                             images[i].rgba.data());
  }
  std::fwrite(table.data(), 1, table.size(), stdout);
  std::fflush(stdout);

  // Outputs an earlier run left in the folder stay (pelt removes no file it did not write this
  // run), beside the new CSV: the user is told which do not show this sweep. The row images
  // are counted for the folder's own files only.
  const std::set<fs::path> drawn(row_images.begin(), row_images.end());
  auto stale_outputs = [&](bool plot_written) {
    std::string note;
    std::error_code ec;
    const fs::path png = dir / "tradeoff.png";
    if (!plot_written && fs::exists(png, ec))
      note += "; " + png.string() + " is an earlier run's plot and does not show this sweep";
    size_t old_images = 0;
    std::string first;
    for (fs::directory_iterator it(dir / "images", ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".png" && !drawn.count(it->path()) && old_images++ == 0)
        first = it->path().filename().string();
    if (old_images > 0)
      note += "; " + (dir / "images").string() + " holds " + std::to_string(old_images) + " row image" +
              (old_images == 1 ? "" : "s") + " of an earlier sweep (" + first + (old_images > 1 ? ", ..." : "") +
              ") that this one did not draw";
    return note;
  };
  if (o.no_plot) {
    std::fprintf(stderr, "pelt tradeoff: wrote %s and %s (no plot: --no-plot%s)\n",
                 (dir / "tradeoff.csv").string().c_str(), (dir / "tradeoff.md").string().c_str(),
                 stale_outputs(false).c_str());
    return 0;
  }
  const tradeoff::PlotOutcome plot =
      tradeoff::make_plot(dir / "tradeoff.csv", dir / "tradeoff.png",
                          "pelt tradeoff " + scene_name + " (" + ran_at + ")",
                          front);
  if (!plot.made) {
    std::fprintf(stderr,
                 "pelt: error: plot: %s; %s and %s were written, the plot was not made (or pass --no-plot)%s\n",
                 plot.problem.c_str(), (dir / "tradeoff.csv").string().c_str(),
                 (dir / "tradeoff.md").string().c_str(), stale_outputs(false).c_str());
    return 2;
  }
  std::fprintf(stderr, "pelt tradeoff: wrote %s, %s and %s%s\n", (dir / "tradeoff.csv").string().c_str(),
               (dir / "tradeoff.md").string().c_str(), (dir / "tradeoff.png").string().c_str(),
               stale_outputs(true).c_str());
  return 0;
}

}  // namespace

Run add_tradeoff_command(CLI::App& app) {
  auto o = std::make_shared<TradeoffOptions>();
  CLI::App* sub = app.add_subcommand(
      "tradeoff", "Measure what each quality knob costs in time and error against the reference renderer");
  sub->add_option("scene", o->scene, "Scene file (JSON, version 1); its `quality` block is the default row")
      ->required();
  sub->add_option("-o,--output", o->output, "Output folder (default: out/tradeoff/<scene file stem>)");
  sub->add_option("--runs", o->runs, "Timed frames per setting and pass, after one warm-up each (at least 5)")
      ->check(CLI::Range(5, 1000));
  add_image_options(*sub, o->width, o->height, o->threads);
  add_simd_option(*sub);
  std::string knob_names;
  for (std::string_view k : io::kKnobs) knob_names += (knob_names.empty() ? "" : ",") + std::string(k);
  CLI::Option* knobs =
      sub->add_option("--knobs", o->knobs, "Knobs to sweep, comma-separated (default: " + knob_names + ")");
  add_budget_options(*sub, o->budget);
  sub->add_flag("--no-plot", o->no_plot, "Write the CSV and markdown only, without running python3");
  sub->add_flag("--images", o->images, "Also write every setting's image as <output>/images/<knob>_<setting>.png");
  return [o, knobs] {
    o->knobs_given = knobs->count() > 0;
    return run_tradeoff(*o);
  };
}

}  // namespace pelt::cli
