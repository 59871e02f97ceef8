// Text outputs written atomically, and destinations proven writable before the work: the
// file appears whole or not at all, no temporary is left behind, and every failure is an
// InputError naming the file and the option.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"
#include "tools/io/output_file.h"

namespace pelt::io {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Every entry below `dir`, relative and sorted (folders and files).
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// The InputError `fn` throws (a test failure when it throws none).
template <class Fn>
InputError error_of(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", "", "");
}

TEST(OutputFile, WriteTextAtomicWritesTheWholeTextAndNothingElse) {
  TempDir dir;
  const fs::path p = dir.path() / "results.json";
  write_text_atomic(p, "[1, 2]\n", "--json");
  EXPECT_EQ(read(p), "[1, 2]\n");
  write_text_atomic(p, "[3]\n", "--json");  // replaces an earlier file
  EXPECT_EQ(read(p), "[3]\n");
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"results.json"});
}

TEST(OutputFile, AFailedWriteNamesFileAndOptionAndLeavesNothing) {
  TempDir dir;
  const fs::path taken = dir.write("taken", "a file, not a folder");
  const fs::path p = taken / "results.json";
  const InputError e = error_of([&] { write_text_atomic(p, "[]\n", "--json"); });
  EXPECT_EQ(e.file, p.string());
  EXPECT_EQ(e.field, "--json");
  EXPECT_NE(e.reason.find("cannot create a file in " + taken.string()), std::string::npos) << e.what();
  EXPECT_EQ(read(taken), "a file, not a folder");
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"taken"});
}

TEST(OutputFile, PrepareOutputMakesTheFolderAndLeavesNoFile) {
  TempDir dir;
  const fs::path p = dir.path() / "a" / "b" / "stats.json";
  prepare_output(p, "--stats");
  EXPECT_TRUE(fs::is_directory(dir.path() / "a" / "b"));
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"a", "a/b"}));
  write_text_atomic(p, "{}\n", "--stats");
  EXPECT_EQ(read(p), "{}\n");

  // A file already there is not touched: only the run's end replaces it.
  prepare_output(p, "--stats");
  EXPECT_EQ(read(p), "{}\n");
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"a", "a/b", "a/b/stats.json"}));
}

TEST(OutputFile, PrepareOutputRefusesWhatCannotBecomeTheFile) {
  TempDir dir;
  const fs::path taken = dir.write("taken", "a file, not a folder");
  const InputError under_file = error_of([&] { prepare_output(taken / "deeper" / "fps.json", "--json"); });
  EXPECT_EQ(under_file.file, (taken / "deeper" / "fps.json").string());
  EXPECT_EQ(under_file.field, "--json");
  EXPECT_NE(under_file.reason.find("cannot create folder " + (taken / "deeper").string()), std::string::npos)
      << under_file.what();

  fs::create_directories(dir.path() / "folder");
  const InputError folder = error_of([&] { prepare_output(dir.path() / "folder", "--stats"); });
  EXPECT_EQ(folder.field, "--stats");
  EXPECT_EQ(folder.reason, "is a folder, not a file");

  const InputError empty = error_of([&] { prepare_output("", "--json"); });
  EXPECT_EQ(empty.reason, "names no file");
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"folder", "taken"}));
}

TEST(OutputFile, TheTemporaryLiesBesideTheTarget) {
  EXPECT_EQ(temp_beside("out/x.json").parent_path(), fs::path("out"));
  EXPECT_EQ(temp_beside("x.json").parent_path(), fs::path("."));
  EXPECT_EQ(temp_beside("out/x.json").filename().string().rfind(".x.json.tmp-", 0), 0u);
}

// A legal output name of up to 255 bytes keeps a legal temporary: the target's part of the
// temporary's name is cut (a hunt found names of 229-255 bytes refused, "File name too long"), and
// the write lands under the full name.
TEST(OutputFile, ANameOf255BytesIsWritten) {
  TempDir dir;
  for (const size_t length : {size_t(224), size_t(240), size_t(255)}) {
    const std::string name = std::string(length - 5, 'd') + ".json";
    const fs::path temp = temp_beside(dir.path() / name);
    EXPECT_LE(temp.filename().string().size(), 255u) << length;
    EXPECT_EQ(temp.filename().string().rfind(".ddd", 0), 0u);
    write_text_atomic(dir.path() / name, "{}", "--stats");
    EXPECT_TRUE(fs::exists(dir.path() / name)) << length;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 3);  // no temporary left
}

