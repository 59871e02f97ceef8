// Output files (images, GIFs, JSON results and statistics, tables) are written to a
// temporary beside the target and renamed over it only once complete, so a failed or
// interrupted write leaves no partial file. A destination that cannot be written is found
// before the work that fills it (prepare_output), not after minutes of rendering.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pelt::io {

// The temporary an atomic writer fills before renaming it over `path`: `.NAME.tmp-PID-TOKEN-N`
// in path's folder (the same file system, so the rename is atomic), TOKEN random per process
// and N counting this process's temporaries, so no two temporaries share a name.
std::filesystem::path temp_beside(const std::filesystem::path& path);
// The `PID-TOKEN-N` part of the next such name (also for temporaries that must keep their
// extension, as the plot's .png).
std::string temp_suffix();

// Makes a file's creation atomic against the signal handler that ends the process: while a
// section lives, remove_temp_files_in_signal_handler waits for it to end, and once the handler
// has begun no section starts (its thread waits for the exit). Without it, a writer thread
// could create a temporary after the handler's unlink loop and before its _exit, and the file
// would stay. SIGINT and SIGTERM are blocked on the section's thread meanwhile, since a handler
// run there would wait for itself; keep a section to a few system calls.
class TempCreation {
 public:
  TempCreation();
  ~TempCreation();
  TempCreation(const TempCreation&) = delete;
  TempCreation& operator=(const TempCreation&) = delete;
  // The thread's signal mask before the section, for a child spawned inside it to start with.
  const sigset_t& previous_mask() const { return previous_; }

 private:
  sigset_t previous_;
};

// Removes its file at scope exit unless released: every early exit leaves no file behind.
// The constructor creates the file (empty), keeps it open, and lists its path for
// remove_temp_files_in_signal_handler, all in one TempCreation, so a process ended by a signal
// (a second Ctrl-C, SIGTERM) leaves none either. Writers open write_path(), never path(): an
// open by name after the handler's unlink would create the file again.
class TempFile {
 public:
  explicit TempFile(std::filesystem::path p);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::filesystem::path& path() const { return path_; }
  // The file to open for writing: /proc/self/fd/N, the descriptor kept since its creation,
  // whose open reaches the same file and never makes a name (not even once unlinked). path()
  // where /proc is not mounted, or the creation failed (the writer's open then reports why).
  const std::string& write_path() const { return write_path_; }
  // A library's message about write_path(), naming path() instead.
  std::string named(std::string message) const;
  // Flushes the file's data to the disk (fsync); 0 or its errno.
  int sync() const;
  // Whether path() still names this file (its folder may have been moved or removed since).
  bool at_its_path() const;
  // 0 when the constructor created the file, else its errno.
  int creation_error() const { return creation_error_; }
  // The file stays (it has been renamed into place) with the mode the umask gave it; its
  // descriptor is closed.
  void release();

 private:
  std::filesystem::path path_;
  std::string write_path_;
  bool released_ = false;
  int slot_ = -1;  // in the signal handler's list; -1 when the list was full or after release
  int fd_ = -1;
  int creation_error_ = 0;
  mode_t mode_ = 0600;  // the mode the umask gave the file (the owner may read and write it until release)
};

// Removes every live TempFile's file, after killing and reaping the child set by
// set_temp_writer_child, which may be writing one, then the empty folders of
// remove_created_folders; first it waits for every TempCreation in flight on other threads,
// and bars new ones; a file whose folder was moved is found by its descriptor. Async-signal-safe
// (kill, waitpid, fstat, lstat, readlink, unlink, rmdir, poll and string functions only, no
// allocation, no locks): for a handler about to end the process, which must not return after it.
void remove_temp_files_in_signal_handler();
// Removes the folders prepare_output made that are still empty, deepest first: for a run that
// ends with an error or a signal before writing into them (remove_temp_files_in_signal_handler
// calls it). Async-signal-safe (rmdir only).
void remove_created_folders();
// A child process writing into a TempFile (the tradeoff's plot script), while it runs; 0: none.
// Spawn the child and set it inside one TempCreation, or a signal in between would miss it.
void set_temp_writer_child(pid_t pid);

