// Output files (images, GIFs, JSON results and statistics, tables) are written to a
// temporary beside the target and renamed over it only once complete, so a failed or
// interrupted write leaves no partial file. A destination that cannot be written is found
// before the work that fills it (prepare_output), not after minutes of rendering.
#pragma once

#include <filesystem>
#include <string>

namespace pelt::io {

// The temporary an atomic writer fills before renaming it over `path`: `.NAME.tmp-PID` in
// path's folder (the same file system, so the rename is atomic).
std::filesystem::path temp_beside(const std::filesystem::path& path);

// Removes its file at scope exit unless released: every early exit leaves no file behind.
class TempFile {
 public:
  explicit TempFile(std::filesystem::path p) : path_(std::move(p)) {}
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::filesystem::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  bool released_ = false;
};

// Creates path's folder (with its parents, as `pelt render -o` does) and proves that a file
// can be made there by creating and removing the temporary an atomic write would use. The
// target itself is not touched. Throws InputError(path, field, reason): e.g. a parent that
// is a regular file, a read-only folder, or a path that names a folder.
void prepare_output(const std::filesystem::path& path, const std::string& field);

// Writes `text` to `path` atomically (through temp_beside). Throws InputError(path, field,
// reason) and leaves neither the target nor the temporary when any step fails.
void write_text_atomic(const std::filesystem::path& path, const std::string& text, const std::string& field);

}  // namespace pelt::io
