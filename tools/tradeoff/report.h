// The tradeoff report: one row per measured setting, written as CSV (for the plot and for
// other tools) and as a markdown table (for people and the README).
#pragma once

#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "tools/tradeoff/image_compare.h"

namespace pelt::tradeoff {

// Frame times of one setting, in milliseconds.
struct Timing {
  double median = 0, min = 0, max = 0;
  int runs = 0;           // timed frames in all passes together, the same number in each
  int passes = 1;         // 2: measured on the way through the sweep and again on the way back
  bool warmed_up = true;  // false for the reference: its single run is the first frame
};
// Median (mean of the middle two for an even count), min and max. Throws
// std::invalid_argument for no runs.
Timing summarize(std::span<const double> ms, bool warmed_up = true);

// One setting measured in two passes, each after its own warm-up frame: the lower of the two
// passes' medians, and min and max over both. The machine's state drifts during a sweep (a
// shared host lowers the clock after sustained load and gives it back later), and the drift
// only ever adds time, so the faster pass is the better estimate of what the setting costs.
// Throws std::invalid_argument if a pass has no runs or the two have different counts.
Timing combine_passes(std::span<const double> first, std::span<const double> second);

// A setting's frame time over the default's, frame by frame: each of its timed frames on the way
// back is drawn right beside one of the default's (taking turns at going first), so both share
// the machine's phase. pairs == 0: not measured (the reference, and the default itself).
struct PairedRatio {
  double median = 0, min = 0, max = 0;
  int pairs = 0;
};
// Median (mean of the middle two for an even count), min and max of per-pair ratios. Throws
// std::invalid_argument for no pairs.
PairedRatio summarize_ratios(std::span<const double> ratios);

struct Row {
  std::string knob, setting;
  Timing time;
  ImageError error;
  std::string same_as;  // "knob=setting" of the row whose measurement this one reuses, or ""
  bool preset = false;  // a named preset (highlighted in the plot)
  PairedRatio vs_default;
  bool baseline = false;  // the default row: the denominator of every vs_default (1 by definition)
};

// A row with the same settings as `earlier` takes its measurement: time, error, paired ratio
// and whether it is the baseline. Its own labels (knob, setting, same_as, preset) stay.
void reuse_measurement(Row& row, const Row& earlier);

// The CSV's first line, exactly.
inline constexpr const char* kCsvHeader =
    "knob,setting,ms_median,rmse,psnr_db,max_abs,share_over_1_255,time_vs_default";

// One field as CSV: quoted (with doubled quotes) only when it holds a comma, quote or line
// break.
std::string csv_field(const std::string& s);
// A number for the report: `inf` / `-inf` / `nan` spelled out, otherwise %.*g with
// `digits` significant digits (C locale).
std::string format_number(double v, int digits);

// Milliseconds in fixed notation: 3 decimals for the CSV (`for_people` false), else to about 3
// significant digits for people (1234, 123, 12.3, 1.23).
std::string format_ms(double ms, bool for_people);

// Header line and one line per row, "\n"-terminated. ms with 3 decimals, errors with 6
// significant digits (enough to tell rows apart, few enough to read), time_vs_default (the
// paired ratio's median) with 4, 1 for the baseline, empty where it was not measured.
void write_csv(std::ostream& out, std::span<const Row> rows);

// A markdown table: the CSV's columns (time_vs_default as `vs default, paired`: "0.69x
// (0.68-0.70)", "1x" for the baseline, "-" where not measured), then `runs (min-max ms)`
// and `pareto` (yes/no from `front`, which has one entry per row). Throws std::invalid_argument on a size mismatch.
std::string markdown_table(std::span<const Row> rows, const std::vector<bool>& front);

}  // namespace pelt::tradeoff