// Every temporary's name is its own: the pid, a random token of the process (pids repeat across pid
// namespaces, where two renders of one folder removed each other's temporaries) and a count.
TEST(OutputFile, NoTwoTemporariesShareAName) {
  const std::string a = temp_beside("x.png").filename().string(), b = temp_beside("x.png").filename().string();
  EXPECT_NE(a, b);
  const std::string pid = ".x.png.tmp-" + std::to_string(::getpid()) + "-";
  EXPECT_EQ(a.rfind(pid, 0), 0u) << a;
  EXPECT_EQ(b.rfind(pid, 0), 0u) << b;
  EXPECT_EQ(a.size(), pid.size() + 16 + 1 + std::to_string(std::stoull(a.substr(a.rfind('-') + 1))).size()) << a;
}

TEST(OutputFile, ATemporaryExistsFromItsConstructionUntilItsDestruction) {
  TempDir dir;
  const fs::path p = dir.path() / ".x.tmp";
  {
    const TempFile tmp(p);
    EXPECT_TRUE(fs::exists(p));
    EXPECT_EQ(fs::file_size(p), 0u);
  }
  EXPECT_FALSE(fs::exists(p));
  TempFile kept(p);
  kept.release();
  EXPECT_TRUE(fs::exists(p));
}

// A folder moved away while its output is written (a user tidying a shot's folder during a
// sequence): the temporary's path names nothing, and both the rename and the removal by that
// path failed, leaving the temporary in the moved folder. It is now removed where it lies, and
// the error says what happened.
TEST(OutputFile, AFolderMovedDuringTheWriteKeepsNoTemporary) {
  TempDir dir;
  fs::create_directory(dir.path() / "shot");
  {
    const TempFile tmp(dir.path() / "shot" / ".x.tmp");
    fs::rename(dir.path() / "shot", dir.path() / "moved");
    EXPECT_TRUE(fs::exists(dir.path() / "moved" / ".x.tmp"));
    EXPECT_FALSE(tmp.at_its_path());
  }
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"moved"});

  fs::create_directory(dir.path() / "shot");
  const fs::path target = dir.path() / "shot" / "frame.json";
  const InputError e = error_of([&] {
    AtomicOutput out(target);
    std::ofstream(out.write_path()) << "{}\n";
    fs::rename(dir.path() / "shot", dir.path() / "again");
    out.commit("-o", "the frame");
  });
  EXPECT_EQ(e.file, target.string());
  EXPECT_NE(e.reason.find("its folder was moved or removed while it was written"), std::string::npos) << e.what();
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"again", "moved"}));
}

// Where the temporary's name was taken by another file after its folder moved, that file stays:
// the file removed is the temporary itself, found by its descriptor.
TEST(OutputFile, OnlyTheTemporaryItselfIsRemovedWhereItLies) {
  TempDir dir;
  fs::create_directory(dir.path() / "shot");
  {
    const TempFile tmp(dir.path() / "shot" / ".x.tmp");
    fs::rename(dir.path() / "shot", dir.path() / "moved");
    fs::create_directory(dir.path() / "shot");
    dir.write("shot/.x.tmp", "someone else's");
  }
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"moved", "shot", "shot/.x.tmp"}));

  // Nor does a link (here a dangling one) that took the name keep the temporary.
  fs::remove_all(dir.path() / "shot");
  fs::remove_all(dir.path() / "moved");
  fs::create_directory(dir.path() / "shot");
  {
    const TempFile tmp(dir.path() / "shot" / ".x.tmp");
    fs::rename(dir.path() / "shot", dir.path() / "moved");
    fs::create_directory(dir.path() / "shot");
    fs::create_symlink(dir.path() / "nowhere", dir.path() / "shot" / ".x.tmp");
  }
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"moved", "shot", "shot/.x.tmp"}));
}

