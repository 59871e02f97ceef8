// What pelt says when CLI11 refuses the command line: CLI11's own messages name no program
// ("A subcommand is required" for `pelt rendr`; "The following arguments were not expected: 160
// --widht"), so a farm log grepped for `pelt: error` missed them. This names the unknown command
// or option, with the nearest known one.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace pelt::cli {

// The message for `e` (without the `pelt: error: ` prefix): an unknown command or option
// named, with a "did you mean"; else CLI11's own message.
std::string explain_parse_error(CLI::App& app, int argc, char** argv, const CLI::ParseError& e);

}  // namespace pelt::cli
