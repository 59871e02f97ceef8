// The report writers: the CSV's exact header and row format, the markdown table's columns
// and Pareto flags, the timing summary of one and of two passes, the paired ratios, and a
// reused row's measurement.
#include "tools/tradeoff/report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace pelt::tradeoff {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<Row> sample_rows() {
  Row ref{"reference", "reference", summarize(std::vector<double>{1234.5678}, false), {0, kInf, 0, 0}, "", false, {}, false};
  Row sort{"sort", "none", summarize(std::vector<double>{12.0, 13.5, 12.25, 14.0, 12.5}),
           {0.0123456789, 38.17, 0.25, 0.125}, "", false, {}, false};
  Row fast{"preset", "fast", summarize(std::vector<double>{3.0, 3.5, 2.5, 3.25, 3.125}),
           {0.05, 26.0206, 0.5, 0.75}, "", true, {}, false};
  sort.vs_default = summarize_ratios(std::vector<double>{0.875, 0.9, 0.8125, 0.95, 0.925});
  fast.vs_default = summarize_ratios(std::vector<double>{0.25, 0.5, 0.25, 0.3});
  // The scene's own setting, as the default row: the baseline.
  Row again{"spp", "1", sort.time, sort.error, "default=scene", false, {}, true};
  return {ref, sort, fast, again};
}

TEST(TradeoffReport, PairedRatiosGiveMedianMinMax) {
  const PairedRatio r = summarize_ratios(std::vector<double>{1.25, 0.75, 1.0, 2.0});
  EXPECT_EQ(r.median, 1.125);
  EXPECT_EQ(r.min, 0.75);
  EXPECT_EQ(r.max, 2.0);
  EXPECT_EQ(r.pairs, 4);
  EXPECT_THROW(summarize_ratios(std::vector<double>{}), std::invalid_argument);
}

TEST(TradeoffReport, AReusedRowTakesTheMeasurementAndKeepsItsLabels) {
  const std::vector<Row> rows = sample_rows();
  Row earlier = rows[1];
  earlier.baseline = true;
  Row row{"spp", "1", {}, {}, "sort=none", false, {}, false};
  reuse_measurement(row, earlier);
  EXPECT_EQ(row.knob, "spp");
  EXPECT_EQ(row.setting, "1");
  EXPECT_EQ(row.same_as, "sort=none");
  EXPECT_FALSE(row.preset);
  EXPECT_EQ(row.time.median, earlier.time.median);
  EXPECT_EQ(row.time.runs, earlier.time.runs);
  EXPECT_EQ(row.error.rmse, earlier.error.rmse);
  EXPECT_EQ(row.error.psnr_db, earlier.error.psnr_db);
  EXPECT_EQ(row.vs_default.median, earlier.vs_default.median);
  EXPECT_EQ(row.vs_default.pairs, earlier.vs_default.pairs);
  EXPECT_TRUE(row.baseline);
}

TEST(TradeoffReport, SummarizeGivesMedianMinMax) {
  const Timing odd = summarize(std::vector<double>{5, 1, 4, 2, 3});
  EXPECT_EQ(odd.median, 3);
  EXPECT_EQ(odd.min, 1);
  EXPECT_EQ(odd.max, 5);
  EXPECT_EQ(odd.runs, 5);
  EXPECT_TRUE(odd.warmed_up);
  const Timing even = summarize(std::vector<double>{4, 1, 3, 2}, false);
  EXPECT_EQ(even.median, 2.5);
  EXPECT_FALSE(even.warmed_up);
  EXPECT_THROW(summarize(std::vector<double>{}), std::invalid_argument);
}