// The handler may unlink a temporary while a writer thread is about to open it: the writer opens
// write_path(), which reaches the same file and never makes its name again (an open by name
// would create the file anew, to stay behind after the handler's exit).
TEST(OutputFile, OpeningTheWritePathNeverMakesTheNameAgain) {
  TempDir dir;
  const fs::path p = dir.path() / ".x.tmp";
  TempFile tmp(p);
  ASSERT_EQ(tmp.creation_error(), 0);
  EXPECT_NE(tmp.write_path(), p.string());
  EXPECT_EQ(tmp.named("cannot open " + tmp.write_path() + "!"), "cannot open " + p.string() + "!");
  std::ofstream(tmp.write_path(), std::ios::binary) << "pixels";
  EXPECT_EQ(read(p), "pixels");
  ASSERT_EQ(::unlink(p.c_str()), 0);  // what the handler does
  std::ofstream after(tmp.write_path(), std::ios::binary);
  after << "more";
  after.close();
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// A umask without the owner's write (0277) made the created temporary read-only, and the writer's
// second open of it failed (for any user but root). The owner may write until release(), which
// gives back the umask's mode. named() leaves another descriptor's path alone.
TEST(OutputFile, ARestrictiveUmaskStillLetsTheWriterOpenTheTemporary) {
  TempDir dir;
  const fs::path p = dir.path() / ".x.tmp";
  const mode_t before = ::umask(0277);
  TempFile tmp(p);
  ::umask(before);
  ASSERT_EQ(tmp.creation_error(), 0);
  EXPECT_EQ(fs::status(p).permissions() & fs::perms::owner_all, fs::perms::owner_read | fs::perms::owner_write);
  std::ofstream(tmp.write_path(), std::ios::binary) << "pixels";
  tmp.release();
  EXPECT_EQ(fs::status(p).permissions() & fs::perms::all, fs::perms::owner_read);
  EXPECT_EQ(read(p), "pixels");
  fs::permissions(p, fs::perms::owner_write, fs::perm_options::add);  // for TempDir's clean-up
  const TempFile other(dir.path() / ".y.tmp");
  EXPECT_EQ(other.named(other.write_path() + "5 and " + other.write_path()),
            other.write_path() + "5 and " + (dir.path() / ".y.tmp").string());
}

TEST(OutputFile, AFailedCreationIsReportedAndWritesGoToTheName) {
  TempDir dir;
  const TempFile tmp(dir.path() / "no-such-folder" / ".x.tmp");
  EXPECT_EQ(tmp.creation_error(), ENOENT);
  EXPECT_EQ(tmp.write_path(), (dir.path() / "no-such-folder" / ".x.tmp").string());
}

// A device, a FIFO or a file reached through /proc is written in place: renaming a temporary over
// it would put a regular file in its place (as root, /dev/null itself became one).
TEST(OutputFile, DevicesPipesAndProcLinksAreWrittenInPlace) {
  TempDir dir;
  EXPECT_FALSE(writes_through(dir.path() / "missing.json"));
  EXPECT_FALSE(writes_through(dir.path()));
  write_text_atomic(dir.path() / "plain.json", "1\n", "--json");
  EXPECT_FALSE(writes_through(dir.path() / "plain.json"));
  EXPECT_TRUE(writes_through("/dev/null"));
  if (fs::is_symlink("/dev/stdout")) {
    EXPECT_TRUE(writes_through("/dev/stdout"));
  }

  const fs::path fifo = dir.path() / "pipe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_TRUE(writes_through(fifo));  // else the write below would wait for a reader forever
  prepare_output(fifo, "--json");
  std::string received;
  std::thread reader([&] { received = read(fifo); });
  write_text_atomic(fifo, "[1, 2]\n", "--json");
  reader.join();
  EXPECT_EQ(received, "[1, 2]\n");
  EXPECT_TRUE(fs::is_fifo(fifo));

  const fs::path link = dir.path() / "null.json";
  fs::create_symlink("/dev/null", link);
  write_text_atomic(link, "gone\n", "--json");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  std::vector<std::string> names;  // no temporary left beside them
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"null.json", "pipe.json", "plain.json"}));
}

