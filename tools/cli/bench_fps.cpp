// `pelt bench fps`: the fur paper's Tables 1-3 (Box, Teapot, Teapot2) measured on this
// CPU: counts in the seed's layout and median FPS of an animated run (orbiting camera,
// the wind lerp every frame, every frame fully rasterized into memory: an RGBA8 framebuffer, as
// the paper's GPU and the llvmpipe harness draw into, or pelt's float RGBA with --framebuffer).
// --versus prices a quality knob on a shared, noisy machine: every frame is drawn with both
// settings, one right after the other, and the per-frame ratio of their times is reported.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "raster/simd_targets.h"
#include "tools/cli/budget_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/simd_option.h"
#include "tools/cli/quality_options.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"
#include "tools/render/frame_timing.h"
#include "tools/render/scene_renderer.h"
#include "tools/render/interrupt.h"

namespace pelt::cli {
namespace {

struct PaperTable {
  const char* name;      // our scene name (as in the llvmpipe harness)
  const char* mesh;      // built-in spec
  const char* paper;     // the seed's caption
  int vertex[4];         // Base, Shell, Fin, Sum as printed in the seed
  int face[4];
  double fps;            // GeForce 7600GT, "about"
};

constexpr PaperTable kTables[] = {
    {"box", "box:7", "Table 1, Mesh 1 \"Box.obj\"", {296, 4736, 4736, 5032}, {588, 9408, 26460, 36456}, 30},
    {"teapot", "teapot:3", "Table 2, Mesh 2 \"Teapot.obj\"", {302, 4832, 4832, 5134}, {552, 8832, 25560, 34944}, 30},
    {"teapot2", "teapot:5", "Table 3, Mesh 3 \"Teapot2.obj\"", {882, 13152, 13152, 14034}, {1560, 24960, 71400, 97920}, 10},
};

struct Options {
  std::vector<std::string> scenes{"box", "teapot", "teapot2"};
  int width = 1024, height = 768;
  std::vector<int> threads{1, 2};
  int frames = 200, warmup = 20;
  bool match_llvmpipe = false;
  std::string sort;  // empty: tile, or none with --match-llvmpipe (the harness's order)
  std::string filter;  // empty: trilinear (the harness's filter too)
  std::string fins;    // empty: silhouette, or all with --match-llvmpipe (the harness draws every fin)
  std::string shells;  // empty: 16, the paper's
  std::string fin_quads;  // empty: the default quality's
  std::string json;
  // --versus "knob=value[,knob=value]": the run's quality with these knobs changed, drawn
  // frame by frame beside it (unset: none).
  std::optional<std::string> versus;
  // "rgba8": RGBA8 UNORM bytes (raster::RenderTarget::color8), the GPU's and the harness's
  // framebuffer; "float": linear float RGBA, what `pelt render` resolves to (four times the bytes).
  std::string framebuffer = "rgba8";
  bool rgba8() const { return framebuffer == "rgba8"; }
};

constexpr float kElevationDeg = 20.0f;
constexpr int kPaperShells = 16;
constexpr float kFovyDeg = 45.0f;

// The harness draws every fin; pelt's own run fades them in near silhouettes.
fur::FinMode default_fins(bool match) { return match ? fur::FinMode::all : fur::FinMode::silhouette; }

io::Camera orbit_camera(float distance, float radius, float azimuth) {
  const float el = glm::radians(kElevationDeg);
  io::Camera c;
  c.eye = distance * glm::vec3(std::cos(el) * std::sin(azimuth), std::sin(el), std::cos(el) * std::cos(azimuth));
  c.target = glm::vec3(0.0f);
  c.up = glm::vec3(0, 1, 0);
  c.fovy_deg = kFovyDeg;
  c.near = distance - 1.3f * radius;
  c.far = distance + 1.3f * radius;
  return c;
}

float azimuth(int frame, bool match) {
  // The harness turns 0.002 rad a frame from 0.6 rad; pelt's own run turns 1 degree a frame.
  return match ? 0.6f + 0.002f * frame : 0.6f + glm::radians(1.0f) * frame;
}

// The distance at which the mesh spans 60% of the image height at frame 0 (the harness's
// framing), by bisection on the projected vertical extent of its vertices.
float framing_distance(const Mesh& m, float radius, float aspect) {
  auto span = [&](float d) {
    const io::Camera c = orbit_camera(d, radius, azimuth(0, true));
    const glm::mat4 vp = c.projection(aspect) * c.view();
    float lo = 1e30f, hi = -1e30f;
    for (const glm::vec3& p : m.positions) {
      const glm::vec4 q = vp * glm::vec4(p, 1.0f);
      lo = std::min(lo, q.y / q.w);
      hi = std::max(hi, q.y / q.w);
    }
    return 0.5f * (hi - lo);
  };
  float a = 1.3f * radius + 1e-3f, b = 100.0f * radius;
  for (int i = 0; i < 80; ++i) {
    const float mid = 0.5f * (a + b);
    (span(mid) > 0.6f ? a : b) = mid;
  }
  return 0.5f * (a + b);
}

io::Scene bench_scene(const PaperTable& t, bool match) {
  io::Scene s;
  s.file = std::string("<bench fps ") + t.name + ">";
  s.image.background = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  io::Light sun;
  sun.type = io::LightType::directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  s.lights.push_back(sun);
  if (!match) {
    io::Light amb;
    amb.type = io::LightType::ambient;
    amb.color = glm::vec3(0.35f);
    s.lights.push_back(amb);
  }
  io::SceneObject o;
  o.name = t.name;
  o.mesh = t.mesh;
  o.builtin = io::parse_builtin_spec(t.mesh);
  o.material.type = io::MaterialType::lambert;
  o.material.color = glm::vec3(0.8f, 0.58f, 0.36f) * 0.45f;
  fur::FurParams fp;
  fp.shells = kPaperShells;
  fp.texture_size = 256;
  fp.length = 0.1f;
  fp.density = 30.0f;
  fp.fins = default_fins(match);
  if (!match) {
    fp.gravity = fur::GravityParams{};
    fp.wind = fur::WindParams{};
  }
  o.fur = fp;
  s.objects.push_back(o);
  io::Animation a;
  a.frames = 1 << 20;
  a.fps = 60.0;
  s.animation = a;
  return s;
}

struct Result {
  const PaperTable* table = nullptr;
  int threads = 0;
  std::vector<double> ms{};
  fur::FurCounts counts{};
  // The work of the timed frames, summed (raster::RasterStats): what a frame's time buys.
  uint64_t fragments_blended = 0, lanes_shaded = 0, pixels_shaded = 0;
  // With --versus: the other setting's time for each timed frame (same camera, same frame),
  // and per frame its time over this run's.
  std::vector<double> versus_ms{}, versus_ratio{};

