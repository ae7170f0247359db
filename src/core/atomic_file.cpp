#include "inhap/core/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>

#include "inhap/core/error.hpp"

namespace inhap {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  tmp_ = path_ + ".tmp." + std::to_string(::getpid());
  errno = 0;
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (!file_) throw IoError(path_, "cannot open for writing");
  // A buffer of its own per file (stdio allocates it): two AtomicFiles open at once must not
  // share one.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

AtomicFile::~AtomicFile() {
  if (file_) {
    std::fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::write(std::string_view bytes) {
  write(bytes.data(), bytes.size());
}

void AtomicFile::write(const void* data, std::size_t size) {
  if (size == 0) return;
  errno = 0;
  if (std::fwrite(data, 1, size, file_) != size) throw IoError(path_, "write failed");
}

void AtomicFile::commit() {
  errno = 0;
  bool ok = std::fflush(file_) == 0;
  ok = (std::fclose(file_) == 0) && ok;
  file_ = nullptr;
  if (!ok) {
    std::remove(tmp_.c_str());
    throw IoError(path_, "write failed");
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    std::remove(tmp_.c_str());
    throw IoError(path_, "cannot rename temporary file onto");
  }
}

void write_file_atomic(const std::string& path, std::string_view content) {
  AtomicFile f(path);
  f.write(content);
  f.commit();
}

std::string read_file(const std::string& path) {
  // One allocation of the file's size and one fread (large meshes are read this way); the loop
  // also handles files whose size is unknown or changes while reading.
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw IoError(path, "cannot open for reading");
  std::string out;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  std::size_t used = 0;
  out.resize(ec ? std::size_t{1} << 16 : static_cast<std::size_t>(size) + 1);
  while (true) {
    used += std::fread(out.data() + used, 1, out.size() - used, f);
    if (used < out.size()) break;
    out.resize(out.size() * 2);
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IoError(path, "read failed");
  out.resize(used);
  return out;
}

}  // namespace inhap
