#include "tools/cli/huge_page_malloc.h"

#include <charconv>
#include <climits>
#include <cstdlib>
#include <fstream>

#include <gnu/libc-version.h>
#include <sys/auxv.h>
#include <unistd.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PELT_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define PELT_ASAN 1
#endif

namespace pelt::cli {
namespace {

// Set for the restarted process only: GLIBC_TUNABLES as it was before ("" when unset), given
// back at once, so the programs pelt starts (the plot's Python) see the user's environment, and
// so the restart happens once even where glibc drops the tunable (a setuid binary).
constexpr const char* kRestartedFrom = "PELT_GLIBC_TUNABLES_BEFORE_RESTART";

}  // namespace

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
#if defined(PELT_ASAN)
  (void)argv;
  (void)kRestartedFrom;
#else
  if (const char* before = std::getenv(kRestartedFrom)) {  // this is the restarted process
    if (*before) ::setenv("GLIBC_TUNABLES", before, 1);
    else ::unsetenv("GLIBC_TUNABLES");
    ::unsetenv(kRestartedFrom);
    return;
  }
  // Not for a setuid binary (glibc ignores the tunable there), nor when the dynamic loader was
  // run as the program (`ld.so ./pelt`: /proc/self/exe is the loader).
  if (::getauxval(AT_SECURE) != 0 || ::getauxval(AT_BASE) == 0) return;
  const char* present = std::getenv("GLIBC_TUNABLES");
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(f, modes);
  const std::optional<std::string> with = huge_page_tunables(present, modes, gnu_get_libc_version());
  if (!with) return;
  // The binary's own path, so the process keeps its name (`pelt`, not `exe`, for ps and pgrep);
  // a binary replaced since it started ("... (deleted)") fails the exec, and pelt runs as it is.
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return;
  self[n] = '\0';
  const std::string saved = present ? present : "";
  if (::setenv(kRestartedFrom, saved.c_str(), 1) != 0) return;
  if (::setenv("GLIBC_TUNABLES", with->c_str(), 1) == 0) ::execv(self, argv);
  if (present) ::setenv("GLIBC_TUNABLES", saved.c_str(), 1);
  else ::unsetenv("GLIBC_TUNABLES");
  ::unsetenv(kRestartedFrom);
#endif
}

}  // namespace pelt::cli
