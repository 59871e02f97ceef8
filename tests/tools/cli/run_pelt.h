// Runs the built `pelt` binary (${PELT_BINARY_DIR}/pelt), or another program, as a child
// process with its stdout and stderr captured, for tests of the command line and its scripts.
#pragma once

#include "tests/tools/io/temp_dir.h"
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace pelt::cli_test {

// ${PELT_BINARY_DIR}/pelt when the test environment sets it, else the path CMake
// compiled in.
inline std::filesystem::path pelt_binary() {
  if (const char* dir = std::getenv("PELT_BINARY_DIR")) return std::filesystem::path(dir) / "pelt";
  return PELT_BINARY_PATH;
}

inline std::filesystem::path source_dir() {
  const char* dir = std::getenv("PELT_SOURCE_DIR");
  return std::filesystem::path(dir ? dir : ".");
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

using pelt::io::TempDir;  // a fresh folder removed with its contents at scope exit

// A started process; output goes to files in `log_dir`.
struct Child {
  pid_t pid = -1;
  std::filesystem::path out, err;
};

// Starts `program` (a path) with `args`.
inline Child start_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                           const std::filesystem::path& log_dir) {
  static std::atomic<int> counter{0};
  const int n = counter++;
  Child c;
  c.out = log_dir / ("stdout_" + std::to_string(n) + ".txt");
  c.err = log_dir / ("stderr_" + std::to_string(n) + ".txt");
  const std::string bin = program.string();
  std::vector<std::string> argv_s{bin};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  c.pid = ::fork();
  if (c.pid == 0) {
    const int o = ::open(c.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(c.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    std::vector<char*> argv;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    ::execv(bin.c_str(), argv.data());
    ::_exit(127);
  }
  return c;
}

struct Result {
  int code = -1;  // exit code, or -signal when killed by a signal
  std::string out, err;
};

inline Child start_pelt(const std::vector<std::string>& args, const std::filesystem::path& log_dir) {
  return start_program(pelt_binary(), args, log_dir);
}

// Waits for a started process (pelt or another program) and reads what it wrote.
inline Result wait_child(const Child& c) {
  int status = 0;
  ::waitpid(c.pid, &status, 0);
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  r.out = read_text(c.out);
  r.err = read_text(c.err);
  return r;
}

inline Result run_pelt(const std::vector<std::string>& args, const std::filesystem::path& log_dir) {
  return wait_child(start_pelt(args, log_dir));
}

inline Result run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                          const std::filesystem::path& log_dir) {
  return wait_child(start_program(program, args, log_dir));
}

}  // namespace pelt::cli_test
