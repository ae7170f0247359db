// Test helpers for the surface module: sphere samplings and simple meshes. Units: mm.
#pragma once

#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::test {

/// n points exactly on the sphere (centre c, radius r), Fibonacci spiral (near-uniform).
inline std::vector<Vec3> fibonacci_sphere(int n, double r, const Vec3& c = Vec3::Zero()) {
  std::vector<Vec3> pts;
  const double ga = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1.0 - z * z);
    pts.push_back(c + r * Vec3(s * std::cos(ga * i), s * std::sin(ga * i), z));
  }
  return pts;
}

/// n uniformly random directions on the sphere plus isotropic Gaussian noise sigma.
inline std::vector<Vec3> random_sphere(int n, double r, double sigma, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    const Vec3 d = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    pts.push_back(r * d + sigma * Vec3(rng.normal(), rng.normal(), rng.normal()));
  }
  return pts;
}

/// Signed volume enclosed by a closed mesh (positive when oriented outward), mm^3.
inline double signed_volume(const TriMesh& m) {
  double v = 0;
  for (const Tri& t : m.triangles)
    v += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  return v;
}

/// Largest | |v - c| - r | over the vertices, mm.
inline double max_radial_error(const TriMesh& m, double r, const Vec3& c = Vec3::Zero()) {
  double e = 0;
  for (const Vec3& p : m.positions) e = std::max(e, std::abs((p - c).norm() - r));
  return e;
}

/// Subdivided icosahedron projected on the sphere of radius r (closed, outward).
inline TriMesh icosphere(int levels, double r) {
  TriMesh m;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  m.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::vector<Tri> next;
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));
      return mid[key] = static_cast<int>(m.positions.size() - 1);
    };
    for (const Tri& t : m.triangles) {
      const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = next;
  }
  for (Vec3& p : m.positions) p = r * p.normalized();
  m.compute_normals();
  return m;
}

}  // namespace inhap::test
