// Small meshes with known geometry for the renderer tests. Units: mm, N/mm.
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "inhap/geometry/trimesh.hpp"

namespace inhap::test {

/// Regular grid over [x0, x0 + nx*h] x [y0, y0 + ny*h], z = height(x, y), two triangles per
/// cell, counter-clockwise seen from +z; `stiffness` vertex property from k(x, y).
inline TriMesh grid_mesh(int nx, int ny, double h, double x0, double y0,
                         const std::function<double(double, double)>& height,
                         const std::function<double(double, double)>& k) {
  TriMesh m;
  std::vector<double> ks;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + i * h, y = y0 + j * h;
      m.positions.emplace_back(x, y, height(x, y));
      ks.push_back(k(x, y));
    }
  auto id = [nx](int i, int j) { return std::int32_t(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.set_property("stiffness", std::move(ks));
  m.compute_normals();
  return m;
}

inline TriMesh flat_plane(int nx, int ny, double h, double x0, double y0, double k = 1.0) {
  return grid_mesh(
      nx, ny, h, x0, y0, [](double, double) { return 0.0; }, [k](double, double) { return k; });
}

/// Icosphere (subdivided icosahedron, vertices projected onto the sphere), outward normals.
inline TriMesh icosphere(double radius, int subdivisions, const Vec3& centre = Vec3::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Tri> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = int(v.size() - 1);
    };
    std::vector<Tri> g;
    for (const Tri& tri : f) {
      int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
  TriMesh m;
  for (const auto& p : v) m.positions.push_back(centre + radius * p);
  m.triangles = f;
  m.compute_normals();
  return m;
}

/// Axis-aligned closed box [lo, hi] with outward normals, each face split n x n times.
inline TriMesh closed_box(const Vec3& lo, const Vec3& hi, int n = 1) {
  TriMesh m;
  // Each face: origin corner, two edge vectors u, v with u x v pointing outwards.
  const Vec3 d = hi - lo;
  struct Face {
    Vec3 o, u, v;
  };
  const Face faces[6] = {
      {lo, Vec3(0, d.y(), 0), Vec3(d.x(), 0, 0)},                             // z = lo, -z
      {Vec3(lo.x(), lo.y(), hi.z()), Vec3(d.x(), 0, 0), Vec3(0, d.y(), 0)},   // z = hi, +z
      {lo, Vec3(d.x(), 0, 0), Vec3(0, 0, d.z())},                             // y = lo, -y
      {Vec3(lo.x(), hi.y(), lo.z()), Vec3(0, 0, d.z()), Vec3(d.x(), 0, 0)},   // y = hi, +y
      {lo, Vec3(0, 0, d.z()), Vec3(0, d.y(), 0)},                             // x = lo, -x
      {Vec3(hi.x(), lo.y(), lo.z()), Vec3(0, d.y(), 0), Vec3(0, 0, d.z())}};  // x = hi, +x
  std::map<std::tuple<long, long, long>, int> ids;  // weld shared vertices
  auto vid = [&](const Vec3& p) {
    auto key = std::make_tuple(std::lround(p.x() * 1e6), std::lround(p.y() * 1e6),
                               std::lround(p.z() * 1e6));
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    m.positions.push_back(p);
    return ids[key] = int(m.positions.size() - 1);
  };
  for (const Face& fc : faces)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        auto P = [&](int a, int b) {
          return vid(fc.o + (double(a) / n) * fc.u + (double(b) / n) * fc.v);
        };
        int a = P(i, j), b = P(i + 1, j), c = P(i + 1, j + 1), e = P(i, j + 1);
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, e});
      }
  m.compute_normals();
  return m;
}

/// Inside of a box corner: walls x = 0, y = 0, z = 0 over [0, size]^2, the free space is the
/// positive octant (normals point into it); each wall split n x n.
inline TriMesh concave_corner(double size, int n) {
  TriMesh m;
  std::map<std::tuple<long, long, long>, int> ids;
  auto vid = [&](const Vec3& p) {
    auto key = std::make_tuple(std::lround(p.x() * 1e6), std::lround(p.y() * 1e6),
                               std::lround(p.z() * 1e6));
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    m.positions.push_back(p);
    return ids[key] = int(m.positions.size() - 1);
  };
  // (u, v) with u x v = wall normal: z-wall: x, y; x-wall: y, z; y-wall: z, x.
  const Vec3 axes[3][2] = {{Vec3::UnitX(), Vec3::UnitY()},
                           {Vec3::UnitY(), Vec3::UnitZ()},
                           {Vec3::UnitZ(), Vec3::UnitX()}};
  for (const auto& uv : axes)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        auto P = [&](int a, int b) {
          return vid(size * ((double(a) / n) * uv[0] + (double(b) / n) * uv[1]));
        };
        int a = P(i, j), b = P(i + 1, j), c = P(i + 1, j + 1), e = P(i, j + 1);
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, e});
      }
  m.compute_normals();
  return m;
}

}  // namespace inhap::test
