// The one exception type for bad user input (scene files, meshes, images, CLI values).
// The CLI maps it to exit code 2; everything else that throws is a bug.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pelt::io {

// unreadable_file_reason's word for a missing file, which callers say in their own words.
inline constexpr const char* kFileNotFound = "not found";

// Why the file at `path` cannot be read as a file ("" when it can): missing (kFileNotFound), a
// folder, or not a regular file. Every reader of a file a user names checks it first: a pipe or
// a device such as /dev/zero would be read without end, and a folder's "size" (2^63) was
// allocated by tinygltf.
inline std::string unreadable_file_reason(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return kFileNotFound;
  if (std::filesystem::is_directory(path, ec)) return "is a folder";
  if (!std::filesystem::is_regular_file(path, ec)) return "is not a regular file (a device, a pipe or a socket)";
  return "";
}

// A bad input, located as precisely as we can: the file it came from, the field inside
// it (a JSON path such as `objects[1].transform.scale`, or an element such as
// `vertex 12`; empty when the whole file is at fault) and why it was rejected.
// what() reads "FILE: FIELD: REASON", leaving out an empty FILE or FIELD (a command-line
// option is named as the field with no file: "--frames: ..."), so a user can act on the
// message without a debugger.
struct InputError : std::runtime_error {
  InputError(std::string file_, std::string field_, std::string reason_)
      : std::runtime_error(compose(file_, field_, reason_)),
        file(std::move(file_)),
        field(std::move(field_)),
        reason(std::move(reason_)) {}

  std::string file;
  std::string field;
  std::string reason;

 private:
  static std::string compose(const std::string& file, const std::string& field,
                             const std::string& reason) {
    std::string s = file;
    if (!field.empty()) s += (s.empty() ? "" : ": ") + field;
    s += (s.empty() ? "" : ": ") + reason;
    // A NUL from the input (a JSON "\u0000" in a path) would end what() there, and the message
    // with it: it is shown as \0.
    for (size_t at = s.find('\0'); at != std::string::npos; at = s.find('\0', at + 2)) s.replace(at, 1, "\\0");
    return s;
  }
};

}  // namespace pelt::io
