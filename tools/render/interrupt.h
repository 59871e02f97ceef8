// Ctrl-C (SIGINT) or SIGTERM (a farm's scheduler pre-empting a job). Every command that writes
// files installs a guard before its first temporary (a writability probe, an output being
// written), so that no signal finds a temporary without a handler to remove it.
// - Stop::after_frame (`pelt render`): the first signal asks the render loop to stop after the
//   frame in flight (so no frame is lost half-written); a second one ends the process at once.
// - Stop::now (benchmarks, tradeoff sweeps, which have no frame worth finishing): the first
//   signal ends the process at once.
// Ending at once: the temporaries of writes in flight are removed, a child process writing one
// killed first (io::remove_temp_files_in_signal_handler), and the process exits with 128 + the
// signal.
#pragma once

namespace pelt::render {

class InterruptGuard {
 public:
  enum class Stop { after_frame, now };
  // Installs the SIGINT and SIGTERM handler and clears any earlier request.
  explicit InterruptGuard(Stop stop = Stop::after_frame);
  // Restores the previous handlers.
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // True once SIGINT or SIGTERM arrived while the guard was installed; polled between frames.
  static bool requested();
  // The signal that asked (SIGINT or SIGTERM), 0 before any: the exit status is 128 + it.
  static int signal_number();
};

}  // namespace pelt::render
