// `pelt render SCENE.json -o OUT`: renders one frame, a range of frames (an image per
// frame through a `#` pattern, or one animated GIF), or a farm shard of a range.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "raster/parallel.h"
#include "tools/cli/budget_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/simd_option.h"
#include "tools/cli/quality_options.h"
#include "tools/io/gif_writer.h"
#include "tools/io/image_backend.h"
#include "tools/io/exr_writer.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/io/scene.h"
#include "tools/render/frame_sequence.h"
#include "tools/render/interrupt.h"
#include "tools/render/overdraw_heatmap.h"
#include "tools/render/progress.h"
#include "tools/render/scene_renderer.h"

namespace pelt::cli {
namespace {

// Whether a render will need OpenImageIO's module, so that it is worth loading ahead: its frames'
// file type, or maps the scene names (io::needs_image_module_to_write, _to_read; loading the
// module's libraries took 0.4 s, more than the set-up and a frame of a small scene). Maps a mesh
// file names load it when the set-up reaches them: a file may name none (bunny.obj) or only PNGs,
// and ahead of its maps the load would overlap only the mesh's parsing.
bool will_need_image_module(const io::Scene& scene, const std::string& output) {
  if (io::needs_image_module_to_write(output)) return true;
  const auto needs = [](const std::filesystem::path& map) { return !map.empty() && io::needs_image_module_to_read(map); };
  return std::any_of(scene.objects.begin(), scene.objects.end(), [&](const io::SceneObject& o) {
    return needs(o.material.color_map) || needs(o.material.normal_map) || needs(o.fur_length_map);
  });
}

struct RenderOptions {
  std::string scene;
  std::string output;
  int width = 0, height = 0;
  int threads = 0;
  int png_compression = io::kDefaultPngCompression;
  std::string stats;
  std::string aov = "color";
  QualityFlags quality;
  io::Budget budget;
  std::string frame;   // --frame K
  std::string frames;  // --frames A:B
  std::string shard;   // --shard i/N
  bool resume = false;
  bool quiet = false;
};

// The AOVs by name, in the order --help and the error for an unknown one list them.
constexpr std::pair<std::string_view, render::Aov> kAovs[] = {
    {"color", render::Aov::color},       {"depth", render::Aov::depth}, {"id", render::Aov::id},
    {"overdraw", render::Aov::overdraw}, {"sebum", render::Aov::sebum}, {"epidermis", render::Aov::epidermis},
    {"dermis", render::Aov::dermis}};

std::string aov_names(std::string_view separator) {
  std::string names;
  for (const auto& [name, aov] : kAovs) names += (names.empty() ? "" : std::string(separator)) + std::string(name);
  return names;
}

render::Aov parse_aov(const std::string& s) {
  for (const auto& [name, aov] : kAovs)
    if (s == name) return aov;
  throw io::InputError("", "--aov", "unknown AOV `" + s + "` (" + aov_names(", ") + ")");
}

void write_frame(const std::filesystem::path& path, const render::FrameImage& img, render::Aov aov,
                 const io::ImageWriteOptions& options) {
  switch (aov) {
    case render::Aov::depth:
      io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::f32, img.depth.data(), options);
      break;
    case render::Aov::id:
    case render::Aov::overdraw: {
      const std::vector<uint32_t>& counts = aov == render::Aov::id ? img.id : img.overdraw;
      if (aov == render::Aov::overdraw && render::output_kind(path) == render::OutputKind::png) {
        const std::vector<uint8_t> heat = render::heatmap_rgb8(counts);  // a picture of the counts
        io::write_image_atomic(path, img.width, img.height, 3, io::PixelType::u8, heat.data(), options);
      } else if (render::output_kind(path) == render::OutputKind::exr) {
        std::vector<float> f(counts.begin(), counts.end());
        io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::f32, f.data(), options);
      } else {
        io::write_image_atomic(path, img.width, img.height, 1, io::PixelType::u32, counts.data(), options);
      }
      break;
    }
    default: {
      io::ImageWriteOptions colour = options;
      colour.alpha = io::Alpha::premultiplied;  // FrameImage::color
      io::write_image_atomic(path, img.width, img.height, 4, io::PixelType::f32, img.color.data(), colour);
      break;
    }
  }
}

