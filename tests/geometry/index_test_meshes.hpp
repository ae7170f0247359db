// Shared by the MeshIndex tests: brute-force distances with the independent reference routine,
// and the hard test meshes (a bumpy height field, a soup with zero-area triangles, translated
// copies). Units: mm.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "geometry/reference_distance.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "support/meshes.hpp"

namespace inhap::test {

/// Squared distance from p to triangle f of m (reference routine).
inline double ref_d2(const TriMesh& m, std::size_t f, const Vec3& p) {
  const auto& t = m.triangles[f];
  return ref_distance2(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
}

/// Squared distance from p to the nearest triangle of m, over all of them.
inline double brute_force_d2(const TriMesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < m.num_triangles(); ++f) best = std::min(best, ref_d2(m, f, p));
  return best;
}

/// Height field with bumps and a slope (for make_grid_mesh).
inline double bumpy(double x, double y) {
  return 0.3 * std::sin(1.3 * x) * std::cos(0.9 * y) + 0.05 * x;
}

/// A random soup of n triangles with `degenerate` zero-area ones mixed in: repeated vertices
/// (every third) and collinear vertices.
inline TriMesh soup_with_degenerates(std::uint64_t seed, int n = 600, int degenerate = 150) {
  TriMesh m = random_soup(n, seed);
  Rng rng(seed + 1);
  for (int i = 0; i < degenerate; ++i) {
    const auto base = static_cast<std::int32_t>(m.positions.size());
    const Vec3 a(rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3 d = 0.05 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    m.positions.push_back(a);
    m.positions.push_back(a + d);
    m.positions.push_back(i % 3 == 0 ? a : a + rng.uniform(-2, 2) * d);  // repeated / collinear
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

/// m moved by t.
inline TriMesh translated(TriMesh m, const Vec3& t) {
  for (auto& p : m.positions) p += t;
  return m;
}

}  // namespace inhap::test
