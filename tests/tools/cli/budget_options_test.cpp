// The --max-* flags (tools/cli/budget_options.h): suffixes, limits, and a bad value
// refused as a CLI11 validation error naming the flag (which pelt turns into exit 2).
#include "tools/cli/budget_options.h"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tools/io/input_error.h"

namespace pelt::cli {
namespace {

// Parses `args` as the options of a subcommand holding the budget flags.
io::Budget parse(std::vector<std::string> args) {
  CLI::App app;
  CLI::App* sub = app.add_subcommand("render");
  io::Budget b;
  add_budget_options(*sub, b);
  args.insert(args.begin(), "render");
  std::reverse(args.begin(), args.end());  // CLI11 takes a vector in reverse order
  app.parse(args);
  return b;
}

// The text of the CLI11 error `args` raise.
std::string parse_error(const std::vector<std::string>& args) {
  try {
    parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(BudgetOptions, DefaultsWhenNoFlagIsGiven) {
  const io::Budget b = parse({});
  const io::Budget d;
  EXPECT_EQ(b.max_pixels, d.max_pixels);
  EXPECT_EQ(b.max_texture_side, d.max_texture_side);
  EXPECT_EQ(b.max_shells, d.max_shells);
  EXPECT_EQ(b.max_faces, d.max_faces);
  EXPECT_EQ(b.max_memory_bytes, d.max_memory_bytes);
  EXPECT_EQ(b.max_blur_pairs, d.max_blur_pairs);
}

TEST(BudgetOptions, EveryFlagSetsItsMember) {
  const io::Budget b = parse({"--max-pixels", "1000000", "--max-texture-side", "2048", "--max-shells", "32",
                              "--max-faces", "2M", "--max-memory", "512M", "--max-blur-pairs", "3G"});
  EXPECT_EQ(b.max_pixels, 1000000u);
  EXPECT_EQ(b.max_texture_side, 2048);
  EXPECT_EQ(b.max_shells, 32);
  EXPECT_EQ(b.max_faces, 2u << 20);
  EXPECT_EQ(b.max_memory_bytes, 512u << 20);
  EXPECT_EQ(b.max_blur_pairs, uint64_t{3} << 30);
  EXPECT_EQ(parse({"--max-memory=8G"}).max_memory_bytes, uint64_t{8} << 30);
}

TEST(BudgetOptions, SuffixesArePowersOf1024) {
  const auto bytes = [](const char* t) { return parse_budget_value(t, "--max-memory", UINT64_MAX, true); };
  EXPECT_EQ(bytes("1"), 1u);
  EXPECT_EQ(bytes("3k"), 3u << 10);
  EXPECT_EQ(bytes("3K"), 3u << 10);
  EXPECT_EQ(bytes("5m"), 5u << 20);
  EXPECT_EQ(bytes("8GiB"), uint64_t{8} << 30);
  EXPECT_EQ(bytes("8GB"), uint64_t{8} << 30);
  EXPECT_EQ(bytes("2T"), uint64_t{2} << 40);
  EXPECT_EQ(bytes("4096B"), 4096u);
  EXPECT_EQ(bytes("15000000000"), 15000000000u);
}

TEST(BudgetOptions, BadValuesNameTheFlagAndTheValue) {
  struct Case {
    std::vector<std::string> args;
    std::string flag, part;
  };
  const Case cases[] = {
      {{"--max-memory", "lots"}, "--max-memory", "`lots`"},
      {{"--max-memory", "8X"}, "--max-memory", "`8X`"},
      {{"--max-memory", "-1G"}, "--max-memory", "`-1G`"},
      {{"--max-memory", "1.5G"}, "--max-memory", "`1.5G`"},
      {{"--max-memory", "0"}, "--max-memory", "at least 1"},
      {{"--max-memory", "99999999999999999999"}, "--max-memory", "too large"},
      {{"--max-memory", "16777216T"}, "--max-memory", "too large"},  // 2^64 bytes
      {{"--max-faces", "8GB"}, "--max-faces", "`8GB`"},             // a count takes no B
      {{"--max-pixels", ""}, "--max-pixels", "expected"},
      {{"--max-texture-side", "0"}, "--max-texture-side", "at least 1"},
      // Budgets beyond what the code can honour: the rasterizer's texture side, the fur's shells.
      {{"--max-texture-side", "16385"}, "--max-texture-side", "more than the largest accepted value 16384"},
      {{"--max-shells", "129"}, "--max-shells", "more than the largest accepted value 128"},
  };
  for (const Case& c : cases) {
    const std::string what = parse_error(c.args);
    EXPECT_NE(what.find(c.flag), std::string::npos) << what;
    EXPECT_NE(what.find(c.part), std::string::npos) << what;
  }
}

TEST(BudgetOptions, ParseValueThrowsInputErrorNamingTheFlag) {
  try {
    parse_budget_value("12Q", "--max-faces", UINT64_MAX, false);
    FAIL() << "accepted";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file, "");
    EXPECT_EQ(e.field, "--max-faces");
    EXPECT_NE(e.reason.find("`12Q`"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_budget_value("2147483647", "--max-shells", 2147483647u, false), 2147483647u);
}

}  // namespace
}  // namespace pelt::cli
