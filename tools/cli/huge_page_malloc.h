// pelt's start-up on a kernel whose transparent huge pages are "madvise" (Debian's and Ubuntu's
// cloud kernels): glibc's malloc then backs its large blocks with 4 KiB pages, and a frame's
// set-up (meshes, maps, mip chains, frame buffers, OpenImageIO's load on another thread) takes
// tens of thousands of page faults, much of a one-frame render's time on a virtual machine.
// glibc 2.35 and later madvise their large blocks into huge pages when the tunable
// glibc.malloc.hugetlb=1 is set, but read tunables only from the environment at process start;
// so pelt sets it and executes itself again, once, before anything else runs.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace pelt::cli {

// The GLIBC_TUNABLES value to restart with, given the present one (nullptr: unset), the
// kernel's /sys/kernel/mm/transparent_hugepage/enabled line and glibc's version; none when the
// tunable is already there (the user's choice, or the restart's), the kernel's mode is not
// "madvise" ("always" gives huge pages anyway, "never" none), or glibc predates 2.35.
std::optional<std::string> huge_page_tunables(const char* present, std::string_view kernel_modes,
                                              std::string_view glibc_version);

// Executes this program again with those tunables, or returns: nothing to do, a sanitized build
// (whose allocator is not glibc's), a setuid binary, a program started by running the dynamic
// loader, or the restart failed (pelt then runs as it is). The restarted process gives
// GLIBC_TUNABLES back its value at once: only its own malloc, set up at its start, keeps it.
void restart_with_huge_page_malloc(char** argv);

}  // namespace pelt::cli
