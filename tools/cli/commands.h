// The `pelt` subcommands. Each registers its options on the CLI11 app and returns the
// function that runs it; errors in user input are io::InputError (exit code 2).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace pelt::cli {

using Run = std::function<int()>;

Run add_render_command(CLI::App& app);
Run add_info_command(CLI::App& app);
Run add_bench_command(CLI::App& app);
Run add_tradeoff_command(CLI::App& app);

// Subcommands of `bench`, each added to the `bench` app.
Run add_bench_fps(CLI::App& bench);
Run add_bench_skin(CLI::App& bench);

}  // namespace pelt::cli