TEST(TradeoffReport, TwoPassesGiveTheFasterMedianAndTheRangeOfBoth) {
  // The first pass ran just after a long load (slower); the second is the estimate.
  const Timing t = combine_passes(std::vector<double>{24, 22, 23, 25, 30}, std::vector<double>{19, 20, 21, 18, 19.5});
  EXPECT_EQ(t.median, 19.5);
  EXPECT_EQ(t.min, 18);
  EXPECT_EQ(t.max, 30);
  EXPECT_EQ(t.runs, 10);
  EXPECT_EQ(t.passes, 2);
  EXPECT_TRUE(t.warmed_up);
  // Symmetric: the order of the passes does not matter.
  const Timing u = combine_passes(std::vector<double>{19, 20, 21, 18, 19.5}, std::vector<double>{24, 22, 23, 25, 30});
  EXPECT_EQ(u.median, t.median);
  EXPECT_EQ(u.min, t.min);
  EXPECT_EQ(u.max, t.max);
  EXPECT_THROW(combine_passes(std::vector<double>{1, 2}, std::vector<double>{}), std::invalid_argument);
  EXPECT_THROW(combine_passes(std::vector<double>{1, 2}, std::vector<double>{1, 2, 3}), std::invalid_argument);

  Row row{"filter", "nearest", t, {0.01, 40, 0.1, 0.01}, "", false, {}, false};
  const std::string md = markdown_table(std::vector<Row>{row}, {true});
  EXPECT_NE(md.find("| 19.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 2 x 5 runs (18.0-30.0) |"), std::string::npos) << md;
}

TEST(TradeoffReport, CsvHeaderAndRowsExactly) {
  std::ostringstream out;
  write_csv(out, sample_rows());
  EXPECT_EQ(out.str(),
            "knob,setting,ms_median,rmse,psnr_db,max_abs,share_over_1_255,time_vs_default\n"
            "reference,reference,1234.568,0,inf,0,0,\n"
            "sort,none,12.500,0.0123457,38.17,0.25,0.125,0.9\n"
            "preset,fast,3.125,0.05,26.0206,0.5,0.75,0.275\n"
            "spp,1,12.500,0.0123457,38.17,0.25,0.125,1\n");
}

TEST(TradeoffReport, CsvFieldsAreQuotedOnlyWhenNeeded) {
  EXPECT_EQ(csv_field("normal_blur"), "normal_blur");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
}

TEST(TradeoffReport, NumbersSpellOutInfinityAndNan) {
  EXPECT_EQ(format_number(kInf, 6), "inf");
  EXPECT_EQ(format_number(-kInf, 6), "-inf");
  EXPECT_EQ(format_number(std::nan(""), 6), "nan");
  EXPECT_EQ(format_number(0.000123456789, 4), "0.0001235");
  EXPECT_EQ(format_ms(1234.5678, false), "1234.568");
  EXPECT_EQ(format_ms(1234.5678, true), "1235");
  EXPECT_EQ(format_ms(12.345, true), "12.3");
  EXPECT_EQ(format_ms(1.2345, true), "1.23");
}

TEST(TradeoffReport, MarkdownTableHasTheColumnsSpreadAndParetoFlags) {
  const std::vector<Row> rows = sample_rows();
  const std::string t = markdown_table(rows, {true, false, true, false});
  std::istringstream in(t);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 2 + rows.size());
  EXPECT_EQ(lines[0],
            "| knob | setting | ms_median | vs default, paired | rmse | psnr_db | max_abs | share_over_1_255 | runs "
            "(min-max ms) | pareto |");
  EXPECT_EQ(lines[2], "| reference | reference | 1235 | - | 0 | inf | 0 | 0 | 1 run, no warm-up | yes |");
  EXPECT_EQ(lines[3],
            "| sort | none | 12.5 | 0.9x (0.812-0.95) | 0.01235 | 38.17 | 0.25 | 0.125 | 5 runs (12.0-14.0) | no |");
  EXPECT_EQ(lines[4], "| preset | fast | 3.12 | 0.275x (0.25-0.5) | 0.05 | 26.02 | 0.5 | 0.75 | 5 runs (2.50-3.50) | yes |");
  EXPECT_NE(lines[5].find("| 1x |"), std::string::npos) << lines[5];
  EXPECT_NE(lines[5].find("same settings as default=scene"), std::string::npos) << lines[5];
  // Every line has the same number of cells.
  for (const std::string& l : lines) EXPECT_EQ(std::count(l.begin(), l.end(), '|'), 11) << l;
}

TEST(TradeoffReport, MarkdownTableRefusesMismatchedFlags) {
  EXPECT_THROW(markdown_table(sample_rows(), {true}), std::invalid_argument);
}

}  // namespace
}  // namespace pelt::tradeoff
