// pelt: a CPU rasterizer for fur and skin. Exit codes: 0 success, 1 internal error,
// 2 bad input (scene, mesh, parameter, option), with a message naming the file, the
// field and the reason.
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "tools/cli/commands.h"
#include "tools/cli/huge_page_malloc.h"
#include "tools/cli/parse_errors.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"

namespace {

// An option given an empty value (`--frame ""`, `--shard "$UNSET"`) is refused: taken as "not
// given", it would render every frame, or every shard's frames, with no word said.
void refuse_empty_values(CLI::App& app) {
  for (CLI::Option* opt : app.get_options())
    if (opt->get_type_size() != 0)
      opt->check(CLI::Validator(
          [](std::string& value) { return value.empty() ? std::string("needs a value, got an empty one") : std::string(); },
          "", "non-empty"));
  for (CLI::App* sub : app.get_subcommands({})) refuse_empty_values(*sub);
}

// CLI11 drops the empty items of a delimited list (`--scenes box,,teapot` read as box, teapot;
// `--threads 1,` as 1): refused instead, as an empty value is, since the list is usually
// built by a script whose variable came out empty. Returns the message, or "" when none.
std::string empty_list_item(CLI::App& app, int argc, char** argv) {
  std::map<std::string, char> delimited;  // "--scenes" -> ','
  const std::function<void(CLI::App&)> gather = [&](CLI::App& a) {
    for (CLI::Option* opt : a.get_options())
      if (const char d = opt->get_delimiter(); d != '\0')
        for (const std::string& name : opt->get_lnames()) delimited["--" + name] = d;
    for (CLI::App* sub : a.get_subcommands({})) gather(*sub);
  };
  gather(app);
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i], value;
    const size_t eq = arg.find('=');
    if (eq != std::string::npos && arg.rfind("--", 0) == 0) {
      value = arg.substr(eq + 1);
      arg.resize(eq);
    } else if (i + 1 < argc) {
      value = argv[i + 1];
    }
    const auto it = delimited.find(arg);
    if (it == delimited.end() || value.empty()) continue;
    const char d = it->second;
    if (value.front() == d || value.back() == d || value.find(std::string(2, d)) != std::string::npos)
      return arg + ": `" + value + "` has an empty item";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  pelt::cli::restart_with_huge_page_malloc(argv);
  CLI::App app{"pelt: tiled SIMD rasterizer for fur and skin"};
  app.set_version_flag("--version", std::string("pelt ") + PELT_VERSION, "Print pelt's version and exit");
  app.require_subcommand(1);
  std::map<CLI::App*, pelt::cli::Run> runs;
  for (auto add : {pelt::cli::add_render_command, pelt::cli::add_info_command,
                   pelt::cli::add_bench_command, pelt::cli::add_tradeoff_command}) {
    pelt::cli::Run run = add(app);
    runs[app.get_subcommands({}).back()] = std::move(run);
  }
  refuse_empty_values(app);
  if (const std::string empty = empty_list_item(app, argc, argv); !empty.empty()) {
    std::fprintf(stderr, "pelt: error: %s\n", empty.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "pelt: error: %s\n", pelt::cli::explain_parse_error(app, argc, argv, e).c_str());
    return 2;
  }
  int code = 1;
  try {
    for (auto& [sub, run] : runs)
      if (sub->parsed()) code = run();
  } catch (const pelt::io::InputError& e) {
    std::fprintf(stderr, "pelt: error: %s\n", e.what());
    code = 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pelt: internal error: %s\n", e.what());
    code = 1;
  }
  // A run that fails takes back the output folders it made and left empty.
  if (code != 0) pelt::io::remove_created_folders();
  return code;
}
