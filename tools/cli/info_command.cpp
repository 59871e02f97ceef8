// `pelt info SCENE.json`: what a scene will compute, without rendering.
#include <cstdio>

#include "tools/cli/commands.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::cli {
namespace {

int run_info(const std::string& path) {
  const io::Scene scene = io::load_scene(path);
  render::RenderSettings rs;
  render::SceneRenderer r(scene, rs);
  std::printf("scene      %s\n", path.c_str());
  std::printf("image      %d x %d, %d frame(s)\n", r.width(), r.height(), r.frame_count());
  std::printf("objects    %zu\n", scene.objects.size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const io::SceneObject& o = scene.objects[i];
    std::printf("  [%zu] %-16s mesh %s%s\n", i, o.name.c_str(), o.mesh.c_str(),
                o.fur ? ", fur" : "");
  }
  std::printf("triangles  %llu base, %llu fur\n", static_cast<unsigned long long>(r.base_triangles()),
              static_cast<unsigned long long>(r.fur_triangles()));
  std::printf("lights     %zu\n", scene.lights.size());
  return 0;
}

}  // namespace

Run add_info_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("info", "Show what a scene will compute, without rendering");
  sub->add_option("scene", *path, "Scene file (JSON, version 1)")->required();
  return [path] { return run_info(*path); };
}

}  // namespace pelt::cli
