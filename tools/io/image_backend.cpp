#include "tools/io/image_backend.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/io/input_error.h"

#ifndef PELT_IMAGE_MODULE_BUILT
#error "PELT_IMAGE_MODULE_BUILT must name the module this build makes (set by the CMake target)"
#endif

namespace pelt::io {
namespace {

constexpr const char* kModuleName = "libpelt_oiio.so";

struct State {
  std::mutex mutex;
  bool tried = false;
  const ImageBackend* backend = nullptr;
  std::string error;
  // Last member: destroyed first, so an exit during a preload waits for it before the
  // rest of the state goes.
  std::future<void> preload;
};

State& state() {
  static State s;
  return s;
}

std::vector<std::string> candidates() {
  if (const char* env = std::getenv("PELT_IMAGE_MODULE"); env && *env) return {env};
  std::vector<std::string> paths;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / kModuleName).string());
  const std::string built = PELT_IMAGE_MODULE_BUILT;
  if (paths.empty() || paths.front() != built) paths.push_back(built);
  return paths;
}

void load(State& s) {
  const std::lock_guard lock(s.mutex);
  if (s.tried) return;
  s.tried = true;
  std::string why;
  for (const std::string& path : candidates()) {
    // Lazy binding: symbols are resolved on first call, not all at once here. The handle
    // is never closed: the backend lives until the process ends.
    void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
      const char* e = ::dlerror();  // names the file
      why += "\n  " + (e ? std::string(e) : path + ": cannot be loaded");
      continue;
    }
    auto entry = reinterpret_cast<ImageBackendEntry>(::dlsym(handle, kImageBackendSymbol));
    ImageBackend* b = entry ? entry(kImageBackendAbi) : nullptr;
    if (!b) {
      why += "\n  " + path + ": " +
             (entry ? "built for another version of pelt" : std::string("no ") + kImageBackendSymbol + " in it");
      ::dlclose(handle);
      continue;
    }
    s.backend = b;
    return;
  }
  s.error = "cannot load pelt's OpenImageIO module (" + std::string(kModuleName) +
            ", built with pelt; PELT_IMAGE_MODULE names another):" + why;
}

}  // namespace

const ImageBackend& image_backend() {
  State& s = state();
  load(s);
  if (!s.backend) throw std::runtime_error(s.error);
  return *s.backend;
}

const ImageBackend& image_backend_for(const std::string& file) {
  try {
    return image_backend();
  } catch (const std::runtime_error& e) {
    throw InputError(file, "", e.what());
  }
}

void preload_image_backend() {
  State& s = state();
  // The thread's load() waits for this lock, so it starts once the future is stored.
  const std::lock_guard lock(s.mutex);
  if (s.tried || s.preload.valid()) return;
  s.preload = std::async(std::launch::async, [&s] { load(s); });
}

void wait_for_image_backend_preload() {
  State& s = state();
  std::unique_lock lock(s.mutex);
  if (!s.preload.valid()) return;
  lock.unlock();  // the loading thread takes the lock
  s.preload.wait();
}

bool image_backend_loaded() {
  State& s = state();
  const std::lock_guard lock(s.mutex);
  return s.backend != nullptr;
}

}  // namespace pelt::io

#if defined(__SANITIZE_ADDRESS__)
// LeakSanitizer, in the sanitizer build only. preload_image_backend loads the module on a
// thread of its own, and two of OpenImageIO's dependencies keep per-thread data that they
// never free when that thread ends: DCMTK's logger (liboflog, log4cplus buffers, 2.5 KB) and
// SRT (libsrt-gnutls, 120 bytes). Once per process, in libraries pelt does not build; on the
// main thread the same blocks stay reachable and are not reported. Only allocations made in
// those two libraries are ignored.
extern "C" __attribute__((visibility("default"), used)) const char* __lsan_default_suppressions() {
  return "leak:liboflog.so\nleak:libsrt-gnutls.so\n";
}

// AddressSanitizer, in the sanitizer build only: do not track dynamic TLS by intercepting
// __tls_get_addr. The module brings 33 libraries with thread-local storage, loaded by
// dlopen, so their blocks are dynamic TLS; GCC 12's runtime guesses a block's bounds from a
// glibc 2.19 header when its address is 16 past a page boundary, and on glibc 2.36 that
// guess reads garbage: the leak checker's scan at exit then crashed ("Tracer caught signal
// 11", DTLS range 0x29c3-0x800003ac5) in about one process in ten. The blocks stay
// covered: glibc allocates them with malloc and holds them in the thread's DTV, itself a
// malloc'd block reached from static TLS, so the checker still scans what they point to.
extern "C" __attribute__((visibility("default"), used)) const char* __asan_default_options() {
  return "intercept_tls_get_addr=0";
}
#endif
