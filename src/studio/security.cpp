#include "inhap/studio/security.hpp"

#include <fmt/format.h>
#include <sodium.h>

#include <array>
#include <system_error>

#include "inhap/core/error.hpp"
#include "inhap/studio/protocol.hpp"

namespace fs = std::filesystem;

namespace inhap::studio {

std::string make_token() {
  if (sodium_init() < 0) throw Error("libsodium: sodium_init failed");
  std::array<unsigned char, 16> bytes{};
  randombytes_buf(bytes.data(), bytes.size());
  std::array<char, 33> hex{};
  sodium_bin2hex(hex.data(), hex.size(), bytes.data(), bytes.size());
  return std::string(hex.data(), 32);
}

bool token_matches(std::string_view presented, std::string_view token) {
  if (presented.empty() || token.empty() || presented.size() != token.size()) return false;
  return sodium_memcmp(presented.data(), token.data(), token.size()) == 0;
}

namespace {

// Value of `key` in a list of `key=value` items separated by `sep` (spaces after it skipped).
std::string item_value(std::string_view list, std::string_view key, char sep) {
  std::size_t pos = 0;
  while (pos <= list.size()) {
    std::size_t end = list.find(sep, pos);
    if (end == std::string_view::npos) end = list.size();
    std::string_view item = list.substr(pos, end - pos);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    const std::size_t eq = item.find('=');
    if (eq != std::string_view::npos && item.substr(0, eq) == key)
      return std::string(item.substr(eq + 1));
    pos = end + 1;
  }
  return {};
}

bool loopback_authority(std::string_view authority, int port) {
  const std::string p = std::to_string(port);
  return authority == "127.0.0.1:" + p || authority == "localhost:" + p;
}

}  // namespace

std::string query_value(std::string_view query, std::string_view key) {
  return item_value(query, key, '&');
}

std::string cookie_value(std::string_view cookie_header, std::string_view name) {
  return item_value(cookie_header, name, ';');
}

bool request_authorized(std::string_view query, std::string_view cookie_header,
                        std::string_view token) {
  return token_matches(query_value(query, "token"), token) ||
         token_matches(cookie_value(cookie_header, kCookieName), token);
}

bool host_allowed(std::string_view host, int port) {
  return loopback_authority(host, port);
}

bool origin_allowed(std::string_view origin, int port, bool required) {
  if (origin.empty()) return !required;
  constexpr std::string_view scheme = "http://";
  if (origin.substr(0, scheme.size()) != scheme) return false;
  return loopback_authority(origin.substr(scheme.size()), port);
}

void Workspace::check_name(std::string_view relative) const {
  const auto refuse = [&](const char* why) {
    throw Error(fmt::format("workspace path \"{}\": {}", quote_input(relative, 200), why));
  };
  if (relative.empty()) refuse("expected a file name, got nothing");
  if (relative.find('\0') != std::string_view::npos) refuse("contains a NUL byte");
  if (relative.find('\\') != std::string_view::npos) refuse("contains a backslash");
  const fs::path rel(relative);
  if (rel.is_absolute() || relative.front() == '/')
    refuse("expected a path relative to the workspace, got an absolute path");
  for (const auto& part : rel) {
    if (part == "..") refuse("'..' is not allowed");
    if (part.string().size() > 255) refuse("a name is longer than 255 bytes");
  }
  if (rel.filename().empty() || rel.filename() == ".") refuse("expected a file name");
}

fs::path Workspace::resolve(std::string_view relative) const {
  check_name(relative);
  const auto refuse = [&](const char* why) -> fs::path {
    throw Error(fmt::format("workspace path \"{}\": {}", quote_input(relative, 200), why));
  };
  // Symlinks: resolve what exists of the path and require it to stay inside the root.
  std::error_code ec;
  const fs::path full = fs::weakly_canonical(root_ / fs::path(relative), ec);
  if (ec) return refuse("cannot be resolved");
  auto r = root_.begin();
  auto f = full.begin();
  for (; r != root_.end(); ++r, ++f)
    if (f == full.end() || *r != *f) return refuse("leads outside the workspace (symlink)");
  if (f == full.end()) return refuse("expected a file inside the workspace, got the workspace");
  return full;
}

}  // namespace inhap::studio
