// The benchmark map of the renderer benchmarks (bench_render, bench_loop): a 100 mm square
// heightmap with 40 Gaussian bumps 1-4 mm high and a smooth stiffness map in [0.1, 1] N/mm;
// n x n vertices (257: 131,072 triangles at 0.39 mm). Units: mm, N/mm.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace inhap::bench {

inline TriMesh bumpy_map(int n, std::uint64_t seed) {
  const double spacing = 100.0 / (n - 1);
  Grid h(n, n), k(n, n);
  Rng rng(seed);
  struct Blob {
    double x, y, r, a;
  };
  std::vector<Blob> bumps, soft;
  for (int i = 0; i < 40; ++i)
    bumps.push_back(
        {rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(2, 8), rng.uniform(1, 4)});
  for (int i = 0; i < 25; ++i)
    soft.push_back(
        {rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(4, 12), rng.uniform(0.3, 1)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i * spacing, y = j * spacing;
      double z = 0, s = 0;
      for (const auto& b : bumps)
        z += b.a * std::exp(-((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y)) / (2 * b.r * b.r));
      for (const auto& b : soft)
        s += b.a * std::exp(-((x - b.x) * (x - b.x) + (y - b.y) * (y - b.y)) / (2 * b.r * b.r));
      h.at(i, j) = z;
      k.at(i, j) = 1.0 - 0.9 * std::min(1.0, s);  // 0.1 .. 1 N/mm
    }
  return grid_to_mesh(h, spacing, &k);
}

/// The force-tracking hand of the renderer benchmarks (as in rendering::simulate_stroke): a
/// Lissajous path over the map at about `speed` mm/s, pressing toward 1.5 N with a 30 ms time
/// constant. next() gives the position after one 1 ms tick given the last force and stiffness.
struct StrokeHand {
  double speed = 50;  ///< mean stroke speed, mm/s
  double t = 0;       ///< s
  Vec3 p{50, 50, 10};
  Vec3 next(bool contact, const Vec3& force, double k) {
    const double dt = 1e-3, F = 1.5, tau = 0.03, w = speed / 45.0;
    t += dt;
    const double vz = contact ? std::clamp((force.norm() - F) / (k * tau), -100.0, 100.0) : -20.0;
    p = Vec3(50 + 45 * std::sin(w * t), 50 + 45 * std::sin(1.37 * w * t + 0.5), p.z() + vz * dt);
    return p;
  }
};

}  // namespace inhap::bench