// Everything decided from the options and the scene before any rendering, so a bad
// option costs nothing and leaves no output.
struct Plan {
  render::OutputKind kind = render::OutputKind::png;
  std::vector<int> frames;  // in rendering order
  int planned = 0;          // frames in the range (or shard) before --resume
  render::FrameRange range;  // the frames asked for, before the shard and --resume
};

// The statistics must not replace a frame of the range that this run does not render (one that
// --resume skips, or another shard's), as they may not replace one it renders: the frames it
// could name are the numbers in its name (checking every frame of a range of millions would
// take seconds). A sequence's outputs only; a GIF is one file, checked as such.
void check_stats_spare_frames(io::OutputNames& outputs, const std::string& stats, const render::OutputPattern& pattern,
                              render::FrameRange range) {
  if (!pattern.has_frame_field()) {
    outputs.add_frame(pattern.path_for(range.first), "-o");
    return;
  }
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  for (size_t i = 0; i < stats.size();) {
    if (!digit(stats[i])) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end < stats.size() && digit(stats[end])) ++end;
    size_t first = i;
    while (first + 1 < end && stats[first] == '0') ++first;
    if (end - first <= 9) {  // larger numbers are past any frame (an int)
      const int frame = std::stoi(stats.substr(first, end - first));
      if (frame >= range.first && frame <= range.last) outputs.add_frame(pattern.path_for(frame), "-o");
    }
    i = end;
  }
}

// The run's outputs against its inputs (the scene, a mesh, a map a mesh names: what the set-up
// read) and each other: --stats, the GIF or every frame this run writes, and the range's frames
// the statistics' name could be. Throws InputError naming the output and the other file.
void check_output_names(const std::vector<std::filesystem::path>& inputs, const RenderOptions& o, const Plan& plan,
                        const render::OutputPattern& pattern) {
  io::OutputNames outputs(inputs);
  if (!o.stats.empty()) outputs.add(o.stats, "--stats");
  if (plan.kind == render::OutputKind::gif) {
    outputs.add(o.output, "-o");
    return;
  }
  for (int f : plan.frames) outputs.add_frame(pattern.path_for(f), "-o");
  if (!o.stats.empty()) check_stats_spare_frames(outputs, o.stats, pattern, plan.range);
}

Plan plan_render(const RenderOptions& o, const io::Scene& scene, render::Aov aov,
                 const render::OutputPattern& pattern) {
  Plan plan;
  plan.kind = render::output_kind(o.output);
  const bool gif = plan.kind == render::OutputKind::gif;
  const int frame_count = scene.animation ? scene.animation->frames : 1;
  const render::FrameRange range =
      !o.frame.empty()    ? render::parse_frame(o.frame, frame_count, "--frame")
      : !o.frames.empty() ? render::parse_frame_range(o.frames, frame_count, "--frames")
                          : render::FrameRange{0, frame_count - 1};
  const render::Shard shard = o.shard.empty() ? render::Shard{} : render::parse_shard(o.shard);

  // Depth and ids are values, not colours: an 8-bit sRGB PNG would bend and round them away.
  if ((aov == render::Aov::depth || aov == render::Aov::id) && plan.kind == render::OutputKind::png)
    throw io::InputError(o.output, "--aov",
                         "the " + o.aov + " AOV holds " +
                             (aov == render::Aov::depth ? "float depths" : "32-bit triangle ids") +
                             ", which a PNG cannot store; write it as " +
                             (aov == render::Aov::depth ? ".exr or .tif" : ".tif (32-bit unsigned) or .exr"));
  if (render::skin_layer(aov)) {
    if (std::none_of(scene.objects.begin(), scene.objects.end(),
                     [](const io::SceneObject& obj) { return obj.material.type == io::MaterialType::skin; }))
      throw io::InputError("", "--aov",
                           "the " + o.aov + " AOV is a layer of the skin shader, and no object of " +
                               scene.file.string() + " has a skin material");
  }
  if (gif) {
    // GIF counts a frame's delay in hundredths of a second in 16 bits.
    const double fps = scene.animation ? scene.animation->fps : io::Animation{}.fps;
    if (const std::optional<std::string> refusal = io::gif_fps_refusal(fps))
      throw io::InputError(scene.file.string(), "animation.fps",
                           *refusal + (fps > 100.0 ? " (write a PNG sequence, -o frame_####.png, instead)" : ""));
    if (fps > 50.0)  // a warning, which --quiet does not silence
      std::fprintf(stderr,
                   "pelt: warning: %s (animation.fps): %g frames per second is a GIF delay of 1/100 s, which most web "
                   "browsers play as 1/10 s; 50 fps or fewer plays as asked everywhere\n",
                   scene.file.string().c_str(), fps);
    if (pattern.has_frame_field())
      throw io::InputError(o.output, "-o", "a GIF holds every frame in one file; remove the `#` run");
    if (render::per_pixel_value(aov))
      throw io::InputError("", "--aov", "a GIF holds colour only; write the " + o.aov + " AOV as .exr or .tif" +
                                            (aov == render::Aov::overdraw ? " (or .png, as a heat map)" : ""));
    if (shard.count > 1)
      throw io::InputError("", "--shard", "a GIF is one file and cannot be split across jobs; shard to a "
                                          "PNG sequence (-o out/frame_####.png) instead");
    if (o.resume)
      throw io::InputError("", "--resume", "a GIF is written whole or not at all; resume works with image "
                                           "sequences (-o out/frame_####.png)");
  } else if (range.count() > 1 && !pattern.has_frame_field()) {
    throw io::InputError(o.output, "-o",
                         std::to_string(range.count()) + " frames need a `#` run in the file name for the frame "
                         "number (e.g. out/frame_####.png), or pick one frame with --frame");
  }
  plan.range = range;
  plan.frames = render::shard_frames(range, shard);
  plan.planned = static_cast<int>(plan.frames.size());
  if (o.resume) plan.frames = render::frames_without_output(plan.frames, pattern);
  return plan;
}

