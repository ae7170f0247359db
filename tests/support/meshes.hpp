// Synthetic test meshes (header-only). Units: mm. All are deterministic; random_soup takes a seed.
//   make_grid_mesh  height field z = h(x, y) on an nx x ny vertex grid (open, normals up)
//   make_sphere     icosphere (closed, outward, 20 * 4^s triangles)
//   make_torus      torus around the z axis (closed, outward, 2 nu nv triangles)
//   random_soup     n unconnected random triangles (no shared vertices)
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::test {

/// nx x ny vertices at (i * spacing, j * spacing, height(x, y)), i in [0, nx), j in [0, ny);
/// vertex index j * nx + i. Each cell is split along its (i, j)-(i+1, j+1) diagonal into two
/// triangles, counter-clockwise seen from +z: 2 (nx - 1)(ny - 1) triangles. No height: flat z = 0.
inline TriMesh make_grid_mesh(int nx, int ny, double spacing,
                              const std::function<double(double, double)>& height = nullptr) {
  TriMesh m;
  m.positions.reserve(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = i * spacing, y = j * spacing;
      m.positions.emplace_back(x, y, height ? height(x, y) : 0.0);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const std::int32_t v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      m.triangles.push_back({v00, v10, v11});
      m.triangles.push_back({v00, v11, v01});
    }
  return m;
}

/// Icosphere centred at the origin: an icosahedron whose faces are split in four
/// `subdivisions` times, every vertex pushed onto the sphere of `radius`. Closed, shared
/// vertices, faces counter-clockwise seen from outside.
inline TriMesh make_sphere(double radius, int subdivisions) {
  TriMesh m;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  const double ico[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                             {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                             {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (const auto& v : ico) m.positions.push_back(Vec3(v[0], v[1], v[2]).normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> mid;
    auto midpoint = [&](std::int32_t a, std::int32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const auto id = static_cast<std::int32_t>(m.positions.size());
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      mid.emplace(key, id);
      return id;
    };
    std::vector<Tri> next;
    next.reserve(4 * m.triangles.size());
    for (const Tri& t : m.triangles) {
      const std::int32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                         ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  for (auto& p : m.positions) p *= radius;
  // Orient every face outwards (the table above is, this only guards against typos).
  for (Tri& t : m.triangles) {
    const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(t[1], t[2]);
  }
  return m;
}

/// Torus around the z axis, major radius R, tube radius r: vertex (i, j) at angles
/// u = 2 pi i / nu (around z), v = 2 pi j / nv (around the tube), index j * nu + i.
/// Closed (indices wrap), faces counter-clockwise seen from outside, nu * nv * 2 triangles.
inline TriMesh make_torus(double R, double r, int nu, int nv) {
  TriMesh m;
  const double two_pi = 2.0 * 3.14159265358979323846;
  m.positions.reserve(static_cast<std::size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = two_pi * i / nu, v = two_pi * j / nv;
      const double rho = R + r * std::cos(v);
      m.positions.emplace_back(rho * std::cos(u), rho * std::sin(u), r * std::sin(v));
    }
  m.triangles.reserve(2 * m.positions.size());
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
      const std::int32_t v00 = j * nu + i, v10 = j * nu + i1, v01 = j1 * nu + i, v11 = j1 * nu + i1;
      m.triangles.push_back({v00, v10, v11});  // d/du x d/dv points outwards
      m.triangles.push_back({v00, v11, v01});
    }
  return m;
}

/// n unconnected triangles: centres uniform in [0, 1]^3, each vertex the centre plus a
/// uniform offset in [-0.05, 0.05]^3 (so they overlap and intersect each other).
inline TriMesh random_soup(int n, std::uint64_t seed) {
  TriMesh m;
  Rng rng(seed);
  m.positions.reserve(3 * static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f) {
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = rng.uniform();  // one draw per statement: fixed order
    for (int k = 0; k < 3; ++k) {
      Vec3 p = c;
      for (int a = 0; a < 3; ++a) p[a] += rng.uniform(-0.05, 0.05);
      m.positions.push_back(p);
    }
    m.triangles.push_back({3 * f, 3 * f + 1, 3 * f + 2});
  }
  return m;
}

}  // namespace inhap::test
