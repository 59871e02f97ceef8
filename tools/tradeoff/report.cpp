#include "tools/tradeoff/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/render/frame_timing.h"

namespace pelt::tradeoff {

Timing summarize(std::span<const double> ms, bool warmed_up) {
  if (ms.empty()) throw std::invalid_argument("summarize: no timed runs");
  Timing t;
  t.median = render::quantile({ms.begin(), ms.end()}, 0.5);
  t.min = *std::min_element(ms.begin(), ms.end());
  t.max = *std::max_element(ms.begin(), ms.end());
  t.runs = int(ms.size());
  t.warmed_up = warmed_up;
  return t;
}

PairedRatio summarize_ratios(std::span<const double> ratios) {
  if (ratios.empty()) throw std::invalid_argument("summarize_ratios: no pairs");
  const Timing t = summarize(ratios);
  return {t.median, t.min, t.max, t.runs};
}

void reuse_measurement(Row& row, const Row& earlier) {
  row.time = earlier.time;
  row.error = earlier.error;
  row.vs_default = earlier.vs_default;
  row.baseline = earlier.baseline;
}

Timing combine_passes(std::span<const double> first, std::span<const double> second) {
  if (first.size() != second.size())
    throw std::invalid_argument("combine_passes: " + std::to_string(first.size()) + " and " +
                                std::to_string(second.size()) + " runs in the two passes");
  const Timing a = summarize(first), b = summarize(second);
  Timing t;
  t.median = std::min(a.median, b.median);
  t.min = std::min(a.min, b.min);
  t.max = std::max(a.max, b.max);
  t.runs = a.runs + b.runs;
  t.passes = 2;
  return t;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string format_number(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string format_ms(double ms, bool for_people) {
  if (!std::isfinite(ms)) return format_number(ms, 4);
  const int decimals = !for_people ? 3 : ms >= 100 ? 0 : ms >= 10 ? 1 : 2;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, ms);
  return buf;
}

void write_csv(std::ostream& out, std::span<const Row> rows) {
  out << kCsvHeader << "\n";
  for (const Row& r : rows)
    out << csv_field(r.knob) << ',' << csv_field(r.setting) << ',' << format_ms(r.time.median, false) << ','
        << format_number(r.error.rmse, 6) << ',' << format_number(r.error.psnr_db, 6) << ','
        << format_number(r.error.max_abs, 6) << ',' << format_number(r.error.share_over_1_255, 6) << ','
        << (r.baseline ? std::string("1") : r.vs_default.pairs > 0 ? format_number(r.vs_default.median, 4) : std::string())
        << "\n";
}

namespace {

std::string paired(const Row& r) {
  if (r.baseline) return "1x";
  if (r.vs_default.pairs == 0) return "-";
  return format_number(r.vs_default.median, 3) + "x (" + format_number(r.vs_default.min, 3) + "-" +
         format_number(r.vs_default.max, 3) + ")";
}

std::string spread(const Row& r) {
  const int per_pass = r.time.runs / std::max(1, r.time.passes);
  std::string s = (r.time.passes > 1 ? std::to_string(r.time.passes) + " x " : std::string()) +
                  std::to_string(per_pass) + (per_pass == 1 ? " run" : " runs");
  if (!r.time.warmed_up) s += ", no warm-up";
  if (r.time.runs > 1) s += " (" + format_ms(r.time.min, true) + "-" + format_ms(r.time.max, true) + ")";
  if (!r.same_as.empty()) s += "; same settings as " + r.same_as;
  return s;
}

}  // namespace

std::string markdown_table(std::span<const Row> rows, const std::vector<bool>& front) {
  if (front.size() != rows.size())
    throw std::invalid_argument("markdown_table: " + std::to_string(front.size()) + " Pareto flags for " +
                                std::to_string(rows.size()) + " rows");
  std::string t =
      "| knob | setting | ms_median | vs default, paired | rmse | psnr_db | max_abs | share_over_1_255 | runs (min-max "
      "ms) | pareto |\n"
      "|---|---|---:|---|---:|---:|---:|---:|---|---|\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    t += "| " + r.knob + " | " + r.setting + " | " + format_ms(r.time.median, true) + " | " +
         paired(r) + " | " + format_number(r.error.rmse, 4) + " | " + format_number(r.error.psnr_db, 4) + " | " +
         format_number(r.error.max_abs, 4) + " | " + format_number(r.error.share_over_1_255, 4) + " | " +
         spread(r) + " | " + (front[i] ? "yes" : "no") + " |\n";
  }
  return t;
}

}  // namespace pelt::tradeoff
