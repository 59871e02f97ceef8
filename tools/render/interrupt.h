// Ctrl-C during a multi-frame render: the first SIGINT asks the render loop to stop after
// the frame in flight (so no frame is lost half-written); a second one ends the process
// at once (the default action, restored by the first).
#pragma once

namespace pelt::render {

class InterruptGuard {
 public:
  // Installs the SIGINT handler and clears any earlier request.
  InterruptGuard();
  // Restores the previous SIGINT handler.
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // True once SIGINT arrived while the guard was installed; polled between frames.
  static bool requested();
};

}  // namespace pelt::render
