// `pelt info SCENE.json`: what a scene will compute, without rendering.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "tools/cli/budget_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/simd_option.h"
#include "tools/cli/quality_options.h"
#include "tools/io/scene.h"
#include "tools/render/animation.h"
#include "tools/render/budget_check.h"
#include "tools/render/force_schedule.h"
#include "tools/render/scene_renderer.h"

namespace pelt::cli {
namespace {

const char* material_name(io::MaterialType t) {
  switch (t) {
    case io::MaterialType::unlit: return "unlit";
    case io::MaterialType::lambert: return "lambert";
    case io::MaterialType::blinn: return "blinn";
    case io::MaterialType::skin: return "skin";
  }
  return "?";
}

// In how many of the scene's frames object i's gravity pose and wind pose are made: the
// renderer's own decisions (render::ForceSchedule) over the frames' inputs, so the line
// agrees with the stats of a render.
struct ForceFrames {
  int frames = 0, gravity = 0, wind = 0;
};

ForceFrames count_force_frames(const io::Scene& scene, size_t object) {
  ForceFrames c;
  c.frames = scene.animation ? scene.animation->frames : 1;
  render::ForceSchedule schedule;
  render::FrameInputs in;
  for (int k = 0; k < c.frames; ++k) {
    render::evaluate_frame_inputs(scene, k, in);
    const render::ForceStep step =
        schedule.next(in.fur[object].gravity, in.fur[object].wind, in.time_seconds, !scene.animation);
    c.gravity += step.gravity && step.gravity_bends;
    c.wind += step.wind;
  }
  return c;
}

// "off" without the block, else the frames that compute it ("in 1 of 96 frames").
std::string force_frames(bool present, int computed, int frames) {
  if (!present) return "off";
  return "computed in " + std::to_string(computed) + " of " + std::to_string(frames) + (frames == 1 ? " frame" : " frames");
}

struct InfoOptions {
  std::string path;
  int width = 0, height = 0, threads = 0;  // as `pelt render` takes them
  QualityFlags quality;
  io::Budget budget;
};

int run_info(const InfoOptions& o) {
  const std::string& path = o.path;
  const io::Scene file_scene = io::load_scene(path);
  render::RenderSettings rs;
  // As `pelt render` sets them, so the memory estimate (and its budget check) is the render's:
  // the same image buffers and the same workers' scratch.
  rs.width = o.width;
  rs.height = o.height;
  rs.threads = worker_threads(o.threads);
  rs.quality = resolve_quality(file_scene, o.quality);
  rs.budget = o.budget;
  rs.describe_only = true;
  // A still is one image; an animation's frames as files (a GIF's extra is said below).
  rs.output = file_scene.animation && file_scene.animation->frames > 1 ? render::ImageOutput::sequence
                                                                       : render::ImageOutput::still;
  const std::unique_ptr<render::SceneRenderer> owned = naming_flag_origin(
      file_scene, o.quality, o.width, o.height, [&] { return std::make_unique<render::SceneRenderer>(file_scene, rs); });
  const render::SceneRenderer& r = *owned;
  for (const std::string& w : r.warnings()) std::fprintf(stderr, "pelt: warning: %s\n", w.c_str());
  // Shells, fins and skin models as the quality draws them.
  const io::Scene scene = render::apply_quality(file_scene, r.quality());
  std::printf("scene      %s\n", path.c_str());
  std::printf("image      %d x %d, %d frame(s)%s\n", r.width(), r.height(), r.frame_count(),
              scene.animation ? "" : " (still)");
  std::printf("quality    %s\n", io::describe(r.quality()).c_str());
  std::printf("simd       %s (this CPU runs %s)\n", simd_in_use().c_str(), simd_runnable().c_str());
  std::printf("lights     %zu\n", scene.lights.size());
  std::printf("objects    %zu\n", scene.objects.size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const io::SceneObject& o = scene.objects[i];
    std::printf("  [%zu] %s: mesh %s, material %s", i, o.name.empty() ? "-" : o.name.c_str(), o.mesh.c_str(),
                material_name(o.material.type));
    if (o.material.type == io::MaterialType::skin) {
      const shading::SkinParams& k = o.material.skin;
      std::printf(" (single scattering %s, multiple scattering %s, fresnel %s, phase %s, specular %s)",
                  std::string(shading::to_string(k.single_scattering)).c_str(),
                  std::string(shading::to_string(k.multiple_scattering)).c_str(),
                  std::string(shading::to_string(k.fresnel)).c_str(),
                  std::string(shading::to_string(k.phase)).c_str(),
                  std::string(shading::to_string(k.specular)).c_str());
    }
    std::printf("\n");
    // Which maps are drawn, whose, and where the mesh file places them.
    const auto map_line = [](const char* kind, bool scene_names, const io::MapPlacement& p) {
      return std::string(kind) + (scene_names ? " (the scene's)" : " (the mesh file's: " + io::describe(p) + ")");
    };
    const auto maps_line = [&](const render::SceneRenderer::MapsDrawn& m) {
      std::string alpha;  // the mesh file's material's alpha, as drawn
      char factor[48];
      std::snprintf(factor, sizeof factor, "%g", double(m.alpha_factor));
      const std::string times = m.alpha_factor != 1.0f ? " x " + std::string(factor) : "";
      const std::string of = !m.color             ? "the factor's alpha " + std::string(factor)
                             : m.alpha_map.empty() ? "the colour map's alpha" + times
                             : m.alpha_map_alone   ? "map_d " + m.alpha_map + times
                                                   : "the colour map's alpha with its map_d " + m.alpha_map + times;
      if (m.alpha_mode == io::AlphaMode::mask) {
        char cut[48];
        std::snprintf(cut, sizeof cut, "%g", double(m.alpha_cutoff));
        alpha = "cut out where " + of + " is below " + cut +
                (m.cut_away ? ", which is everywhere: neither the part nor fur over it is drawn" : "");
      } else if (m.alpha_mode == io::AlphaMode::blend) {
        alpha = "blended by " + of;
      }
      if (!m.color && !m.normal) return alpha.empty() ? std::string("none") : alpha;
      return (m.color ? map_line("colour", !o.material.color_map.empty(), m.color_placement) : std::string()) +
             (m.color && m.normal ? ", " : "") +
             (m.normal ? map_line("normal", !o.material.normal_map.empty(), m.normal_placement) : std::string()) +
             (alpha.empty() ? "" : "; " + alpha);
    };
    const std::vector<render::SceneRenderer::MapsDrawn> maps = r.maps_drawn(i);
    if (maps.size() == 1 && (maps[0].color || maps[0].normal || maps[0].alpha_mode != io::AlphaMode::opaque)) {
      std::printf("       maps: %s\n", maps_line(maps[0]).c_str());
    } else if (maps.size() > 1) {
      // The mesh file's materials give its faces several sets of maps.
      std::printf("       maps by material (%zu parts):\n", maps.size());
      for (const render::SceneRenderer::MapsDrawn& m : maps)
        std::printf("         %s, %zu triangle%s: %s\n",
                    m.material == io::kNoMaterial ? m.material.c_str() : ("`" + m.material + "`").c_str(), m.triangles,
                    m.triangles == 1 ? "" : "s", maps_line(m).c_str());
    }
    // The blur's time is its pairs, and one under the budget can still take minutes: info
    // estimates them (RenderSettings::describe_only) and shows what --max-blur-pairs let through;
    // one over it ended the set-up with the refusal, as every budget ends info.
    if (const std::optional<uint64_t> pairs = r.blur_pair_estimate(i)) {
      const float* radius = o.material.skin.normal_blur_radius;
      if (radius[0] == 0.0f && radius[1] == 0.0f && radius[2] == 0.0f)
        std::printf("       normal blur: radius 0, 0, 0, no search: the normals as they are\n");
      else
        std::printf("       normal blur: radius %g, %g, %g reaches about %llu (source, neighbour) vertex pairs, "
                    "%.3g %% of the budget of %llu (%s)\n",
                    double(radius[0]), double(radius[1]), double(radius[2]), static_cast<unsigned long long>(*pairs),
                    100.0 * double(*pairs) / double(rs.budget.max_blur_pairs),
                    static_cast<unsigned long long>(rs.budget.max_blur_pairs), io::kMaxBlurPairsFlag);
    }
    if (const fur::FurGeometry* g = r.fur_geometry(i)) {
      const fur::FurCounts* c = &g->counts;
      const fur::FurParams& f = *o.fur;
      // Faces whose part cuts everything grow no fur (render::FurObject): a mesh cut away whole
      // computes nothing for it, in any frame.
      size_t gone = 0;
      for (const render::SceneRenderer::MapsDrawn& m : maps) gone += m.cut_away ? m.triangles : 0;
      if (gone == c->base_faces) {
        std::printf("       fur: %d shells, fins %s, cut away whole with the surface: nothing computed or drawn\n",
                    f.shells, std::string(fur::to_string(f.fins)).c_str());
      } else {
        const ForceFrames forces = count_force_frames(scene, i);
        std::printf("       fur: %d shells, fins %s, gravity %s, wind %s\n", f.shells,
                    std::string(fur::to_string(f.fins)).c_str(),
                    force_frames(f.gravity.has_value(), forces.gravity, forces.frames).c_str(),
                    force_frames(f.wind.has_value(), forces.wind, forces.frames).c_str());
        if (gone > 0)
          std::printf("       cut away %zu of %zu base faces grow none (their parts cut everywhere)\n", gone,
                      c->base_faces);
      }
      if (!o.fur_length_map.empty())
        std::printf("       length   x the first channel of %s at the mesh's uvs; %zu of %zu base faces grow none\n",
                    o.fur_length_map.filename().string().c_str(), g->bald_faces, c->base_faces);
      if (f.use_color_map)
        std::printf("       colour   root_color to tip_color x each face's colour map at the mesh's uvs (none: x 1)\n");
      std::printf("       vertices base %zu, shell %zu, fin %zu (shared), sum %zu\n", c->base_vertices,
                  c->shell_vertices, c->fin_vertices, c->total_vertices);
      std::printf("       faces    base %zu, shell %zu, fin %zu, sum %zu\n", c->base_faces, c->shell_faces,
                  c->fin_faces, c->total_faces);
      std::printf("       edges    %zu (a fin quad each per pair of layers)", c->edges);
      if (c->joined_vertices > 0)
        std::printf(", %zu vertex copies (texture seams, hard edges, box mapping) joined to the vertex they copy", c->joined_vertices);
      std::printf("\n");
      // Where the strands lie, and how large: a uv-mapped mesh's strand size depends on its UV layout
      // until scaled, which the user tunes with texture_repeat.
      if (g->strand_coordinates == fur::StrandCoordinates::mesh)
        std::printf("       strands  on the mesh's uvs x %.4g (texture_repeat %g)\n", g->strand_uv_scale,
                    double(f.texture_repeat));
      else
        std::printf("       strands  %s, %.4g texture repeats per scene unit (texture_repeat %g)\n",
                    std::string(fur::to_string(g->strand_coordinates)).c_str(), g->strand_uv_scale,
                    double(f.texture_repeat));
    }
  }
  std::printf("triangles  %llu before fur, %llu after\n", static_cast<unsigned long long>(r.base_triangles()),
              static_cast<unsigned long long>(r.base_triangles() + r.fur_triangles()));
  std::printf("memory     about %s at the peak of `pelt render` on %d thread%s (what --max-memory is checked "
              "against)",
              render::describe_bytes(r.budget_estimate()).c_str(), rs.threads, rs.threads == 1 ? "" : "s");
  if (rs.output == render::ImageOutput::sequence) {
    const int spp = r.quality().spp;
    const uint64_t gif = r.budget_estimate() + render::image_bytes(r.width(), r.height(), spp, render::ImageOutput::gif) -
                         render::image_bytes(r.width(), r.height(), spp, render::ImageOutput::sequence);
    std::printf(";\n           %s written as one GIF; one frame alone (--frame) less",
                render::describe_bytes(gif).c_str());
  }
  std::printf("\n");
  return 0;
}

}  // namespace

Run add_info_command(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand("info", "Show what a scene will compute, without rendering");
  sub->add_option("scene", o->path, "Scene file (JSON, version 1)")->required();
  add_image_options(*sub, o->width, o->height, o->threads);
  add_simd_option(*sub);
  add_quality_options(*sub, o->quality);
  add_budget_options(*sub, o->budget);
  return [o] { return run_info(*o); };
}

}  // namespace pelt::cli
