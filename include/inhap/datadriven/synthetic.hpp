// A synthetic soft planar object with a known force law, for tests, benchmarks and demos of the
// data-driven force model when no recording is at hand. Not the virtual lab (which simulates a
// device): just a closed-form f(p, pdot, q) and a proxy that slides on a Coulomb cone.
//
// Units: mm, mm/s, N, s. The undeformed surface is the plane z = 0 for the probe centre; depth
// d = max(0, -p_z). Force law:
//   k(x, y) = k0 + k1 exp(-|(x, y) - blob|^2 / (2 sigma^2))        (an inclusion), N/mm^e
//   f_z = max(0, k d^e (1 + c ddot)),  ddot = -pdot_z                (Hunt-Crossley)
//   f_xy = kt k (q_xy - p_xy), |f_xy| <= mu f_z (the proxy q slides, radial return)
// The probe follows a free-exploration-like path: smooth moves between random waypoints over
// the area, each with a random depth (some above the surface), so pushes, deep pushes and
// slides all occur.
#pragma once

#include <cstddef>
#include <cstdint>

#include "inhap/core/csv.hpp"
#include "inhap/core/types.hpp"

namespace inhap::datadriven {

struct SyntheticObject {
  double k0 = 0.35, k1 = 0.45;                       ///< N/mm^e
  double blob_x = 10, blob_y = -5, blob_sigma = 12;  ///< mm
  double exponent = 1.5;
  double damping = 0.004;  ///< c, s/mm
  double kt = 0.5;         ///< tangential stiffness relative to k, 1/mm^(e-1)
  double mu = 1.2;         ///< friction coefficient

  double stiffness(double x, double y) const;
  /// Force for probe p, velocity v and proxy q (already on the friction cone), N.
  Vec3 force(const Vec3& p, const Vec3& v, const Vec3& q) const;
  /// Proxy update: q_xy follows p_xy onto the friction cone (radial return); q_z = 0.
  Vec3 update_proxy(const Vec3& p, const Vec3& q_prev, bool was_contact) const;
};

struct SyntheticParams {
  std::size_t samples = 65000;
  std::uint64_t seed = 1;
  double dt = 1e-3;                           ///< s
  double quantum = 0.01;                      ///< encoder quantisation of the recorded p, mm
  double noise = 0.02;                        ///< force-sensor noise (standard deviation), N
  double max_depth = 4.0;                     ///< mm
  double extent = 30.0;                       ///< half-width of the explored square, mm
  double min_move_s = 0.4, max_move_s = 1.5;  ///< duration of one move between waypoints, s
};

/// A recording t,px,py,pz,fx,fy,fz with extra columns qx,qy,qz (true proxy), contact (0/1) and
/// tfx,tfy,tfz (noise-free force).
Recording synthetic_recording(const SyntheticParams& params, const SyntheticObject& object = {});

}  // namespace inhap::datadriven
