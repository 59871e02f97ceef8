#include "tools/io/suggest.h"

#include <gtest/gtest.h>

namespace pelt::io {
namespace {

TEST(Suggest, EditDistance) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("shells", "shels"), 1u);
  EXPECT_EQ(edit_distance("Fovy", "fovy"), 0u);
  EXPECT_EQ(edit_distance("ab", "ba"), 1u);
  EXPECT_EQ(edit_distance("abc", "ca"), 3u);
}

TEST(Suggest, NearestName) {
  constexpr std::string_view names[] = {"width", "height", "background"};
  EXPECT_EQ(nearest_name("widht", names), "width");
  EXPECT_EQ(nearest_name("hieght", names), "height");
  EXPECT_EQ(nearest_name("backgroud", names), "background");
  EXPECT_EQ(nearest_name("camera", names), "");
  EXPECT_EQ(did_you_mean("widt", names), " (did you mean `width`?)");
  EXPECT_EQ(did_you_mean("zzz", names), "");
}

}  // namespace
}  // namespace pelt::io