  // --versus's figures, read by the printed line and the JSON alike.
  struct Versus {
    double ratio_median, ratio_q25, ratio_q75, fps_median;
  };
  Versus versus() const {
    return {render::quantile(versus_ratio, 0.5), render::quantile(versus_ratio, 0.25), render::quantile(versus_ratio, 0.75),
            1000.0 / render::quantile(versus_ms, 0.5)};
  }

  double mean(uint64_t sum) const { return double(sum) / double(ms.size()); }
  // Nanoseconds per blended fragment at the median frame time, on all of the run's threads;
  // none when no fragment was blended (a frame too small to show the fur).
  std::optional<double> ns_per_fragment() const {
    if (fragments_blended == 0) return std::nullopt;
    return render::quantile(ms, 0.5) * 1e6 / mean(fragments_blended);
  }
};

// The quality knobs of every run: the harness draws in submission order and every fin, pelt's
// default sorts per tile, fades the fins in near silhouettes and merges their quads where the
// strands run straight (`fin_quads`, which the harness's mode refuses); --sort and --fins override
// both, --filter overrides trilinear and --shells the paper's 16 (re-sliced at the same optical
// depth, so the fur's look holds and only its cost and accuracy move). Throws io::InputError
// for a bad value.
io::Quality bench_quality(const Options& o) {
  io::Quality q;
  q.sort = o.match_llvmpipe ? io::SortQuality::none : io::SortQuality::tile;
  q.fins = default_fins(o.match_llvmpipe);
  q.shells = kPaperShells;
  if (o.match_llvmpipe) q.fin_quads = io::FinQuads::layer;  // the harness draws eq. 1's quads
  for (const auto& [knob, value] : {std::pair{"sort", &o.sort}, std::pair{"filter", &o.filter},
                                    std::pair{"fins", &o.fins}, std::pair{"shells", &o.shells},
                                    std::pair{"fin_quads", &o.fin_quads}})
    apply_knob_flag(q, knob, *value);
  if (o.match_llvmpipe && q.fin_quads == io::FinQuads::merged)
    throw io::InputError("", "--fin-quads", "merged fins are not drawn with --match-llvmpipe (the harness's fins are "
                                            "one quad per pair of layers)");
  return q;
}

// What --versus draws each frame with besides the run's setting.
struct VersusSetting {
  io::Quality quality;
  std::string simd;  // another SIMD target ("": the run's own)
};

// The knobs of --versus applied to the run's quality `base`: "knob=value" pairs separated by
// commas, knob names as in `pelt tradeoff` (e.g. "filter=bilinear_mip,fins=off"), and `simd`
// for another SIMD target (e.g. "simd=avx2": the price of the vector width). Throws
// io::InputError naming --versus for a malformed pair, an unknown knob or value, a knob given
// twice, or a setting that changes nothing (a comparison of a run with itself, or of skin
// knobs in scenes without skin).
VersusSetting versus_setting(const std::string& spec, const io::Quality& base, bool match_llvmpipe) {
  VersusSetting v{base, ""};
  io::Quality& q = v.quality;
  std::vector<std::string> seen;
  // getline finds no item after a last comma: an empty one, refused as the others are.
  if (!spec.empty() && spec.back() == ',') throw io::InputError("", "--versus", "`" + spec + "` has an empty item");
  std::stringstream pairs(spec);
  std::string pair;
  while (std::getline(pairs, pair, ',')) {
    const size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size())
      throw io::InputError("", "--versus", "`" + pair + "` is not knob=value (e.g. filter=bilinear_mip)");
    const std::string knob = pair.substr(0, eq), value = pair.substr(eq + 1);
    if (std::find(seen.begin(), seen.end(), knob) != seen.end())
      throw io::InputError("", "--versus", "knob `" + knob + "` given twice");
    seen.push_back(knob);
    if (knob == "simd") {
      if (value == "auto") throw io::InputError("", "--versus", "simd=auto: name a target (" + simd_runnable() + ")");
      if (std::string e = raster::simd_pin_refusal(value, raster::runnable_simd_targets()); !e.empty())
        throw io::InputError("", "--versus", "simd=" + value + ": " + e);
      if (value != simd_in_use()) v.simd = value;
      continue;
    }
    if (auto e = io::set_knob(q, knob, value)) throw io::InputError("", "--versus", *e);
  }
  if (seen.empty()) throw io::InputError("", "--versus", "no knob=value given (e.g. filter=bilinear_mip)");
  if (q == base && v.simd.empty())
    throw io::InputError("", "--versus", "`" + spec + "` is the run's own setting: nothing to compare");
  // The benchmark's scenes are fur on a lambert base: the skin's knobs draw the same frame.
  io::Quality fur_knobs = q;
  fur_knobs.multiple_scattering = base.multiple_scattering;
  fur_knobs.single_scattering = base.single_scattering;
  if (fur_knobs == base && v.simd.empty())
    throw io::InputError("", "--versus", "`" + spec + "` changes only skin knobs, and the benchmark's scenes have no "
                                         "skin: the same frame, nothing to compare");
  if (match_llvmpipe && q.fin_quads == io::FinQuads::merged)
    throw io::InputError("", "--versus", "merged fins are not drawn with --match-llvmpipe (the harness's fins are "
                                         "one quad per pair of layers)");
  return v;
}

// The knobs whose value in `other` differs from the run's, with that value, in kKnobs order.
std::vector<std::pair<std::string, std::string>> differing_knobs(const io::Quality& run, const io::Quality& other) {
  std::vector<std::pair<std::string, std::string>> knobs;
  for (std::string_view knob : io::kKnobs)
    if (std::string v = io::knob_value(other, knob); v != io::knob_value(run, knob)) knobs.emplace_back(knob, std::move(v));
  return knobs;
}

// The knobs whose value differs, the SIMD target last.
std::vector<std::pair<std::string, std::string>> differing_knobs(const io::Quality& run, const VersusSetting& other) {
  std::vector<std::pair<std::string, std::string>> knobs = differing_knobs(run, other.quality);
  if (!other.simd.empty()) knobs.emplace_back("simd", other.simd);
  return knobs;
}

// One line of the setting that differs: "filter=bilinear_mip fins=off".
std::string versus_label(const io::Quality& run, const VersusSetting& other) {
  std::string label;
  for (const auto& [knob, value] : differing_knobs(run, other)) label += (label.empty() ? "" : " ") + knob + "=" + value;
  return label;
}

Result run_one(const PaperTable& t, int threads, const Options& o, const io::Quality& q,
               const VersusSetting* versus) {
  const io::Scene scene = bench_scene(t, o.match_llvmpipe);
  std::vector<io::SceneMesh> meshes(1);
  meshes[0].loaded.mesh = io::make_builtin_mesh(t.mesh);
  const Mesh& m = meshes[0].loaded.mesh;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::vec3 centre = 0.5f * (lo + hi);
  float radius = 0.0f;
  for (const glm::vec3& p : m.positions) radius = std::max(radius, glm::length(p - centre));
  const float aspect = float(o.width) / float(o.height);
  const float distance = framing_distance(m, radius, aspect);

  render::RenderSettings rs;
  rs.width = o.width;
  rs.height = o.height;
  rs.threads = threads;
  rs.match_llvmpipe = o.match_llvmpipe;
  rs.quality = q;
  rs.color8 = o.rgba8();
  std::optional<render::SceneRenderer> other;  // --versus: the same scene with the other setting
  if (versus) {
    std::vector<io::SceneMesh> other_meshes(1);
    other_meshes[0].loaded.mesh = m;
    render::RenderSettings vs = rs;
    vs.quality = versus->quality;
    other.emplace(scene, std::move(other_meshes), vs);
  }
  render::SceneRenderer r(scene, std::move(meshes), rs);
  render::FrameImage img;
  render::FrameStats st, other_st;
  Result res{.table = &t, .threads = threads, .counts = *r.fur_counts(0)};
  for (int f = 0; f < o.warmup + o.frames; ++f) {
    const io::Camera cam = orbit_camera(distance, radius, azimuth(f, o.match_llvmpipe));
    auto draw = [&] { r.render(f, img, st, &cam); };
    double ms = 0.0, other_ms = 0.0;
    if (other)
      std::tie(ms, other_ms) = render::time_side_by_side(f, draw, [&] {
        std::optional<raster::SimdTargetScope> target;
        if (!versus->simd.empty()) target.emplace(versus->simd);
        other->render(f, img, other_st, &cam);
      });
    else
      ms = render::time_ms(draw);
    if (f >= o.warmup) {
      res.ms.push_back(ms);
      res.fragments_blended += st.raster.fragments_blended;
      res.lanes_shaded += st.raster.lanes_shaded;
      res.pixels_shaded += st.raster.pixels_shaded;
      if (other) {
        res.versus_ms.push_back(other_ms);
        res.versus_ratio.push_back(other_ms / ms);
      }
    }
  }
  return res;
}

// --versus's figures for JSON, or null without it: the other setting's knobs and FPS, and the
// per-frame ratio of its time to the run's (median and quartiles).
nlohmann::json versus_json(const Result& r, const io::Quality& run, const VersusSetting* versus) {
  if (!versus || r.versus_ratio.empty()) return nlohmann::json();
  nlohmann::json knobs = nlohmann::json::object();
  for (const auto& [knob, value] : differing_knobs(run, *versus)) knobs[knob] = value;
  const Result::Versus v = r.versus();
  return {{"knobs", knobs},
          {"fps_median", v.fps_median},
          {"time_ratio_median", v.ratio_median},
          {"time_ratio_q25", v.ratio_q25},
          {"time_ratio_q75", v.ratio_q75}};
}

void write_json(const std::string& path, const std::vector<Result>& results, const Options& o,
                const io::Quality& quality, const VersusSetting* versus) {
  nlohmann::json list = nlohmann::json::array();
  for (const Result& r : results) {
    const fur::FurCounts& c = r.counts;
    const std::optional<double> ns = r.ns_per_fragment();
    list.push_back({{"scene", r.table->name},
                    {"mesh", r.table->mesh},
                    {"width", o.width},
                    {"height", o.height},
                    {"threads", r.threads},
                    {"simd", simd_in_use()},
                    {"match_llvmpipe", o.match_llvmpipe},
                    {"framebuffer", o.framebuffer},
                    {"sort", io::knob_value(quality, "sort")},
                    {"filter", io::knob_value(quality, "filter")},
                    {"fins", io::knob_value(quality, "fins")},
                    {"fin_quads", io::knob_value(quality, "fin_quads")},
                    {"shells", *quality.shells},
                    {"fps_median", 1000.0 / render::quantile(r.ms, 0.5)},
                    {"fps_min", 1000.0 / *std::max_element(r.ms.begin(), r.ms.end())},
                    {"fps_max", 1000.0 / *std::min_element(r.ms.begin(), r.ms.end())},
                    {"frames", r.ms.size()},
                    {"fragments_blended_mean", r.mean(r.fragments_blended)},
                    {"lanes_shaded_mean", r.mean(r.lanes_shaded)},
                    {"pixels_shaded_mean", r.mean(r.pixels_shaded)},
                    {"ns_per_fragment", ns ? nlohmann::json(*ns) : nlohmann::json()},
                    {"versus", versus_json(r, quality, versus)},
                    {"vertices", {{"base", c.base_vertices}, {"shell", c.shell_vertices}, {"fin", c.fin_vertices}, {"sum", c.total_vertices}}},
                    {"faces", {{"base", c.base_faces}, {"shell", c.shell_faces}, {"fin", c.fin_faces}, {"sum", c.total_faces}}}});
  }
  io::write_text_atomic(path, list.dump(2) + "\n", "--json");
}

int run_fps(const Options& o) {
  check_default_pixel_budget(o.width, o.height);
  const io::Quality quality = bench_quality(o);
  std::optional<VersusSetting> versus;
  if (o.versus) versus = versus_setting(*o.versus, quality, o.match_llvmpipe);
  std::vector<const PaperTable*> tables;
  for (const std::string& s : o.scenes) {
    const PaperTable* t = nullptr;
    for (const PaperTable& k : kTables)
      if (s == k.name) t = &k;
    if (!t) throw io::InputError("", "--scenes", "unknown scene `" + s + "` (box, teapot, teapot2)");
    // A repeat would print the table twice and put two rows of one setting in --json.
    if (std::find(tables.begin(), tables.end(), t) != tables.end())
      throw io::InputError("", "--scenes", "scene `" + s + "` is listed twice");
    tables.push_back(t);
  }
  for (auto th = o.threads.begin(); th != o.threads.end(); ++th)
    if (std::find(o.threads.begin(), th, *th) != th)
      throw io::InputError("", "--threads", "thread count " + std::to_string(*th) + " is listed twice");
  // Before the probe's temporary: a signal ends the run at once, temporaries removed (render/interrupt.h).
  const render::InterruptGuard interrupt(render::InterruptGuard::Stop::now);
  if (!o.json.empty()) io::prepare_output(o.json, "--json");  // before minutes of frames, not after
  std::vector<Result> results;
  std::printf("pelt bench fps: %dx%d %s, SIMD %s, %d frames after %d warm-up, %s, %d shells, fins %s (%s quads), "
              "sort %s, filter %s\n",
              o.width, o.height, o.rgba8() ? "RGBA8" : "float RGBA", simd_in_use().c_str(), o.frames, o.warmup,
              o.match_llvmpipe ? "the llvmpipe harness's scene (--match-llvmpipe)" : "pelt's own fur", *quality.shells,
              io::knob_value(quality, "fins").c_str(), io::knob_value(quality, "fin_quads").c_str(),
              io::knob_value(quality, "sort").c_str(), io::knob_value(quality, "filter").c_str());
  for (const PaperTable* t : tables) {
    std::vector<Result> rows;
    for (int th : o.threads) rows.push_back(run_one(*t, th, o, quality, versus ? &*versus : nullptr));
    const fur::FurCounts& c = rows.front().counts;
    std::printf("\n%s: %s (ours: %s)\n", t->paper, t->name, t->mesh);
    std::printf("%-8s %8s %8s %8s %8s   | paper: %6s %6s %6s %6s\n", "", "Base", "Shell", "Fin", "Sum", "Base", "Shell", "Fin", "Sum");
    std::printf("%-8s %8zu %8zu %8zu %8zu   | %14d %6d %6d %6d\n", "Vertex", c.base_vertices, c.shell_vertices,
                c.fin_vertices, c.total_vertices, t->vertex[0], t->vertex[1], t->vertex[2], t->vertex[3]);
    std::printf("%-8s %8zu %8zu %8zu %8zu   | %14d %6d %6d %6d\n", "Face", c.base_faces, c.shell_faces, c.fin_faces,
                c.total_faces, t->face[0], t->face[1], t->face[2], t->face[3]);
    for (const Result& r : rows)
      std::printf("%-8s %d thread%s: median %.1f FPS (%.1f-%.1f, %zu frames)   | paper: ~%.0f (GeForce 7600GT)\n", "FPS",
                  r.threads, r.threads == 1 ? " " : "s", 1000.0 / render::quantile(r.ms, 0.5),
                  1000.0 / *std::max_element(r.ms.begin(), r.ms.end()),
                  1000.0 / *std::min_element(r.ms.begin(), r.ms.end()), r.ms.size(), t->fps);
    if (versus)
      for (const Result& r : rows) {
        const Result::Versus v = r.versus();
        std::printf("%-8s %d thread%s: %s takes %.3fx the time (quartiles %.3f-%.3f over %zu frames drawn both ways), "
                    "median %.1f FPS\n",
                    "Versus", r.threads, r.threads == 1 ? " " : "s", versus_label(quality, *versus).c_str(),
                    v.ratio_median, v.ratio_q25, v.ratio_q75, r.versus_ratio.size(), v.fps_median);
      }
    const Result& w = rows.front();
    std::printf("%-8s %.2f M translucent fragments blended a frame in %.2f M shaded lanes, %.2f M opaque pixels "
                "(mean of the timed frames);", "Work", w.mean(w.fragments_blended) / 1e6, w.mean(w.lanes_shaded) / 1e6,
                w.mean(w.pixels_shaded) / 1e6);
    for (const Result& r : rows) {
      if (const std::optional<double> ns = r.ns_per_fragment())
        std::printf(" %.1f ns a fragment on %d thread%s", *ns, r.threads, r.threads == 1 ? "" : "s");
      else
        std::printf(" no fragment on %d thread%s", r.threads, r.threads == 1 ? "" : "s");
      std::printf("%s", &r == &rows.back() ? "\n" : ",");
    }
    if (std::string(t->name) == "teapot2")
      std::printf("note: the paper's Teapot2 vertex row is not self-consistent (882 base but 13152 = 16 x 822 shell);"
                  " the welded 5x5 tessellation has %zu base vertices\n", c.base_vertices);
    std::fflush(stdout);
    results.insert(results.end(), rows.begin(), rows.end());
  }
  if (!o.json.empty()) write_json(o.json, results, o, quality, versus ? &*versus : nullptr);
  return 0;
}

}  // namespace

