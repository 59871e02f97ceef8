#include "tools/cli/parse_errors.h"

#include <string_view>
#include <vector>

#include "tools/io/suggest.h"

namespace pelt::cli {
namespace {

// "render, info, bench, tradeoff": the subcommands of `app`.
std::string command_list(CLI::App& app) {
  std::string list;
  for (CLI::App* s : app.get_subcommands({})) list += (list.empty() ? "" : ", ") + s->get_name();
  return list;
}

}  // namespace

std::string explain_parse_error(CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
  // Only words CLI11 could not place are pelt's to name; any other refusal (a value out of
  // range, two options that exclude each other) is CLI11's own message.
  const bool extras = dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr;
  const bool required = dynamic_cast<const CLI::RequiredError*>(&e) != nullptr;
  if (!extras && !required) return e.what();
  // The command the words name, as far as they name one.
  CLI::App* level = &app;
  std::string path = "pelt";
  int i = 1;
  for (; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') break;
    const std::vector<CLI::App*> subs = level->get_subcommands({});
    if (subs.empty()) break;
    CLI::App* next = nullptr;
    for (CLI::App* s : subs)
      if (s->get_name() == word) next = s;
    if (!next) {
      if (level->get_require_subcommand_min() == 0) break;
      std::vector<std::string> names;
      for (CLI::App* s : subs) names.push_back(s->get_name());
      const std::vector<std::string_view> candidates(names.begin(), names.end());
      return "unknown command `" + word + "` for `" + path + "`" + io::did_you_mean(word, candidates) +
             "; the commands are " + command_list(*level);
    }
    level = next;
    path += " " + word;
  }
  if (required && std::string_view(e.what()).find("ubcommand") != std::string_view::npos) {
    return "`" + path + "` needs a command: " + command_list(*level) + " (`" + path + " --help` says what each does)";
  }
  // An option the command does not have.
  std::vector<std::string> options;
  for (const CLI::Option* o : level->get_options())
    for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
  const std::vector<std::string_view> candidates(options.begin(), options.end());
  for (; extras && i < argc; ++i) {
    std::string word = argv[i];
    if (word == "--") break;  // what follows is positional
    if (word.rfind("--", 0) != 0) continue;
    word.resize(std::min(word.size(), word.find('=')));
    bool known = false;
    for (const std::string& o : options) known |= o == word;
    if (!known)
      return "unknown option `" + word + "` for `" + path + "`" + io::did_you_mean(word, candidates) + " (`" + path +
             " --help` lists them)";
  }
  return e.what();
}

}  // namespace pelt::cli
