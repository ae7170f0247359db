// Atomic file writing: content goes to "<path>.tmp.<pid>" and is renamed onto <path> only when
// commit() succeeds, so a crash or an error never leaves a half-written file behind.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace inhap {

class AtomicFile {
 public:
  /// Opens a temporary file beside `path` (binary mode). Throws IoError.
  explicit AtomicFile(std::string path);
  ~AtomicFile();  ///< removes the temporary file if commit() was not called
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view bytes);
  void write(const void* data, std::size_t size);
  std::FILE* handle() { return file_; }
  /// Flushes, closes and renames onto the final path. Throws IoError.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
};

/// Writes a whole string atomically.
void write_file_atomic(const std::string& path, std::string_view content);
/// Reads a whole file. Throws IoError.
std::string read_file(const std::string& path);

}  // namespace inhap
