#include "tools/cli/huge_page_malloc.h"

#include <charconv>
#include <cstdlib>
#include <fstream>

#include <gnu/libc-version.h>
#include <unistd.h>

namespace pelt::cli {

std::optional<std::string> huge_page_tunables(const char* present, std::string_view kernel_modes,
                                              std::string_view glibc_version) {
  constexpr std::string_view kTunable = "glibc.malloc.hugetlb";
  const std::string_view now = present ? present : "";
  if (now.find(kTunable) != std::string_view::npos) return std::nullopt;
  if (kernel_modes.find("[madvise]") == std::string_view::npos) return std::nullopt;
  int major = 0, minor = 0;
  const char* end = glibc_version.data() + glibc_version.size();
  const auto [dot, e1] = std::from_chars(glibc_version.data(), end, major);
  if (e1 != std::errc() || dot == end || *dot != '.') return std::nullopt;
  if (std::from_chars(dot + 1, end, minor).ec != std::errc()) return std::nullopt;
  if (major < 2 || (major == 2 && minor < 35)) return std::nullopt;
  std::string with(now);
  if (!with.empty()) with += ':';
  return with.append(kTunable).append("=1");
}

void restart_with_huge_page_malloc(char** argv) {
#if defined(__SANITIZE_ADDRESS__)
  (void)argv;
#else
  const char* present = std::getenv("GLIBC_TUNABLES");
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(f, modes);
  const std::optional<std::string> with = huge_page_tunables(present, modes, gnu_get_libc_version());
  if (!with) return;
  const std::optional<std::string> saved = present ? std::optional<std::string>(present) : std::nullopt;
  if (::setenv("GLIBC_TUNABLES", with->c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // No /proc (a bare chroot), or the binary is gone: run as it is, the environment as it was.
  if (saved) ::setenv("GLIBC_TUNABLES", saved->c_str(), 1);
  else ::unsetenv("GLIBC_TUNABLES");
#endif
}

}  // namespace pelt::cli