Run add_bench_fps(CLI::App& bench) {
  auto o = std::make_shared<Options>();
  CLI::App* sub = bench.add_subcommand("fps", "The fur paper's FPS tables (box:7, teapot:3, teapot:5)");
  // Each default said: a bare `pelt bench fps` runs for minutes (3 scenes x 2 thread counts x 220
  // frames at 1024 x 768).
  sub->add_option("--scenes", o->scenes, "Scenes, comma-separated (default: box,teapot,teapot2)")->delimiter(',');
  sub->add_option("--width", o->width, "Image width (default: 1024, the paper's)")->check(CLI::Range(16, 16384));
  sub->add_option("--height", o->height, "Image height (default: 768)")->check(CLI::Range(16, 16384));
  sub->add_option("--threads", o->threads, "Thread counts to measure, comma-separated (default: 1,2)")
      ->delimiter(',')
      ->check(CLI::Range(1, 256));
  sub->add_option("--frames", o->frames, "Timed frames, the median over them (default: 200)")
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--warmup", o->warmup, "Frames rendered before timing (default: 20)")->check(CLI::Range(0, 1000000));
  sub->add_flag("--match-llvmpipe", o->match_llvmpipe, "Draw the llvmpipe harness's exact scene");
  add_knob_option(*sub, "sort", o->sort, "Fur sort (default: tile; none with --match-llvmpipe):");
  add_knob_option(*sub, "filter", o->filter, "Fur texture filter (default: trilinear):");
  add_knob_option(*sub, "fins", o->fins, "Fins (default: silhouette; all with --match-llvmpipe):");
  add_knob_option(*sub, "shells", o->shells, "Shells (default: 16, the paper's; 2 to 128), e.g.");
  add_knob_option(*sub, "fin_quads", o->fin_quads, "Fin quads (default: merged; layer with --match-llvmpipe):");
  sub->add_option("--framebuffer", o->framebuffer,
                  "Frame in memory: rgba8 (default, as the GPU and the llvmpipe harness) | float (pelt render's)")
      ->check(CLI::IsMember({"rgba8", "float"}));
  sub->add_option("--versus", o->versus,
                  "Also draw every frame with these knobs changed, e.g. filter=bilinear_mip,fins=off, and report "
                  "the per-frame time ratio");
  sub->add_option("--json", o->json, "Also write the results as JSON");
  add_simd_option(*sub);
  return [o] { return run_fps(*o); };
}

}  // namespace pelt::cli
