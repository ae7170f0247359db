// Small text helpers shared by the file readers (header parsing) and the program (flag
// suggestions, progress lines). No units involved.
#pragma once

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>
#include <vector>

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

/// Levenshtein distance (insertions, deletions, substitutions) between two strings.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` by edit_distance(), when it is closer than half the word's
/// length plus one (the first of equals); empty when none is.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

/// `s` on one line (newlines as spaces), cut to `max_len` characters plus "..." when longer.
std::string one_line(std::string s, std::size_t max_len);

/// The progress line of the program: "[what]  42% (eta 3 s)" (the eta only while unfinished and
/// known), a newline at fraction 1; on a terminal (`tty`) it starts with a carriage return so
/// that it is updated in place.
std::string progress_line(std::string_view what, double fraction, double eta_s, bool tty);

}  // namespace inhap::text
