// inhap studio: workspace files opened beneath the workspace folder without following links
// (security.hpp). openat2(RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS) where the kernel has it (5.6+),
// else one openat(O_NOFOLLOW) per component; the library's path-based readers and writers then
// get a path through the open handle (/proc/self/fd/N), which a link planted later cannot
// redirect.
#include <dirent.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <linux/openat2.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "inhap/core/atomic_file.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/security.hpp"

namespace fs = std::filesystem;

namespace inhap::studio {
namespace {

std::string proc_fd(int fd) {
  return fmt::format("/proc/self/fd/{}", fd);
}

// One openat(O_NOFOLLOW) per component (the names were checked: no "..", no absolute path).
int open_per_component(int root, const std::string& rel, int flags, unsigned mode) {
  std::vector<std::string> parts;
  for (const auto& p : fs::path(rel))
    if (!p.empty() && p != "." && p != "/") parts.push_back(p.string());
  if (parts.empty()) {
    errno = EISDIR;
    return -1;
  }
  int dir = ::fcntl(root, F_DUPFD_CLOEXEC, 0);
  for (std::size_t i = 0; dir >= 0 && i + 1 < parts.size(); ++i) {
    const int next =
        ::openat(dir, parts[i].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    const int err = errno;
    ::close(dir);
    errno = err;
    dir = next;
  }
  if (dir < 0) return -1;
  const int fd = ::openat(dir, parts.back().c_str(), flags | O_NOFOLLOW | O_CLOEXEC, mode);
  const int err = errno;
  ::close(dir);
  errno = err;
  return fd;
}

const char* why(int err) {
  switch (err) {
    case ELOOP:
      return "is or passes through a symbolic link (not followed in the workspace)";
    case EXDEV:
      return "leads outside the workspace";
    case ENOTDIR:
      return "a folder on the way is not a folder (or is a symbolic link)";
    case ENOENT:
      return "no such file or folder";
    default:
      return std::strerror(err);
  }
}

}  // namespace

WorkspacePath::WorkspacePath(int fd, std::string path, std::string name, std::string from,
                             std::string to)
    : fd_(fd),
      path_(std::move(path)),
      name_(std::move(name)),
      from_(std::move(from)),
      to_(std::move(to)) {}

WorkspacePath::~WorkspacePath() {
  if (fd_ >= 0) ::close(fd_);
}

WorkspacePath::WorkspacePath(WorkspacePath&& o) noexcept
    : fd_(o.fd_),
      path_(std::move(o.path_)),
      name_(std::move(o.name_)),
      from_(std::move(o.from_)),
      to_(std::move(o.to_)) {
  o.fd_ = -1;
}

std::string WorkspacePath::tidy(std::string m) const {
  if (from_.empty()) return m;
  for (std::size_t at = m.find(from_); at != std::string::npos; at = m.find(from_, at + to_.size()))
    m.replace(at, from_.size(), to_);
  return m;
}

Workspace::Workspace(const fs::path& root) {
  std::error_code ec;
  fs::create_directories(root, ec);
  if (!fs::is_directory(root))
    throw Error(fmt::format("--workspace {}: not a folder and cannot be created", root.string()));
  root_ = fs::canonical(root);
  root_fd_ = ::open(root_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (root_fd_ < 0) throw IoError(root_.string(), "--workspace: cannot open the folder");
  if (::access((proc_fd(root_fd_) + "/.").c_str(), F_OK) != 0) {
    ::close(root_fd_);
    throw Error("--workspace: /proc/self/fd is needed to open workspace files safely (Linux)");
  }
}

Workspace::~Workspace() {
  if (root_fd_ >= 0) ::close(root_fd_);
}

int Workspace::open(std::string_view relative, int flags, unsigned mode) const {
  check_name(relative);  // no "..", not absolute, no NUL, ...
  const std::string rel(relative);
  int fd = -1;
#ifdef SYS_openat2
  open_how how{};
  how.flags = static_cast<std::uint64_t>(flags | O_CLOEXEC);
  how.mode = (flags & O_CREAT) ? mode : 0;
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS | RESOLVE_NO_MAGICLINKS;
  fd = static_cast<int>(::syscall(SYS_openat2, root_fd_, rel.c_str(), &how, sizeof how));
  if (fd < 0 && (errno == ENOSYS || errno == EPERM))  // an older kernel, or a seccomp filter
    fd = open_per_component(root_fd_, rel, flags, mode);
#else
  fd = open_per_component(root_fd_, rel, flags, mode);
#endif
  if (fd < 0)
    throw Error(fmt::format("workspace path \"{}\": {}", quote_input(relative, 200), why(errno)));
  return fd;
}

WorkspacePath Workspace::input(std::string_view relative) const {
  const int fd = open(relative, O_RDONLY);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error(
        fmt::format("workspace path \"{}\": expected a regular file", quote_input(relative, 200)));
  }
  std::string path = proc_fd(fd), name = quote_input(relative, 200);
  return WorkspacePath(fd, path, name, path, name);
}

WorkspacePath Workspace::output(std::string_view relative) const {
  check_name(relative);
  const std::string file = fs::path(relative).filename().string();
  const std::string parent = fs::path(relative).parent_path().string();
  const int fd = parent.empty() || parent == "." ? ::fcntl(root_fd_, F_DUPFD_CLOEXEC, 0)
                                                 : open(parent, O_RDONLY | O_DIRECTORY);
  if (fd < 0) throw IoError(root_.string(), "cannot open the workspace folder");
  const std::string dir_shown = fd == root_fd_ || parent.empty() || parent == "."
                                    ? std::string()
                                    : quote_input(parent, 200) + "/";
  return WorkspacePath(fd, proc_fd(fd) + "/" + file, quote_input(relative, 200), proc_fd(fd) + "/",
                       dir_shown);
}

std::string Workspace::read(std::string_view relative, std::size_t max_bytes) const {
  const WorkspacePath in = input(relative);
  struct stat st {};
  if (::fstat(in.fd(), &st) != 0 || static_cast<std::size_t>(st.st_size) > max_bytes)
    throw Error(fmt::format("{}: larger than {} bytes", in.name(), max_bytes));
  return with_names({&in}, [&] { return read_file(in.path()); });
}

void Workspace::write(std::string_view relative, std::string_view content) const {
  const WorkspacePath out = output(relative);
  with_names({&out}, [&] { write_file_atomic(out.path(), content); });
}

std::vector<std::string> Workspace::list() const {
  std::vector<std::string> names;
  const int fd = ::openat(root_fd_, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  DIR* d = fd >= 0 ? ::fdopendir(fd) : nullptr;
  if (!d) {
    if (fd >= 0) ::close(fd);
    throw IoError(root_.string(), "cannot list the workspace");
  }
  while (const dirent* e = ::readdir(d)) {
    struct stat st {};
    if (::fstatat(fd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 &&
        (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)))
      names.emplace_back(e->d_name);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace inhap::studio
