// The start-up's restart with glibc.malloc.hugetlb=1 (tools/cli/huge_page_malloc.h): only on
// a kernel that gives huge pages on request and a glibc that reads the tunable, never twice, and
// keeping the tunables the user set.
#include <gtest/gtest.h>

#include "tools/cli/huge_page_malloc.h"

namespace pelt::cli {
namespace {

constexpr const char* kMadvise = "always [madvise] never";

TEST(HugePageMalloc, SetsTheTunableWhereTheKernelGivesHugePagesOnRequest) {
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "2.36"), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables("", kMadvise, "2.35"), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "3.0"), "glibc.malloc.hugetlb=1");
  // The user's own tunables stay, before it.
  EXPECT_EQ(huge_page_tunables("glibc.malloc.mmap_threshold=4096", kMadvise, "2.36"),
            "glibc.malloc.mmap_threshold=4096:glibc.malloc.hugetlb=1");
}

TEST(HugePageMalloc, LeavesItAloneOtherwise) {
  // Set already: by the user (to 0 as well), or by the restart itself, so it never loops.
  EXPECT_EQ(huge_page_tunables("glibc.malloc.hugetlb=0", kMadvise, "2.36"), std::nullopt);
  EXPECT_EQ(huge_page_tunables("glibc.malloc.hugetlb=1", kMadvise, "2.36"), std::nullopt);
  EXPECT_EQ(huge_page_tunables("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=2", kMadvise, "2.36"), std::nullopt);
  // Huge pages always (the kernel gives them anyway) or never, or no such file.
  EXPECT_EQ(huge_page_tunables(nullptr, "[always] madvise never", "2.36"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, "always madvise [never]", "2.36"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, "", "2.36"), std::nullopt);
  // A glibc before 2.35 has no such tunable; a version it cannot read is treated alike.
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "2.34"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "1.99"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "2"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, "x.y"), std::nullopt);
  EXPECT_EQ(huge_page_tunables(nullptr, kMadvise, ""), std::nullopt);
}

}  // namespace
}  // namespace pelt::cli
