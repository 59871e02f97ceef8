#include "tools/io/output_file.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <utility>

#include <csignal>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <unistd.h>

#include "tools/io/input_error.h"

namespace pelt::io {
namespace {

std::filesystem::path folder_of(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

// The live temporaries, for a signal handler: fixed storage, since a handler may not allocate.
// A render has at most a few at once (a frame being written, a GIF, the stats); a temporary
// that finds no free slot is still removed by its destructor on every ordinary exit.
constexpr int kTempSlots = 16;
constexpr size_t kTempPathBytes = 4096;
struct TempSlot {
  std::atomic<bool> claimed{false};  // owned by a TempFile
  std::atomic<bool> live{false};     // `path` is complete and may be unlinked
  std::atomic<int> fd{-1};           // the file's descriptor, once open: finds it if its folder moved
  char path[kTempPathBytes];
};
std::array<TempSlot, kTempSlots> g_temp_slots;
std::atomic<pid_t> g_temp_writer_child{0};
static_assert(std::atomic<pid_t>::is_always_lock_free, "read in a signal handler");

// The folders prepare_output made, shallowest first, for a run that ends before writing into
// them: remove_created_folders takes back those still empty (rmdir removes nothing else).
// Fixed storage as above; a folder past the slots is left, as before.
constexpr int kFolderSlots = 16;
struct FolderSlot {
  std::atomic<bool> live{false};  // `path` is complete
  char path[kTempPathBytes];
};
std::array<FolderSlot, kFolderSlots> g_folder_slots;
std::atomic<int> g_folder_count{0};

// TempCreation's gate. Sequentially consistent on both sides (a section counts itself in, then
// reads g_ending; the handler sets g_ending, then reads the count): either the section sees the
// handler has begun and creates nothing, or the handler sees the section and waits for it.
std::atomic<int> g_creating{0};
std::atomic<bool> g_ending{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "read in a signal handler");

sigset_t ending_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

int claim_temp_slot(const std::filesystem::path& p) {
  const std::string& s = p.native();
  if (s.size() >= kTempPathBytes) return -1;
  for (int i = 0; i < kTempSlots; ++i) {
    TempSlot& slot = g_temp_slots[size_t(i)];
    if (slot.claimed.exchange(true, std::memory_order_acquire)) continue;
    std::memcpy(slot.path, s.c_str(), s.size() + 1);
    slot.live.store(true, std::memory_order_release);
    return i;
  }
  return -1;
}

void free_temp_slot(int i) {
  if (i < 0) return;
  TempSlot& slot = g_temp_slots[size_t(i)];
  slot.live.store(false, std::memory_order_release);
  slot.fd.store(-1, std::memory_order_release);
  slot.claimed.store(false, std::memory_order_release);
}

// Whether `path` itself (not a link's target) is the file `st` describes. Async-signal-safe.
bool names_file(const char* path, const struct stat& st) {
  struct stat named {};
  return ::lstat(path, &named) == 0 && named.st_dev == st.st_dev && named.st_ino == st.st_ino;
}

// Removes the temporary `path`, open as `fd`. Its folder moved away (or renamed) while it was
// written, its path names nothing (or another file), and removing by path left it in the moved
// folder; the kernel still knows where it lies (/proc/self/fd). A file found that way is unlinked
// only if it is this one (device and inode) and still bears the temporary's own name: once
// renamed into place it is the finished output, which a signal right after the rename must not
// take back. That check (the inode and the name together) is what keeps a stale descriptor
// harmless: the handler on another thread may read a slot's descriptor just before release()
// closes it and the number is reused. Async-signal-safe (fstat, lstat, readlink, unlink and
// string functions; no allocation): the handler's.
void remove_temp(const char* path, int fd) {
  struct stat open_file {};
  if (fd < 0 || ::fstat(fd, &open_file) != 0 || names_file(path, open_file)) {
    ::unlink(path);
    return;
  }
  char link[32] = "/proc/self/fd/";
  char digits[12];
  int n = 0;
  for (unsigned v = unsigned(fd); n == 0 || v; v /= 10) digits[n++] = char('0' + v % 10);
  size_t at = std::strlen(link);
  while (n) link[at++] = digits[--n];
  link[at] = 0;
  char where[kTempPathBytes];
  const ssize_t len = ::readlink(link, where, sizeof where - 1);
  if (len <= 0) return;
  where[len] = 0;
  const char* own_name = std::strrchr(path, '/');
  const char* found_name = std::strrchr(where, '/');
  own_name = own_name ? own_name + 1 : path;
  if (!found_name || std::strcmp(found_name + 1, own_name) != 0) return;
  if (names_file(where, open_file)) ::unlink(where);
}

}  // namespace

// Sections nest (a TempFile made inside a section): only the outermost counts, or an inner one
// would wait for a handler that waits for the outer one.
thread_local int t_creation_depth = 0;

TempCreation::TempCreation() {
  const sigset_t block = ending_signals();
  pthread_sigmask(SIG_BLOCK, &block, &previous_);
  if (t_creation_depth++ > 0) return;
  g_creating.fetch_add(1);
  if (g_ending.load()) {
    // The handler has begun and will end the process: nothing may be created now, and this
    // thread has nothing left to do but wait for the exit, counted out so the handler does not
    // wait for it.
    g_creating.fetch_sub(1);
    for (;;) ::pause();
  }
}

TempCreation::~TempCreation() {
  if (--t_creation_depth == 0) g_creating.fetch_sub(1);
  pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

TempFile::TempFile(std::filesystem::path p) : path_(std::move(p)) {
  {
    const TempCreation creating;
    slot_ = claim_temp_slot(path_);
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd_ < 0) creation_error_ = errno;
    if (slot_ >= 0) g_temp_slots[size_t(slot_)].fd.store(fd_, std::memory_order_release);
  }
  // The writer opens the file again (write_path, or the plot script by name), which the mode
  // must allow: a umask without the owner's read and write (0222, 0277) would make the file
  // read-only. The owner gets them until release() gives back the umask's mode.
  if (struct stat st {}; fd_ >= 0 && ::fstat(fd_, &st) == 0) {
    mode_ = st.st_mode & 07777;
    if ((mode_ & 0600) != 0600) ::fchmod(fd_, mode_ | 0600);
  }
  static const bool proc_fds = ::access("/proc/self/fd", X_OK) == 0;
  write_path_ = fd_ >= 0 && proc_fds ? "/proc/self/fd/" + std::to_string(fd_) : path_.string();
}

std::string TempFile::named(std::string message) const {
  if (write_path_ == path_.native()) return message;
  for (size_t at = 0; (at = message.find(write_path_, at)) != std::string::npos;) {
    const size_t end = at + write_path_.size();
    if (end < message.size() && message[end] >= '0' && message[end] <= '9') {  // another descriptor, /proc/self/fd/35
      at = end;
      continue;
    }
    message.replace(at, write_path_.size(), path_.native());
    at += path_.native().size();
  }
  return message;
}

bool TempFile::at_its_path() const {
  struct stat open_file {};
  return fd_ >= 0 && ::fstat(fd_, &open_file) == 0 && names_file(path_.c_str(), open_file);
}

int TempFile::sync() const { return fd_ >= 0 && ::fsync(fd_) != 0 ? errno : 0; }

void TempFile::release() {
  released_ = true;
  if (fd_ >= 0 && (mode_ & 0600) != 0600) ::fchmod(fd_, mode_);
  // Unlisted before the descriptor closes, which narrows the window in which a handler on
  // another thread holds a number a later open may reuse; remove_temp's checks close it.
  free_temp_slot(slot_);
  slot_ = -1;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void set_temp_writer_child(pid_t pid) { g_temp_writer_child.store(pid, std::memory_order_release); }

void remove_temp_files_in_signal_handler() {
  g_ending.store(true);
  // A section on another thread ends within a few system calls (the signals are blocked on its
  // own thread, so it is never this one).
  while (g_creating.load() != 0) ::poll(nullptr, 0, 1);
  // Killed and reaped first: alive, it could create its temporary again after the unlink.
  if (const pid_t child = g_temp_writer_child.load(std::memory_order_acquire); child > 0) {
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
  }
  for (TempSlot& slot : g_temp_slots)
    if (slot.live.load(std::memory_order_acquire)) remove_temp(slot.path, slot.fd.load(std::memory_order_acquire));
  remove_created_folders();
}

void remove_created_folders() {
  for (int i = std::min(g_folder_count.load(), kFolderSlots) - 1; i >= 0; --i)
    if (g_folder_slots[size_t(i)].live.load(std::memory_order_acquire)) ::rmdir(g_folder_slots[size_t(i)].path);
}

OutputNames::OutputNames(const std::vector<std::filesystem::path>& inputs, std::string run) : run_(std::move(run)) {
  for (const std::filesystem::path& in : inputs) inputs_.push_back({entry(in), in, ""});
}

std::filesystem::path OutputNames::entry(const std::filesystem::path& path) {
  const std::filesystem::path folder = folder_of(path);
  if (folder != folder_ || canonical_folder_.empty()) {
    std::error_code ec;
    std::filesystem::path canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(folder, ec), ec);
    folder_ = folder;
    canonical_folder_ = ec ? folder : canonical;
  }
  return canonical_folder_ / path.filename();
}

void OutputNames::check(const std::filesystem::path& at, const std::filesystem::path& path,
                        const std::string& option) const {
  for (const Named& in : inputs_)
    if (in.entry == at)
      throw InputError(path.string(), option,
                       "is an input of this " + run_ + " (" + in.path.string() +
                           "): writing there would destroy it; choose another output name");
  for (const Named& out : kept_)
    if (out.entry == at)
      throw InputError(out.path.string(), out.option,
                       "is also where " + option + " writes (" + path.string() + "): one output would overwrite the other");
}

void OutputNames::add(const std::filesystem::path& path, const std::string& option) {
  const std::filesystem::path at = entry(path);
  check(at, path, option);
  kept_.push_back({at, path, option});
}

void OutputNames::add_frame(const std::filesystem::path& path, const std::string& option) {
  check(entry(path), path, option);
}

std::string temp_suffix() {
  // The pid alone is not unique: processes in separate pid namespaces (containers, or nodes
  // writing one shared folder) share pids, and two such renders of one output truncated and
  // removed each other's temporaries. A random token per process and a count within it make
  // every temporary's name its own.
  static const uint64_t token = [] {
    std::random_device rd;
    return (uint64_t(rd()) << 32) ^ uint64_t(rd());
  }();
  static std::atomic<uint64_t> count{0};
  char tail[64];
  std::snprintf(tail, sizeof tail, "%ld-%016llx-%llu", long(::getpid()), static_cast<unsigned long long>(token),
                static_cast<unsigned long long>(count.fetch_add(1, std::memory_order_relaxed)));
  return tail;
}

std::filesystem::path temp_beside(const std::filesystem::path& path) {
  // Appended piece by piece: `"." + string` trips GCC 12's -Wrestrict false positive.
  std::string tail = ".tmp-";
  tail += temp_suffix();
  std::string name = ".";
  name += path.filename().string();
  // A name is at most 255 bytes (NAME_MAX): the target's own part is cut so that a legal output
  // name of up to 255 keeps a legal temporary (a hunt found names of 229-255 refused, "File name
  // too long"); the suffix alone keeps it unique.
  constexpr size_t kNameMax = 255;
  if (name.size() + tail.size() > kNameMax) name.resize(kNameMax - tail.size());
  name += tail;
  return folder_of(path) / name;
}

TempFile::~TempFile() {
  if (released_) return;
  // Removed before its slot is freed: a signal in between finds it still listed (unlinking a
  // file already gone is harmless), where the other order let it escape the handler. Its path
  // names nothing once its folder has been moved: then it is removed where it lies now.
  remove_temp(path_.c_str(), fd_);
  free_temp_slot(slot_);
  if (fd_ >= 0) ::close(fd_);
}

bool writes_through(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st) || fs::is_directory(st)) return false;
  if (!fs::is_regular_file(st)) return true;
  const auto under_proc = [](const fs::path& p) {
    auto part = p.begin();
    return p.is_absolute() && part != p.end() && ++part != p.end() && *part == "proc";
  };
  if (fs::is_symlink(fs::symlink_status(path, ec)) && under_proc(fs::read_symlink(path, ec))) return true;
  const fs::path folder = fs::weakly_canonical(fs::absolute(folder_of(path), ec), ec);
  return !ec && under_proc(folder);
}

