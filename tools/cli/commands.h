// The `pelt` subcommands. Each registers its options on the CLI11 app and returns the
// function that runs it; errors in user input are io::InputError (exit code 2).
#pragma once

#include <algorithm>
#include <functional>
#include <thread>

#include <CLI/CLI.hpp>

namespace pelt::cli {

using Run = std::function<int()>;

// The worker threads of a command: `requested` when given (> 0), else every core (at least
// one: hardware_concurrency may not know and say 0).
inline int worker_threads(int requested) {
  return requested > 0 ? requested : std::max(1, int(std::thread::hardware_concurrency()));
}

// --width, --height and --threads as `pelt render` takes them (0: the scene's size, every core),
// for the commands that render or estimate a render.
inline void add_image_options(CLI::App& sub, int& width, int& height, int& threads) {
  sub.add_option("--width", width, "Image width (default: the scene's)")->check(CLI::Range(1, 16384));
  sub.add_option("--height", height, "Image height (default: the scene's)")->check(CLI::Range(1, 16384));
  sub.add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 256));
}

Run add_render_command(CLI::App& app);
Run add_info_command(CLI::App& app);
Run add_bench_command(CLI::App& app);
Run add_tradeoff_command(CLI::App& app);

// Subcommands of `bench`, each added to the `bench` app.
Run add_bench_fps(CLI::App& bench);
Run add_bench_skin(CLI::App& bench);

}  // namespace pelt::cli
