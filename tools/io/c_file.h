// A file opened for reading as a C stream, for the C libraries that read from one (libpng's and
// libjpeg's readers, png_reader.h, jpeg_reader.h), closed with its owner.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace pelt::io {

class CFile {
 public:
  CFile() = default;
  CFile(const CFile&) = delete;
  CFile& operator=(const CFile&) = delete;
  ~CFile() {
    if (file_) std::fclose(file_);
  }

  // Opens `file` to read; false with `error` set to the system's reason when it cannot.
  bool open(const std::string& file, std::string& error) {
    file_ = std::fopen(file.c_str(), "rb");
    if (!file_) error = std::strerror(errno);
    return file_ != nullptr;
  }
  std::FILE* get() const { return file_; }

 private:
  std::FILE* file_ = nullptr;
};

}  // namespace pelt::io
