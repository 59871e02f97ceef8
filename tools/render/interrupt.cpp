#include "tools/render/interrupt.h"

#include <atomic>
#include <csignal>
#include <iterator>

#include <unistd.h>

#include "tools/io/output_file.h"

namespace pelt::render {
namespace {

// Lock-free atomics rather than volatile sig_atomic_t: the handler may run on any thread (the
// render's workers start before the guard), and these are written on the main thread.
std::atomic<int> g_signal{0};
std::atomic<bool> g_stop_now{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "read in a signal handler");
constexpr int kSignals[] = {SIGINT, SIGTERM};
struct sigaction g_previous[std::size(kSignals)] {};

void on_signal(int sig) {
  // One exchange, not a load and a store: SIGINT and SIGTERM handled on two threads at once
  // must not both take the first signal's path.
  if (int none = 0; !g_stop_now.load() && g_signal.compare_exchange_strong(none, sig)) return;
  // The user or the scheduler will not wait (a second signal, or a command with nothing to
  // finish). The temporaries go first (and a child writing one, io::set_temp_writer_child), or
  // they would stay behind under a name no later run removes.
  io::remove_temp_files_in_signal_handler();
  // Said, as `pelt render` says its first signal's stop: a log would otherwise end with no line.
  // write(2), not stdio: this is a signal handler.
  const bool again = !g_stop_now.load();
  const char* message = again ? "pelt: interrupted again: stopped at once; what was in flight is not written\n"
                        : sig == SIGINT ? "pelt: interrupted (SIGINT): stopped at once; nothing more is written\n"
                                        : "pelt: interrupted (SIGTERM): stopped at once; nothing more is written\n";
  size_t length = 0;
  while (message[length] != '\0') ++length;
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, message, length);
  ::_exit(128 + sig);
}

}  // namespace

InterruptGuard::InterruptGuard(Stop stop) {
  g_signal.store(0);
  g_stop_now.store(stop == Stop::now);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : kSignals) sigaddset(&sa.sa_mask, sig);  // one handler at a time
  sa.sa_flags = SA_RESTART;
  for (size_t i = 0; i < std::size(kSignals); ++i) {
    sigaction(kSignals[i], nullptr, &g_previous[i]);
    // A signal the process was started ignoring stays ignored, as Unix programs keep it: a shell
    // starts a background job (`pelt render ... &` in a script) with SIGINT ignored, and a hunt
    // found such a job stopped by a SIGINT meant for its shell once pelt's handler was in.
    const bool ignored = !(g_previous[i].sa_flags & SA_SIGINFO) && g_previous[i].sa_handler == SIG_IGN;
    if (!ignored) sigaction(kSignals[i], &sa, nullptr);
  }
}

InterruptGuard::~InterruptGuard() {
  for (size_t i = 0; i < std::size(kSignals); ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
  g_stop_now.store(false);
}

bool InterruptGuard::requested() { return g_signal.load() != 0; }

int InterruptGuard::signal_number() { return g_signal.load(); }

}  // namespace pelt::render
