// A continuous-palpation recording with a known answer, as a robot rig logs it: the probe
// centre slides along a raster over a tilted plane while its depth follows a sinusoid, logged
// at `rate_hz` with jittered time stamps. Force: f_n = k(u, v) d^exponent along the plane's normal
// and Coulomb friction mu f_n against the sliding direction. Units: mm, N, s.
#pragma once

#include <cmath>
#include <numbers>

#include "inhap/core/csv.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/surface_frame.hpp"

namespace inhap::test {

struct PalpationRig {
  Vec3 normal = Vec3(0.1, -0.3, 1.0).normalized();  ///< outward normal of the plane
  Vec3 point = Vec3(5.0, -3.0, -120.0);             ///< a point of the probe-centre plane, mm
  double mu = 0.3;
  double k = 1.0;            ///< N/mm away from the inclusion
  double k_inclusion = 2.0;  ///< N/mm at the centre of the stiffer inclusion
  /// f_n = k d^exponent (1: a linear spring; 1.5: Hertz), k in N/mm^exponent.
  double exponent = 1.0;
  double damping = 0.0;  ///< Hunt-Crossley: f_n x (1 + damping x depth rate), s/mm
  double speed = 10.0;   ///< sliding speed, mm/s
  double width = 30.0, rows = 6, row_step = 4.0;  ///< raster, mm
  double depth_min = 0.2, depth_max = 2.5, palpation_hz = 2.0;
  double rate_hz = 66.0, jitter = 0.2;  ///< logging rate, +- share of its period
  double noise_n = 0.01;
  std::uint64_t seed = 1;

  SurfaceFrame frame() const { return surface_frame(normal); }
  double stiffness(double u, double v) const {
    const double r2 = (u - 0.5 * width) * (u - 0.5 * width) + (v - 8.0) * (v - 8.0);
    return k + (k_inclusion - k) * std::exp(-r2 / (2 * 4.0 * 4.0));
  }
  /// Plane coordinates (u, v) and sliding direction (+-1 along u) at time t.
  void raster(double t, double& u, double& v, double& dir) const {
    const double sweep = width / speed;
    const double total = sweep * rows;
    const double tt = std::fmod(t, total);
    const int row = static_cast<int>(tt / sweep);
    const double s = tt - row * sweep;
    dir = row % 2 == 0 ? 1.0 : -1.0;
    u = dir > 0 ? s * speed : width - s * speed;
    v = row * row_step;
  }
  double depth(double t) const {
    return depth_min + (depth_max - depth_min) * 0.5 *
                           (1.0 - std::cos(2 * std::numbers::pi * palpation_hz * t));
  }

  Recording record(double seconds) const {
    Recording rec;
    Rng rng(seed);
    const SurfaceFrame fr = frame();
    const double period = 1.0 / rate_hz;
    for (long i = 0;; ++i) {
      const double t = 3.25 + (static_cast<double>(i) + jitter * (2 * rng.uniform() - 1)) * period;
      if (t > 3.25 + seconds) break;
      double u, v, dir;
      raster(t, u, v, dir);
      const double d = depth(t);
      const Vec3 p = point + u * fr.t0 + v * fr.t1 - d * fr.n;
      const double rate = (depth_max - depth_min) * std::numbers::pi * palpation_hz *
                          std::sin(2 * std::numbers::pi * palpation_hz * t);
      const double fn =
          stiffness(u, v) * std::pow(d, exponent) * std::max(0.0, 1.0 + damping * rate);
      const Vec3 f = fn * fr.n - mu * fn * dir * fr.t0 +
                     Vec3(rng.normal(), rng.normal(), rng.normal()) * noise_n;
      rec.t.push_back(t);
      rec.p.push_back(p);
      rec.f.push_back(f);
    }
    return rec;
  }
};

}  // namespace inhap::test
