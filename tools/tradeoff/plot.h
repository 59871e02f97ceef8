// The tradeoff plot: the embedded matplotlib script (tools/tradeoff/plot_tradeoff.py) run
// with python3 on a written CSV.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pelt::tradeoff {

// The Python interpreter to use: /usr/bin/python3 when it exists (Debian's, which has
// python3-matplotlib; the first python3 on PATH may be another one without it), else
// "python3", looked up on PATH when run.
std::string default_python();

struct PlotOutcome {
  bool made = false;
  std::string problem;  // when not made: what went wrong and how to fix it
};

// Runs the embedded script with `python` (a path, or a name looked up on PATH) to draw
// `csv` (written by write_csv) into `png`, marking the rows whose `front` flag is set.
// The PNG is written to a temporary beside `png` and renamed over it only when the script
// succeeded, so a failure leaves no partial file. Never throws for a missing interpreter
// or module: the outcome says what was missing.
PlotOutcome make_plot(const std::filesystem::path& csv, const std::filesystem::path& png, const std::string& title,
                      const std::vector<bool>& front, const std::string& python = default_python());

}  // namespace pelt::tradeoff
