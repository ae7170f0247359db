// Guards for JSON files inhap writes and reads (nlohmann::json or ordered_json, header only so
// core does not depend on the JSON library).
//
// - require_finite_json: a writer calls it before writing; nlohmann writes NaN and infinity as
//   `null`, which inhap cannot read back, so a non-finite number is an error naming the file and
//   the JSON path instead.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "inhap/core/error.hpp"

namespace inhap {

namespace detail {
// `where` collects the path from the leaf up, one segment per level (joined by the caller).
template <class Json>
const char* find_non_finite(const Json& j, std::vector<std::string>& where) {
  if (j.is_number_float()) {
    const double v = j.template get<double>();
    return std::isfinite(v) ? nullptr : (std::isnan(v) ? "NaN" : "an infinity");
  }
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      if (const char* bad = find_non_finite(j[i], where)) {
        where.push_back(std::string("[").append(std::to_string(i)).append("]"));
        return bad;
      }
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (const char* bad = find_non_finite(it.value(), where)) {
        where.push_back(std::string(".").append(it.key()));
        return bad;
      }
  }
  return nullptr;
}
}  // namespace detail

/// Throws inhap::Error "FILE: refusing to write NaN at $.a.b[3] ..." when `j` holds a
/// non-finite number anywhere.
template <class Json>
void require_finite_json(const Json& j, const std::string& file) {
  std::vector<std::string> where;
  if (const char* bad = detail::find_non_finite(j, where)) {
    std::string msg = file;
    msg.append(": refusing to write ").append(bad).append(" at $");
    for (auto it = where.rbegin(); it != where.rend(); ++it) msg.append(*it);
    msg.append(" (a result is not finite: an input value is out of range?)");
    throw Error(msg);
  }
}

}  // namespace inhap
