#include "tools/tradeoff/plot.h"

#include "tools/io/output_file.h"

#include <cerrno>
#include <cstring>
#include <system_error>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tools/tradeoff/plot_script.h"

extern char** environ;

namespace pelt::tradeoff {

// Exit codes of plot_tradeoff.py.
constexpr int kNoMatplotlib = 3;

std::string default_python() {
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

PlotOutcome make_plot(const std::filesystem::path& csv, const std::filesystem::path& png, const std::string& title,
                      const std::vector<bool>& front, const std::string& python) {
  namespace fs = std::filesystem;
  std::string indices;
  for (size_t i = 0; i < front.size(); ++i) {
    if (!front[i]) continue;
    if (!indices.empty()) indices += ',';
    indices += std::to_string(i);
  }
  // matplotlib picks the format from the name, so the temporary keeps the .png ending.
  std::string tmp_name = ".";
  tmp_name.append(png.stem().string()).append(".tmp-").append(io::temp_suffix()).append(".png");
  // Listed for the signal handler, with the script writing it (io::set_temp_writer_child): a
  // Ctrl-C while it plots kills the script and removes the file.
  io::TempFile tmp_file(png.parent_path() / tmp_name);
  const fs::path& tmp = tmp_file.path();
  std::string script(io::embedded::plot_tradeoff_py());
  std::vector<std::string> args{python, "-c", script, csv.string(), tmp.string(), title, indices};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  PlotOutcome out;
  pid_t pid = -1;
  int spawn_err = 0;
  {
    // Spawned and listed in one section: a signal in between would leave the script running.
    const io::TempCreation spawning;
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setsigmask(&attr, &spawning.previous_mask());  // not the section's blocked signals
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    // posix_spawnp reports an interpreter that cannot be executed as its return value.
    spawn_err = ::posix_spawnp(&pid, python.c_str(), nullptr, &attr, argv.data(), environ);
    posix_spawnattr_destroy(&attr);
    if (spawn_err == 0) io::set_temp_writer_child(pid);
  }
  if (spawn_err != 0) {
    out.problem = "cannot run `" + python + "`: " + std::strerror(spawn_err) +
                  " (install Debian's python3 and python3-matplotlib)";
    return out;
  }
  // Waited for without reaping, and unlisted before it is reaped: a reaped pid may be reused at
  // once, and the signal handler must never kill another process under it.
  siginfo_t info{};
  int waited;
  while ((waited = ::waitid(P_PID, id_t(pid), &info, WEXITED | WNOWAIT)) < 0 && errno == EINTR) {
  }
  io::set_temp_writer_child(0);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (waited < 0) {
    out.problem = std::string("waiting for the plot script failed: ") + std::strerror(errno);
    return out;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    out.problem = code == kNoMatplotlib
                      ? "matplotlib is missing for `" + python + "` (Debian: apt-get install python3-matplotlib)"
                  : code == 127 ? "cannot run `" + python + "` (install Debian's python3 and python3-matplotlib)"
                  : WIFEXITED(status) ? "the plot script failed with exit code " + std::to_string(code)
                                      : "the plot script was killed by signal " + std::to_string(WTERMSIG(status));
    return out;
  }
  std::error_code ec;
  // The temporary exists from the start (io::TempFile creates it): a script that ended well
  // without plotting leaves it empty.
  if (fs::file_size(tmp, ec) == 0 || ec) {
    out.problem = "the plot script wrote no image";
    return out;
  }
  // Flushed before the rename and its folder after, as every output (io::AtomicOutput::commit).
  if (const int error = tmp_file.sync()) {
    out.problem = "cannot write the plot to the disk at " + png.string() + ": " + std::strerror(error);
    return out;
  }
  fs::rename(tmp, png, ec);
  if (ec) {
    out.problem = "cannot move the plot into place at " + png.string() + ": " + ec.message();
    return out;
  }
  tmp_file.release();
  io::sync_folder_of(png);
  out.made = true;
  return out;
}

}  // namespace pelt::tradeoff
