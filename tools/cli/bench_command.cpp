// `pelt bench fps|skin`: the papers' tables, measured on this machine.
#include "tools/cli/commands.h"

namespace pelt::cli {

Run add_bench_command(CLI::App& app) {
  CLI::App* bench = app.add_subcommand("bench", "Measure the papers' tables (FPS, skin render time)");
  bench->require_subcommand(1);
  auto fps = add_bench_fps(*bench);
  CLI::App* fps_app = bench->get_subcommands({}).back();
  auto skin = add_bench_skin(*bench);
  CLI::App* skin_app = bench->get_subcommands({}).back();
  return [=] { return fps_app->parsed() ? fps() : skin_app->parsed() ? skin() : 2; };
}

}  // namespace pelt::cli
