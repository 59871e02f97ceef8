// The resource-budget flags shared by the commands that load scenes: --max-pixels,
// --max-texture-side, --max-shells, --max-faces, --max-memory and --max-blur-pairs, each raising or lowering
// one member of io::Budget (tools/io/budget.h, where the defaults are explained).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "tools/io/budget.h"

namespace pelt::cli {

// Registers the five flags on `sub`; a parsed value is written into `b`, which must
// outlive the parse. A bad value is a CLI::ValidationError naming the flag (pelt exits 2).
void add_budget_options(CLI::App& sub, io::Budget& b);

// Parses a budget value: a whole number >= 1, optionally followed by a binary multiple
// K, M, G or T (x 1024, 1024^2, ...; either case), and for a byte count (`bytes` true) an
// optional `B` or `iB` after it: "512M", "8G", "8GiB", "1500000". The result must not
// exceed `max`. Throws io::InputError("", flag, reason) otherwise.
uint64_t parse_budget_value(std::string_view text, const std::string& flag, uint64_t max, bool bytes);

// The benchmarks take no budget flags: their renders run at the default budgets. A size past the
// default pixel budget is refused naming the size flags that asked for it (the renderer's own
// refusal would name a scene field of the built-in scene and a flag the benchmarks lack).
// Throws io::InputError("", "--width", reason).
void check_default_pixel_budget(int width, int height);

}  // namespace pelt::cli
