// inhap studio: the server's access rules (docs/studio.md, "Security").
//  - A random token (libsodium randombytes_buf, 128 bits, hex) is printed in the URL; every HTTP
//    request and every WebSocket upgrade must carry it (query `token=` or the cookie the server
//    sets on the first good request), else 403.
//  - The Host header must name the loopback address and port the server listens on (no DNS
//    rebinding), and an Origin header, when present (always on a WebSocket upgrade), must be
//    http://127.0.0.1:PORT or http://localhost:PORT.
//  - Files are read and written only inside the workspace folder: relative paths only, no `..`,
//    no symlink that leads outside (Workspace::resolve).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

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

/// The folder the studio reads and writes in.
class Workspace {
 public:
  /// Creates the folder when missing; throws Error when it cannot be used.
  explicit Workspace(const std::filesystem::path& root);
  const std::filesystem::path& root() const { return root_; }
  /// The absolute path of `relative` inside the workspace. Throws Error (naming the path and the
  /// rule) for an empty or absolute path, a `..` component, a NUL or backslash, a name over 255
  /// bytes, or a path that, following symlinks, leaves the workspace.
  std::filesystem::path resolve(std::string_view relative) const;

 private:
  std::filesystem::path root_;  // canonical
};

}  // namespace inhap::studio
