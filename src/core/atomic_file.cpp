#include "inhap/core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "inhap/core/error.hpp"

namespace inhap {

namespace {

long g_fail_write = 0, g_fail_rename = 0;  // fault injection countdowns (0: off)

bool injected(long& countdown) {
  if (countdown <= 0) return false;
  if (--countdown > 0) return false;
  errno = EIO;
  return true;
}

int rename_file(const std::string& from, const std::string& to) {
  if (injected(g_fail_rename)) return -1;
  return std::rename(from.c_str(), to.c_str());
}

thread_local OutputTransaction* t_active = nullptr;

// 16 hex digits from the kernel's random source: a name nobody can plant a link under in
// advance (the file is also created with O_EXCL | O_NOFOLLOW).
std::string random_suffix() {
  unsigned char b[8] = {};
  std::size_t got = 0;
  while (got < sizeof b) {
    const ssize_t n = ::getrandom(b + got, sizeof b - got, 0);
    if (n > 0)
      got += static_cast<std::size_t>(n);
    else if (errno != EINTR)
      throw Error("getrandom failed");
  }
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned char c : b) out += hex[c >> 4], out += hex[c & 15];
  return out;
}

// A new file, created here and now: fails (EEXIST) when anything, a symlink included, has the
// name already.
std::FILE* create_exclusive(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) return nullptr;
  std::FILE* f = ::fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    ::close(fd);
    ::unlink(path.c_str());
    errno = err;
  }
  return f;
}

}  // namespace

namespace fault {
void fail_nth_write(long n) {
  g_fail_write = n;
}
void fail_nth_rename(long n) {
  g_fail_rename = n;
}
void from_environment() {
  auto nth = [](const char* name) -> long {
    const char* v = std::getenv(name);
    return v && *v ? std::strtol(v, nullptr, 10) : 0;
  };
  if (const long n = nth("INHAP_TEST_FAIL_NTH_WRITE"); n > 0) fail_nth_write(n);
  if (const long n = nth("INHAP_TEST_FAIL_NTH_RENAME"); n > 0) fail_nth_rename(n);
}
}  // namespace fault

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  tmp_ = path_ + ".tmp." + random_suffix();
  std::error_code dir_ec;
  if (std::filesystem::is_directory(path_, dir_ec))
    throw Error(path_ + ": expected a file to write, got a directory");
  errno = 0;
  file_ = create_exclusive(tmp_);
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
  if (injected(g_fail_write) || std::fwrite(data, 1, size, file_) != size)
    throw IoError(path_, "write failed");
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
  if (OutputTransaction* t = OutputTransaction::active()) {
    t->defer(tmp_, path_);
    return;
  }
  errno = 0;
  if (rename_file(tmp_, path_) != 0) {
    const int err = errno;
    std::remove(tmp_.c_str());
    errno = err;
    throw IoError(path_, "cannot move the finished temporary file into place");
  }
}

OutputTransaction::OutputTransaction() {
  if (t_active) throw Error("internal: output transactions do not nest");
  t_active = this;
}

OutputTransaction::~OutputTransaction() {
  if (t_active == this) t_active = nullptr;
  if (!done_)
    for (const Pending& p : pending_) std::remove(p.tmp.c_str());
}

OutputTransaction* OutputTransaction::active() {
  return t_active;
}

void OutputTransaction::defer(std::string tmp, std::string path) {
  // The same path written twice: its temporary (same name) now holds the later content.
  std::erase_if(pending_, [&](const Pending& p) { return p.path == path; });
  pending_.push_back({std::move(tmp), std::move(path)});
}

void OutputTransaction::commit() {
  if (t_active == this) t_active = nullptr;
  done_ = true;
  // A hard link keeps each old output reachable until every rename has succeeded.
  const std::string bak_suffix = ".bak." + random_suffix();
  std::vector<bool> had_old(pending_.size(), false);
  auto cleanup_backups = [&](std::size_t upto) {
    for (std::size_t i = 0; i < upto; ++i)
      if (had_old[i]) std::remove((pending_[i].path + bak_suffix).c_str());
  };
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const std::string& path = pending_[i].path;
    std::error_code ec;
    // symlink_status: a link at the path is kept as the link (link() does not follow it).
    const auto st = std::filesystem::symlink_status(path, ec);
    if (!std::filesystem::exists(st)) continue;
    const std::string bak = path + bak_suffix;
    std::filesystem::create_hard_link(path, bak, ec);
    if (ec && std::filesystem::is_regular_file(st)) std::filesystem::copy_file(path, bak, ec);
    if (ec) {
      cleanup_backups(i);
      for (const Pending& p : pending_) std::remove(p.tmp.c_str());
      throw Error(path + ": cannot keep the old file while replacing it (" + ec.message() + ")");
    }
    had_old[i] = true;
  }
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    errno = 0;
    if (rename_file(pending_[i].tmp, pending_[i].path) == 0) continue;
    const int err = errno;
    for (std::size_t j = 0; j < i; ++j) {  // roll back what was renamed
      if (had_old[j])
        std::rename((pending_[j].path + bak_suffix).c_str(), pending_[j].path.c_str());
      else
        std::remove(pending_[j].path.c_str());
      had_old[j] = false;
    }
    for (std::size_t j = i; j < pending_.size(); ++j) std::remove(pending_[j].tmp.c_str());
    cleanup_backups(pending_.size());
    errno = err;
    throw IoError(
        pending_[i].path,
        "cannot move the finished temporary file into place (no output of this command was "
        "changed)");
  }
  cleanup_backups(pending_.size());
}

OutputFolder::OutputFolder(std::string path) : path_(std::move(path)) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path_, ec)) return;
  // The folders this creates, deepest first (removed again, when empty, on failure).
  for (fs::path p = path_; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    created_.push_back(p.string());
    if (p == p.parent_path()) break;
  }
  fs::create_directories(path_, ec);
  if (ec || !fs::is_directory(path_)) {
    created_.clear();
    throw Error(path_ + ": cannot create the output folder (" +
                (ec ? ec.message() : std::string("a file of that name exists")) + ")");
  }
}

OutputFolder::~OutputFolder() {
  if (keep_) return;
  std::error_code ec;
  for (const std::string& p : created_) {
    if (!std::filesystem::is_empty(p, ec) || ec) return;
    std::filesystem::remove(p, ec);
  }
}

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path + ": expected an output file, got a directory");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw Error(path + ": cannot write: the folder " + parent.string() + " does not exist");
  const std::string probe = path + ".probe." + random_suffix();
  errno = 0;
  std::FILE* f = create_exclusive(probe);
  if (!f) throw IoError(path, "cannot write");
  std::fclose(f);
  std::remove(probe.c_str());
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
  std::error_code dir_ec;
  if (std::filesystem::is_directory(path, dir_ec))
    throw Error(path + ": expected a file, got a directory");
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
