// Order statistics of samples (any unit: the result has the unit of the values).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace inhap {

/// q-quantile (q in [0, 1], clamped) with linear interpolation between order statistics
/// (type 7 of Hyndman & Fan: the default of R and NumPy); NaN for no values.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double h = std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// Median (mean of the two middle values for an even count); `if_empty` for no values.
inline double median(std::vector<double> v,
                     double if_empty = std::numeric_limits<double>::quiet_NaN()) {
  return v.empty() ? if_empty : quantile(std::move(v), 0.5);
}

}  // namespace inhap