void prepare_output(const std::filesystem::path& path, const std::string& field) {
  const std::string file = path.string();
  if (path.empty() || !path.has_filename()) throw InputError(file, field, "names no file");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(file, field, "is a folder, not a file");
  if (writes_through(path)) {
    if (::access(path.c_str(), W_OK) != 0)
      throw InputError(file, field, std::string("cannot be written: ") + std::strerror(errno));
    return;
  }
  const std::filesystem::path dir = folder_of(path);
  {
    // The folders this makes are listed in the same section as they are made, so a signal
    // ending the run finds each one it made listed (and takes it back if still empty).
    std::vector<std::filesystem::path> missing;  // deepest first
    for (std::filesystem::path p = dir; !p.empty() && !std::filesystem::exists(p, ec); p = p.parent_path()) {
      missing.push_back(p);
      if (p == p.parent_path()) break;
    }
    const TempCreation creating;
    std::filesystem::create_directories(dir, ec);
    for (auto it = missing.rbegin(); !ec && it != missing.rend(); ++it) {
      const std::string& name = it->native();
      const int i = g_folder_count.fetch_add(1);
      if (i >= kFolderSlots || name.size() >= kTempPathBytes) continue;
      std::memcpy(g_folder_slots[size_t(i)].path, name.c_str(), name.size() + 1);
      g_folder_slots[size_t(i)].live.store(true, std::memory_order_release);
    }
  }
  if (ec) throw InputError(file, field, "cannot create folder " + dir.string() + ": " + ec.message());
  // Creating the temporary is the test that counts: permissions, a read-only file system and
  // a full inode table all show here, as they would at the end of the run.
  const TempFile probe(temp_beside(path));
  if (const int error = probe.creation_error())
    throw InputError(file, field, "cannot create a file in " + dir.string() + ": " + std::strerror(error));
}

