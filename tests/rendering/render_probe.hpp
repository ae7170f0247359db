// Idealised users for the renderer tests. Units: mm, N.
#pragma once

#include <cmath>

#include "inhap/rendering/renderer.hpp"

namespace inhap::test {

/// A perfectly transparent, force-controlled probe (the assumption of Lemma 1): at lateral
/// position (x, y) it finds the height z at which the renderer outputs the normal force
/// `force_n` along +z in this tick, then commits that tick. The force is affine in z (one tick,
/// same triangle), so two trial ticks on copies of the state give z exactly (secant).
/// Returns the committed z.
inline double press_exact(const rendering::Model& m, rendering::State& st, double x, double y,
                          double force_n, double z_guess, rendering::Algorithm alg) {
  const double dz = 1e-3;
  rendering::State a = st, b = st;
  const double fa = rendering::step(m, a, Vec3(x, y, z_guess), alg).z();
  const double fb = rendering::step(m, b, Vec3(x, y, z_guess - dz), alg).z();
  double z = z_guess;
  if (std::abs(fb - fa) > 1e-12) z = z_guess - dz * (force_n - fa) / (fb - fa);
  rendering::step(m, st, Vec3(x, y, z), alg);
  return z;
}

}  // namespace inhap::test
