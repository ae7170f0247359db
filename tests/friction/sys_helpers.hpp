// Builds sliding-yield-surface models with known answers for the friction tests.
#pragma once

#include <cmath>
#include <functional>
#include <numbers>

#include "inhap/friction/sys_model.hpp"

namespace inhap::test {

/// Reference points `positions` (normal +z), levels f_N = 1, 3, 5 N, 8 directions. At point i
/// the contact is a linear spring k_n (normal) / k_t (tangential) with friction mu(i): the
/// elastic limit of direction k at level f_N is f_T = mu f_N, at depth f_N / k_n and tangential
/// displacement mu f_N / k_t.
inline friction::SysModel coulomb_sys(const std::vector<Vec3>& positions,
                                      const std::function<double(std::size_t)>& mu, double k_n,
                                      double k_t) {
  friction::SysModel m;
  m.f_normal_levels = {1.0, 3.0, 5.0};
  for (int k = 0; k < 8; ++k) m.angles.push_back(k * std::numbers::pi / 4);
  m.plateaus = {0.1, 0.6};
  for (std::size_t i = 0; i < positions.size(); ++i) {
    friction::SysPoint p;
    p.id = static_cast<int>(i);
    p.position = positions[i];
    p.normal = Vec3::UnitZ();
    for (double fn : m.f_normal_levels)
      for (int k = 0; k < 8; ++k) {
        friction::SysBorder b;
        b.f_normal = fn;
        b.direction = k;
        b.result.f_limit = mu(i) * fn;
        b.result.depth = fn / k_n;
        b.result.radius = mu(i) * fn / k_t;
        friction::BorderStep s;
        s.f_tangential = 0.1 * fn;
        s.depth = fn / k_n;
        s.radius = s.f_tangential / k_t;
        b.steps.push_back(s);
        b.result.labels.push_back(0);
        b.result.split = 1;
        p.borders.push_back(b);
      }
    m.points.push_back(p);
  }
  m.rebuild();
  return m;
}

inline std::vector<Vec3> grid_points(int nx, int ny, double spacing, double z = 0.0) {
  std::vector<Vec3> p;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j)
      p.emplace_back(spacing * (j - (nx - 1) / 2.0), spacing * (i - (ny - 1) / 2.0), z);
  return p;
}

}  // namespace inhap::test
