// Preloaded into a `pelt` run by output_durability_test: logs every fsync (the file its
// descriptor names) and rename to the file $PELT_SYNC_LOG, one line each, then does the call.
#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

void log_line(const char* what, const char* a, const char* b) {
  const char* path = std::getenv("PELT_SYNC_LOG");
  if (!path) return;
  char line[8192];
  const int n = std::snprintf(line, sizeof line, "%s %s%s%s\n", what, a, b ? " " : "", b ? b : "");
  if (n <= 0 || size_t(n) >= sizeof line) return;
  const int fd = ::open(path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return;
  [[maybe_unused]] const ssize_t w = ::write(fd, line, size_t(n));  // one write: lines do not interleave
  ::close(fd);
}

template <class Fn>
Fn next(const char* name) {
  return reinterpret_cast<Fn>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" int fsync(int fd) {
  char link[64], target[4096];
  std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = ::readlink(link, target, sizeof target - 1);
  target[n > 0 ? n : 0] = '\0';
  log_line("fsync", target, nullptr);
  static const auto real = next<int (*)(int)>("fsync");
  return real(fd);
}

extern "C" int rename(const char* from, const char* to) {
  log_line("rename", from, to);
  static const auto real = next<int (*)(const char*, const char*)>("rename");
  return real(from, to);
}