int run_render(const RenderOptions& o) {
  const render::Aov aov = parse_aov(o.aov);
  const render::OutputPattern pattern(o.output);
  const io::Scene scene = io::load_scene(o.scene);
  const io::Quality quality = resolve_quality(scene, o.quality);
  const Plan plan = plan_render(o, scene, aov, pattern);
  const render::ProgressMode mode = render::progress_mode(o.quiet, fileno(stderr));
  // Each frame's statistics as the file will hold them, kept only for --stats (a frame's JSON
  // object took about 7 KB, and every frame of a long sequence was kept without --stats too), as
  // text indented for its place in {"frames": [...]}: the same bytes as dumping the whole
  // document, at a third of the memory.
  std::vector<std::string> stats_frames;
  const auto keep_stats = [&](const render::FrameStats& st) {
    if (o.stats.empty()) return;
    std::string text = "    ";
    for (char c : st.to_json().dump(2)) {
      text.push_back(c);
      if (c == '\n') text.append("    ");
    }
    stats_frames.push_back(std::move(text));
  };
  const auto write_stats = [&] {
    if (o.stats.empty()) return;
    io::wait_for_image_backend_preload();  // so that the flag below is the run's
    std::string text = "{\n  \"simd\": \"" + simd_in_use() + "\",\n  \"image_module\": " +
                       (io::image_backend_loaded() ? "true" : "false") + ",\n  \"frames\": [";
    for (size_t i = 0; i < stats_frames.size(); ++i) text.append(i ? ",\n" : "\n").append(stats_frames[i]);
    text.append(stats_frames.empty() ? "]\n}\n" : "\n  ]\n}\n");
    io::write_text_atomic(o.stats, text, "--stats");
  };

  render::RenderSettings rs;
  rs.width = o.width;
  rs.height = o.height;
  rs.threads = worker_threads(o.threads);
  rs.quality = quality;
  rs.budget = o.budget;
  rs.aov = aov;
  rs.output = plan.kind == render::OutputKind::gif ? render::ImageOutput::gif
              : plan.frames.size() == 1           ? render::ImageOutput::still
                                                  : render::ImageOutput::sequence;
  const auto make_renderer = [&](const render::RenderSettings& settings) {
    return naming_flag_origin(scene, o.quality, o.width, o.height,
                              [&] { return std::make_unique<render::SceneRenderer>(scene, settings); });
  };

  if (plan.frames.empty()) {
    // Nothing to finish: a signal while the stats are written ends the run at once, their
    // temporary removed (installed before the probe's temporary, as below).
    const render::InterruptGuard interrupt(render::InterruptGuard::Stop::now);
    if (!o.stats.empty()) {
      // Checked as a render checks them, against the inputs a set-up finds that describes the
      // scene without drawing it.
      render::RenderSettings described = rs;
      described.describe_only = true;
      check_output_names(make_renderer(described)->input_files(), o, plan, pattern);
      io::prepare_output(o.stats, "--stats");
    }
    if (!o.quiet)
      std::fprintf(stderr, "pelt: nothing to render: %s\n",
                   plan.planned == 0 ? ("shard " + o.shard + " has no frames in this range").c_str()
                                     : "every frame's output already exists (--resume)");
    write_stats();
    return 0;
  }

  // OpenImageIO's module, where the render will need it, loads on a thread of its own while the
  // scene is set up and the first frame renders, rather than before everything
  // (tools/io/image_backend.h); the render's
  // worker threads start first, as no thread can start during the load (raster/parallel.h).
  // A signal during the set-up, which writes nothing and has no frame to finish, ends pelt at
  // once, saying so (a farm's log of a job pre-empted there had no line at all).
  std::optional<render::InterruptGuard> during_setup(std::in_place, render::InterruptGuard::Stop::now);
  raster::start_worker_threads(rs.threads);
  io::set_exr_threads(rs.threads);  // EXR frames and maps code their blocks on --threads threads too
  const io::PreloadJoin join_preload;  // declared before the load starts: joined on every way out
  if (will_need_image_module(scene, o.output)) io::preload_image_backend();
  const auto setup_start = std::chrono::steady_clock::now();
  const std::unique_ptr<render::SceneRenderer> owned = make_renderer(rs);
  render::SceneRenderer& renderer = *owned;
  for (const std::string& w : renderer.warnings()) std::fprintf(stderr, "pelt: warning: %s\n", w.c_str());
  // The frames' reports count their own time; what the scene cost once (meshes, maps, fur, the
  // normal blur: the first frame's set-up stages in --stats) is said before them.
  if (mode != render::ProgressMode::quiet)
    std::fprintf(stderr,
                 "pelt: scene set up in %s (meshes, maps, fur, blurred normals: once, before the frames); SIMD %s\n",
                 render::format_duration(
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count())
                     .c_str(),
                 simd_in_use().c_str());
  // Installed before any temporary is created (the writability probes below, the GIF's): a
  // signal that found a temporary but not yet the handler would end the process by the default
  // action and leave the temporary behind. (Installed after the probes, a second Ctrl-C in the
  // moment of a probe did that: the suite's two-signal test caught it on a loaded machine.)
  during_setup.reset();
  render::InterruptGuard interrupt;

  // The destinations are proven writable before the first frame, so a bad path fails now
  // instead of after a whole sequence has rendered.
  check_output_names(renderer.input_files(), o, plan, pattern);
  if (!o.stats.empty()) io::prepare_output(o.stats, "--stats");
  io::prepare_output(plan.kind == render::OutputKind::gif ? std::filesystem::path(o.output)
                                                           : pattern.path_for(plan.frames.front()),
                     "-o");

  std::unique_ptr<io::AnimatedGifWriter> gif;
  if (plan.kind == render::OutputKind::gif) {
    gif = std::make_unique<io::AnimatedGifWriter>(o.output, renderer.width(), renderer.height(),
                                                  scene.animation ? scene.animation->fps : io::Animation{}.fps);
  }

  render::Progress progress(mode, static_cast<int>(plan.frames.size()), stderr);
  int last_done = -1;

  // Frame k is written on a thread of its own while frame k + 1 renders: encoding a PNG
  // (zlib) takes longer than rasterizing a fur frame. One write is in flight at a time, so
  // files (and a GIF's frames) are written in frame order, and a frame counts as done, in the
  // progress and the stats, once its file is written.
  struct Slot {
    render::FrameImage img;
    render::FrameStats st;
    int frame = -1;
    std::chrono::steady_clock::time_point start;
  };
  Slot slots[2];
  std::exception_ptr write_error;
  std::thread writer;
  // Joins a write still in flight on every way out (a render error, an exception below),
  // before the slots and the GIF writer it uses are destroyed.
  struct JoinWriter {
    std::thread& t;
    ~JoinWriter() {
      if (t.joinable()) t.join();
    }
  } join_writer{writer};
  Slot* pending = nullptr;
  auto write_slot = [&](Slot& slot) {
    try {
      render::StageTimer t(slot.st, "write");
      if (gif) {
        gif->add_frame(slot.img.color.data());
      } else {
        const std::filesystem::path path = pattern.path_for(slot.frame);
        io::prepare_output(path, "-o");  // a pattern may put frames in folders of their own
        write_frame(path, slot.img, aov, io::ImageWriteOptions{o.png_compression});
      }
    } catch (...) {
      write_error = std::current_exception();
    }
  };
  auto finish_write = [&] {
    if (!pending) return;
    writer.join();
    Slot& slot = *pending;
    pending = nullptr;
    if (write_error) std::rethrow_exception(write_error);
    keep_stats(slot.st);
    last_done = slot.frame;
    progress.frame_done(slot.frame,
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - slot.start).count());
  };
  size_t next = 0;
  try {
    for (int frame : plan.frames) {
      if (render::InterruptGuard::requested()) break;
      Slot& slot = slots[next];
      next ^= 1;
      slot.frame = frame;
      slot.start = std::chrono::steady_clock::now();
      renderer.render(frame, slot.img, slot.st);
      finish_write();
      pending = &slot;
      writer = std::thread([&write_slot, &slot] { write_slot(slot); });
    }
    finish_write();
  } catch (...) {
    // The frames already written are done and --resume skips them: their statistics are
    // kept as an interrupted run keeps them. The error that stopped the run is the one told.
    if (writer.joinable()) writer.join();
    try {
      write_stats();
    } catch (const std::exception&) {
    }
    throw;
  }
  progress.finish();

  const int done = progress.done();
  const int total = static_cast<int>(plan.frames.size());
  if (done < total) {
    write_stats();
    const std::string after = last_done < 0 ? std::string("before any frame was written")
                                            : "after frame " + std::to_string(last_done);
    std::fprintf(stderr, "pelt: interrupted %s: %d of %d frame(s) rendered%s\n", after.c_str(), done, total,
                 gif ? "; the GIF was not written"
                     : (done > 0 ? "; run again with --resume to render the rest" : ""));
    return 128 + render::InterruptGuard::signal_number();  // as shells report a signal's end
  }
  if (gif) gif->commit();
  write_stats();
  if (render::InterruptGuard::requested()) {
    // The signal came during the last frame, which was finished as any frame in flight is: every
    // output is complete, and the exit status still says the run was interrupted, so a script
    // looping over renders (or a farm's scheduler) sees the signal.
    std::fprintf(stderr, "pelt: interrupted during the last frame (%d): every frame was written\n", last_done);
    return 128 + render::InterruptGuard::signal_number();
  }
  return 0;
}

}  // namespace

