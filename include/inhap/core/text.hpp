// Small text helpers shared by the file readers (header parsing). No units involved.
#pragma once

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

namespace inhap::text {

/// `s` without leading and trailing spaces, tabs, carriage returns and newlines.
inline std::string_view trim_view(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// trim_view() as an owned string.
inline std::string trim(std::string_view s) {
  return std::string(trim_view(s));
}

/// ASCII lower case.
inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace inhap::text
