// Private to the mesh readers: fan triangulation of a polygon given by vertex indices.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap::mesh_detail {

/// Drops consecutive repeats of a vertex (cyclically: "0 1 2 2" is the triangle 0 1 2), then
/// appends the fan (p0, p[i], p[i+1]) to `out`. Returns "" on success, otherwise what is wrong
/// ("expected at least 3 distinct vertices, got 2"). Indices must already be range-checked.
inline std::string fan_triangulate(std::vector<std::int32_t>& poly, std::vector<Tri>& out) {
  std::size_t m = 0;
  for (std::size_t i = 0; i < poly.size(); ++i)
    if (m == 0 || poly[i] != poly[m - 1]) poly[m++] = poly[i];
  while (m > 1 && poly[m - 1] == poly[0]) --m;
  if (m < 3) return fmt::format("expected at least 3 distinct vertices, got {}", m);
  for (std::size_t i = 1; i + 1 < m; ++i) {
    const Tri t{poly[0], poly[i], poly[i + 1]};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      return fmt::format("expected a simple polygon, got vertex {} twice",
                         t[0] == t[1] || t[0] == t[2] ? t[0] : t[1]);
    out.push_back(t);
  }
  return {};
}

}  // namespace inhap::mesh_detail
