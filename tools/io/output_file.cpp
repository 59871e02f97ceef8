#include "tools/io/output_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <unistd.h>

#include "tools/io/input_error.h"

namespace pelt::io {
namespace {

std::filesystem::path folder_of(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

}  // namespace

std::filesystem::path temp_beside(const std::filesystem::path& path) {
  // Appended piece by piece: `"." + string` trips GCC 12's -Wrestrict false positive.
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  return folder_of(path) / name;
}

TempFile::~TempFile() {
  if (released_) return;
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

void prepare_output(const std::filesystem::path& path, const std::string& field) {
  const std::string file = path.string();
  if (path.empty() || !path.has_filename()) throw InputError(file, field, "names no file");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(file, field, "is a folder, not a file");
  const std::filesystem::path dir = folder_of(path);
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(file, field, "cannot create folder " + dir.string() + ": " + ec.message());
  // Opening the temporary is the test that counts: permissions, a read-only file system and
  // a full inode table all show here, as they would at the end of the run.
  const TempFile probe(temp_beside(path));
  std::FILE* f = std::fopen(probe.path().c_str(), "wb");
  if (!f) throw InputError(file, field, "cannot create a file in " + dir.string() + ": " + std::strerror(errno));
  std::fclose(f);
}

void write_text_atomic(const std::filesystem::path& path, const std::string& text, const std::string& field) {
  const std::string file = path.string();
  TempFile tmp(temp_beside(path));
  {
    std::ofstream f(tmp.path(), std::ios::binary);
    if (!f) throw InputError(file, field, "cannot create a file in " + folder_of(path).string());
    f << text;
    f.close();
    if (!f) throw InputError(file, field, "write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp.path(), path, ec);
  if (ec) throw InputError(file, field, "cannot move the file into place: " + ec.message());
  tmp.release();
}

}  // namespace pelt::io