Run add_render_command(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* sub = app.add_subcommand("render", "Render a scene: one frame, a frame range or a farm shard");
  sub->add_option("scene", o->scene, "Scene file (JSON, version 1)")->required();
  sub->add_option("-o,--output", o->output,
                  "Output: .png, .exr, .tif with `#` for the frame number (out/frame_####.png), or .gif")
      ->required();
  add_image_options(*sub, o->width, o->height, o->threads);
  add_simd_option(*sub);
  sub->add_option("--png-compression", o->png_compression,
                  "PNG zlib level: 0 (fastest) to 9 (smallest) (default: " +
                      std::to_string(io::kDefaultPngCompression) + ")")
      ->check(CLI::Range(0, 9));
  sub->add_option("--stats", o->stats, "Write per-frame stage statistics as JSON");
  sub->add_option("--aov", o->aov, aov_names(" | "));
  add_quality_options(*sub, o->quality);
  add_budget_options(*sub, o->budget);
  CLI::Option* frame = sub->add_option("--frame", o->frame, "One frame of the animation (0-based)");
  CLI::Option* frames =
      sub->add_option("--frames", o->frames, "Frame range FIRST:LAST, inclusive (default: every frame)");
  frame->excludes(frames);
  sub->add_option("--shard", o->shard, "Render only part INDEX/COUNT of the range: every COUNT-th frame "
                                       "from FIRST + INDEX (0-based)");
  sub->add_flag("--resume", o->resume, "Skip frames whose output file already exists");
  sub->add_flag("-q,--quiet", o->quiet, "No progress report");
  return [o] { return run_render(*o); };
}

}  // namespace pelt::cli
