// The signal handler's own exits say why the run ended (a farm's log would otherwise end with
// no line): in a child process, which the handler ends with _exit.
#include "tools/render/interrupt.h"

#include <csignal>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

namespace pelt::render {
namespace {

struct Ended {
  int status = 0;
  std::string err;
};

// Runs `body` in a child whose stderr is captured.
template <class Body>
Ended in_child(Body body) {
  int fds[2];
  EXPECT_EQ(::pipe(fds), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], STDERR_FILENO);
    ::close(fds[0]);
    body();
    ::_exit(0);
  }
  ::close(fds[1]);
  Ended e;
  char buf[256];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) e.err.append(buf, size_t(n));
  ::close(fds[0]);
  ::waitpid(pid, &e.status, 0);
  return e;
}

TEST(Interrupt, StoppingAtOnceIsSaid) {
  const Ended term = in_child([] {
    const InterruptGuard guard(InterruptGuard::Stop::now);
    ::raise(SIGTERM);
  });
  ASSERT_TRUE(WIFEXITED(term.status));
  EXPECT_EQ(WEXITSTATUS(term.status), 128 + SIGTERM);
  EXPECT_EQ(term.err, "pelt: interrupted (SIGTERM): stopped at once; nothing more is written\n");

  // After a frame-end stop was asked for, a second signal ends the run at once.
  const Ended twice = in_child([] {
    const InterruptGuard guard(InterruptGuard::Stop::after_frame);
    ::raise(SIGINT);
    if (!InterruptGuard::requested()) ::_exit(3);
    ::raise(SIGINT);
  });
  ASSERT_TRUE(WIFEXITED(twice.status));
  EXPECT_EQ(WEXITSTATUS(twice.status), 128 + SIGINT);
  EXPECT_EQ(twice.err, "pelt: interrupted again: stopped at once; what was in flight is not written\n");
}

}  // namespace
}  // namespace pelt::render
