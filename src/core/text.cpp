#include "inhap/core/text.hpp"

#include <fmt/format.h>

namespace inhap::text {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = word.size() / 2 + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

std::string progress_line(std::string_view what, double fraction, double eta_s, bool tty) {
  return fmt::format(
      "{}[{}] {:3.0f}%{}{}", tty ? "\r" : "", what, 100.0 * fraction,
      eta_s > 0 && fraction < 1.0 ? fmt::format(" (eta {:.0f} s)", eta_s) : std::string(),
      fraction >= 1.0 ? "\n" : "");
}

std::string one_line(std::string s, std::size_t max_len) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  if (s.size() > max_len) s = s.substr(0, max_len) + "...";
  return s;
}

}  // namespace inhap::text