AtomicOutput::AtomicOutput(std::filesystem::path target)
    : target_(std::move(target)), target_string_(target_.string()) {
  if (!writes_through(target_)) tmp_.emplace(temp_beside(target_));
}

void AtomicOutput::commit(const std::string& field, const std::string& what) {
  if (!tmp_) return;
  if (const int error = tmp_->sync())
    throw InputError(target_string_, field, "cannot write " + what + " to the disk: " + std::strerror(error));
  std::error_code ec;
  std::filesystem::rename(tmp_->path(), target_, ec);
  if (ec == std::errc::no_such_file_or_directory && !tmp_->at_its_path())
    throw InputError(target_string_, field,
                     "cannot move " + what + " into place: its folder was moved or removed while it was written");
  if (ec) throw InputError(target_string_, field, "cannot move " + what + " into place: " + ec.message());
  tmp_->release();
  sync_folder_of(target_);
}

void sync_folder_of(const std::filesystem::path& file) {
  if (const int dir = ::open(folder_of(file).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

void write_text_atomic(const std::filesystem::path& path, const std::string& text, const std::string& field) {
  const std::string file = path.string();
  AtomicOutput out(path);
  {
    std::ofstream f(out.write_path(), std::ios::binary);
    if (!f)
      throw InputError(file, field,
                       out.in_place() ? "cannot be written" : "cannot create a file in " + folder_of(path).string());
    f << text;
    f.close();
    if (!f) throw InputError(file, field, "write failed");
  }
  out.commit(field, "the file");
}

}  // namespace pelt::io
