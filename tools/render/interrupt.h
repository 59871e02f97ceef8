// Ctrl-C (SIGINT) or SIGTERM (a farm's scheduler pre-empting a job) during a render: the first
// asks the render loop to stop after the frame in flight (so no frame is lost half-written); a
// second one ends the process at once, after removing the temporaries of writes in flight
// (io::remove_temp_files_in_signal_handler), with the exit status of that signal.
#pragma once

namespace pelt::render {

class InterruptGuard {
 public:
  // Installs the SIGINT and SIGTERM handler and clears any earlier request.
  InterruptGuard();
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