// The exit status of a forked child running `body`, which ends by _exit (a test failure when
// it does not end by itself within 10 s: a wait that never ends).
template <class Body>
int in_child(Body&& body) {
  const pid_t child = ::fork();
  if (child == 0) {
    ::alarm(10);
    body();
    ::_exit(99);
  }
  int status = 0;
  if (child < 0 || ::waitpid(child, &status, 0) != child) return -1;
  if (WIFSIGNALED(status)) return 1000 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

// The handler about to end the process (render/interrupt.h's, here called directly) while a
// writer thread is creating a temporary: it waits for the creation, then removes the file. Without
// the wait it would find nothing to remove, and the writer would create its file just after.
TEST(TempFileSignals, TheHandlerWaitsForATemporaryBeingCreated) {
  TempDir dir;
  const fs::path late = dir.path() / ".late.tmp";
  const int status = in_child([&] {
    std::atomic<bool> in_section{false};
    std::thread([&] {
      {
        const TempCreation creating;  // as TempFile's constructor's, held long on purpose
        in_section = true;
        ::usleep(100000);
        new TempFile(late);  // lives until the exit
      }
      for (;;) ::pause();
    }).detach();
    while (!in_section) ::usleep(1000);
    remove_temp_files_in_signal_handler();
    ::usleep(200000);  // time for a writer the handler did not wait for to create its file
    ::_exit(fs::exists(late) ? 1 : 0);
  });
  EXPECT_EQ(status, 0) << "1: the temporary was created after the handler's clean-up";
  EXPECT_FALSE(fs::exists(late));
}

// A temporary already renamed into place is the finished output: a signal between the rename
// and release() (the handler removes what is still listed) must not take it back through the
// descriptor that finds it under its new name.
TEST(OutputFile, ATemporaryRenamedIntoPlaceIsNotRemovedUnderItsNewName) {
  TempDir dir;
  {
    const TempFile tmp(dir.path() / ".frame.png.tmp");
    fs::rename(dir.path() / ".frame.png.tmp", dir.path() / "frame.png");
  }
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"frame.png"});
}

// The handler finds a temporary whose folder was moved where it lies now.
TEST(TempFileSignals, TheHandlerRemovesATemporaryWhoseFolderMoved) {
  TempDir dir;
  fs::create_directory(dir.path() / "shot");
  const int status = in_child([&] {
    new TempFile(dir.path() / "shot" / ".x.tmp");  // lives until the exit
    fs::rename(dir.path() / "shot", dir.path() / "moved");
    remove_temp_files_in_signal_handler();
    ::_exit(fs::exists(dir.path() / "moved" / ".x.tmp") ? 1 : 0);
  });
  EXPECT_EQ(status, 0) << "1: the temporary stayed in the moved folder";
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"moved"});
}

// Once the handler has begun, no temporary is created: the writer waits for the exit.
TEST(TempFileSignals, NoTemporaryIsCreatedOnceTheHandlerHasBegun) {
  TempDir dir;
  const fs::path late = dir.path() / ".late.tmp";
  const int status = in_child([&] {
    remove_temp_files_in_signal_handler();
    std::atomic<bool> started{false};
    std::thread([&] {
      started = true;
      new TempFile(late);
    }).detach();
    while (!started) ::usleep(1000);
    ::usleep(100000);  // time for the constructor to create its file, were it not barred
    ::_exit(fs::exists(late) ? 1 : 0);
  });
  EXPECT_EQ(status, 0);
  EXPECT_FALSE(fs::exists(late));
}

// A signal that arrives on the thread creating a temporary waits for the creation to end (the
// handler would otherwise wait for its own thread), then removes the file and ends the process.
TEST(TempFileSignals, ASignalDuringACreationIsHandledAfterIt) {
  TempDir dir;
  const fs::path p = dir.path() / ".x.tmp";
  const int status = in_child([&] {
    struct sigaction sa {};
    sa.sa_handler = [](int sig) {
      remove_temp_files_in_signal_handler();
      ::_exit(128 + sig);
    };
    ::sigaction(SIGTERM, &sa, nullptr);
    {
      const TempCreation creating;
      ::raise(SIGTERM);
      new TempFile(p);
      if (!fs::exists(p)) ::_exit(2);
    }
    ::_exit(3);  // the handler did not run when the section ended
  });
  EXPECT_EQ(status, 128 + SIGTERM);
  EXPECT_FALSE(fs::exists(p));
}

}  // namespace
}  // namespace pelt::io
