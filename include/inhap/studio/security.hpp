// inhap studio: the server's access rules (docs/studio.md, "Security").
//  - A random token (libsodium randombytes_buf, 128 bits, hex) is printed in the URL; every HTTP
//    request and every WebSocket upgrade must carry it (query `token=` or the cookie the server
//    sets on the first good request), else 403.
//  - The Host header must name the loopback address and port the server listens on (no DNS
//    rebinding), and an Origin header, when present (always on a WebSocket upgrade), must be
//    http://127.0.0.1:PORT or http://localhost:PORT.
//  - Files are read and written only inside the workspace folder: relative paths only, no `..`;
//    every file is opened beneath the workspace's folder without following any symlink
//    (openat2 RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS, or O_NOFOLLOW per component where the
//    kernel lacks openat2), and written through an exclusively created temporary.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "inhap/core/error.hpp"

namespace inhap::studio {

/// 32 hex characters from libsodium's randombytes_buf (16 random bytes).
std::string make_token();

/// Constant-time comparison of a presented token with the server's (false when either is empty).
bool token_matches(std::string_view presented, std::string_view token);

/// The raw value of `key` in a URL query string ("a=1&token=x" -> "x"), empty when absent.
std::string query_value(std::string_view query, std::string_view key);
/// The value of cookie `name` in a Cookie header ("a=1; inhap_studio=x" -> "x"), empty if absent.
std::string cookie_value(std::string_view cookie_header, std::string_view name);

/// The request carries the token: in the query string or in the studio cookie.
bool request_authorized(std::string_view query, std::string_view cookie_header,
                        std::string_view token);

/// Host header of a request to the server on 127.0.0.1:port: "127.0.0.1:PORT" or
/// "localhost:PORT" (anything else, a missing header included, is refused).
bool host_allowed(std::string_view host, int port);
/// Origin header: empty (a same-origin navigation sends none) when `required` is false, else
/// exactly http://127.0.0.1:PORT or http://localhost:PORT.
bool origin_allowed(std::string_view origin, int port, bool required);

inline constexpr const char* kCookieName = "inhap_studio";

/// A file (input) or the folder of a file to write (output) opened beneath the workspace, with a
/// path through that open handle (/proc/self/fd/N[/NAME]) for the library's path-based readers
/// and writers: the path cannot be redirected by a link planted after the open.
class WorkspacePath {
 public:
  /// `from` in messages stands for `to` (the handle's path for the page's path).
  WorkspacePath(int fd, std::string path, std::string name, std::string from, std::string to);
  ~WorkspacePath();
  WorkspacePath(WorkspacePath&& o) noexcept;
  WorkspacePath(const WorkspacePath&) = delete;
  WorkspacePath& operator=(const WorkspacePath&) = delete;
  WorkspacePath& operator=(WorkspacePath&&) = delete;
  /// For readers (input) and writers (output: the file name is its last component).
  const std::string& path() const { return path_; }
  /// The path as the page gave it (quoted), for messages.
  const std::string& name() const { return name_; }
  int fd() const { return fd_; }
  /// `message` with the handle's path replaced by the page's.
  std::string tidy(std::string message) const;

 private:
  int fd_ = -1;
  std::string path_, name_, from_, to_;
};

/// The folder the studio reads and writes in.
class Workspace {
 public:
  /// Creates the folder when missing and keeps it open; throws Error when it cannot be used.
  explicit Workspace(const std::filesystem::path& root);
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  const std::filesystem::path& root() const { return root_; }
  /// The absolute path of `relative` inside the workspace. Throws Error (naming the path and the
  /// rule) for an empty or absolute path, a `..` component, a NUL or backslash, a name over 255
  /// bytes, or a path that, following symlinks, leaves the workspace. A first check of the
  /// name only: files are opened with input() / output() / read().
  std::filesystem::path resolve(std::string_view relative) const;

  /// Opens `relative` beneath the workspace, following no symlink on the way (the checks of
  /// resolve() first). Returns the descriptor; throws IoError naming the path.
  int open(std::string_view relative, int flags, unsigned mode = 0) const;
  /// A regular file to read.
  WorkspacePath input(std::string_view relative) const;
  /// The folder of a file to write; path() = that folder's handle + "/" + the file name, for
  /// AtomicFile (an exclusive temporary with a random name, renamed onto the name).
  WorkspacePath output(std::string_view relative) const;
  /// The whole content of a regular file (at most max_bytes).
  std::string read(std::string_view relative, std::size_t max_bytes = std::size_t(1) << 28) const;
  /// Writes a whole file atomically (a random exclusive temporary, renamed onto the name).
  void write(std::string_view relative, std::string_view content) const;
  /// Names of the regular files and symlinks directly in the workspace folder, sorted (input()
  /// refuses the symlinks).
  std::vector<std::string> list() const;

 private:
  void check_name(std::string_view relative) const;  ///< the rules of resolve() but symlinks
  std::filesystem::path root_;                       // canonical
  int root_fd_ = -1;
};

/// Runs fn(); an inhap::Error it throws is thrown again with every WorkspacePath's path()
/// replaced by its name() (errors name the file as the page gave it).
template <class Fn>
auto with_names(std::initializer_list<const WorkspacePath*> files, Fn&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (const Error& e) {
    std::string m = e.what();
    for (const WorkspacePath* f : files)
      if (f) m = f->tidy(std::move(m));
    throw Error(m);
  }
}

}  // namespace inhap::studio