// The outputs of a run, checked before any work: none may be one of the run's inputs (the
// scene, a mesh, a map) or another output. A file is compared as the directory entry a write
// replaces, its canonical folder and its name (`textures/../map.png` is `map.png`): writes go
// to a temporary renamed into place, so a link at the output is replaced, never written
// through (but for a link to a device, a pipe or /proc: writes_through). Throws
// InputError(output, option, reason naming the other file).
class OutputNames {
 public:
  // `run` names the command in the message ("an input of this render").
  explicit OutputNames(const std::vector<std::filesystem::path>& inputs, std::string run = "render");
  // An output the later ones are also checked against (`--stats`, a GIF).
  void add(const std::filesystem::path& path, const std::string& option);
  // One frame of a sequence, distinct from the other frames by its number: checked against
  // the inputs and the outputs added before, not kept (a shot may have millions of frames).
  void add_frame(const std::filesystem::path& path, const std::string& option);

 private:
  struct Named {
    std::filesystem::path entry, path;
    std::string option;
  };
  std::filesystem::path entry(const std::filesystem::path& path);
  void check(const std::filesystem::path& entry, const std::filesystem::path& path, const std::string& option) const;
  std::vector<Named> inputs_, kept_;
  std::string run_;
  std::filesystem::path folder_, canonical_folder_;  // the last folder resolved: a sequence's frames share one
};

// Flushes the folder entry of `file` (a name just renamed into place) to the disk, best effort:
// some file systems refuse a folder's fsync (EINVAL), and the file's data are in place by then.
void sync_folder_of(const std::filesystem::path& file);

// True for an output that exists and is written in place rather than replaced by a renamed
// temporary: a device, FIFO or socket (/dev/null, a named pipe), or a file reached through
// /proc (/dev/stdout, /dev/fd/N). A rename would put a regular file in the device's or the
// link's place (as root, /dev/null itself) instead of writing to it.
bool writes_through(const std::filesystem::path& path);

// One output written whole or not at all: into a TempFile beside it, renamed over it by
// commit(); where writes_through, in place, with nothing to rename. Every atomic writer (images,
// GIFs, text) opens write_path() and commits once the data are complete; an output never
// committed leaves no file (its temporary is removed).
class AtomicOutput {
 public:
  explicit AtomicOutput(std::filesystem::path target);
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  // Where the writer opens: the temporary's write_path(), or the target itself in place.
  const std::string& write_path() const { return tmp_ ? tmp_->write_path() : target_string_; }
  bool in_place() const { return !tmp_; }
  // A library's message about write_path(), naming the temporary's path (TempFile::named).
  std::string named(std::string message) const { return tmp_ ? tmp_->named(std::move(message)) : message; }
  // Renames the finished temporary over the target (nothing to do in place): its data flushed
  // to the disk first and the folder's entry after, so a machine that loses power right after
  // a frame is reported done finds that frame whole, not an empty or torn file under its name
  // (which a farm's `--resume` would skip). Throws InputError(target, field, "cannot move
  // `what` into place: reason") or ("cannot write `what` to the disk: reason").
  void commit(const std::string& field, const std::string& what);

 private:
  std::filesystem::path target_;
  std::string target_string_;
  std::optional<TempFile> tmp_;
};

// Creates path's folder (with its parents, as `pelt render -o` does) and proves that a file
// can be made there by creating and removing the temporary an atomic write would use (where
// writes_through, that the output can be written). The target itself is not touched. Throws
// InputError(path, field, reason): e.g. a parent that is a regular file, a read-only folder,
// or a path that names a folder.
void prepare_output(const std::filesystem::path& path, const std::string& field);

// Writes `text` to `path` atomically (through temp_beside), or in place where writes_through.
// Throws InputError(path, field, reason) and leaves neither the target nor the temporary when
// any step fails.
void write_text_atomic(const std::filesystem::path& path, const std::string& text, const std::string& field);

}  // namespace pelt::io
