// Internal helpers shared by the simulated operators. Units: mm, N, s.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include "inhap/core/random.hpp"
#include "inhap/lab/operators.hpp"

namespace inhap::lab::detail {

/// Minimum-jerk interpolation weight for s in [0, 1].
inline double min_jerk(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s);
}
inline double smoothstep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}
/// Log-uniform draw in [lo, hi].
inline double log_uniform(Rng& rng, double lo, double hi) {
  return std::exp(rng.uniform(std::log(lo), std::log(hi)));
}

/// Physiological tremor (8-12 Hz, ~0.03 mm) plus slow postural drift (0.2-0.6 Hz, ~0.3 mm).
class Tremor {
 public:
  explicit Tremor(Rng& rng);
  /// Fades the tremor in over 0.5 s from `t0` (no jolt when the hand takes the stylus).
  void start(double t0) { t0_ = t0; }
  Vec3 at(double t) const;

 private:
  Vec3 amp_fast_, f_fast_, ph_fast_, amp_slow_, f_slow_, ph_slow_;
  double t0_ = 0;
};

/// A person's force perception: the normal contact force, delayed.
class Perception {
 public:
  Perception(double delay_s, double rate_hz);
  void push(double normal_force);
  double force() const { return buf_[(head_ + 1) % buf_.size()]; }  // oldest = delayed

 private:
  std::vector<double> buf_;
  std::size_t head_ = 0;
};

/// A hand path through waypoints, minimum-jerk on each leg (at rest at every waypoint).
class Path {
 public:
  void reset(const Vec3& start);
  /// Appends a leg to `to` with the given peak speed (mm/s), lasting at least `min_s`.
  void add(const Vec3& to, double peak_speed, double min_s = 0.1);
  Vec3 at(double tau) const;
  double duration() const { return ends_.empty() ? 0.0 : ends_.back(); }
  const Vec3& end() const { return pts_.back(); }

 private:
  std::vector<Vec3> pts_;
  std::vector<double> ends_;  // cumulative end time of each leg
};

/// Height (probe centre z) at which a probe of radius `r` clears the whole object by `margin`.
double safe_height(const SoftObject& object, double r, double margin = 10.0);
/// How a person moves between two points above an object: up to a clear height (if lower),
/// across, and down (the legs at `peak_speed`).
Path over_path(const SoftObject& object, double r, const Vec3& from, const Vec3& to,
               double peak_speed);
/// True when a probe of radius r moves straight from a to b without touching the object
/// (checked every 0.5 mm).
bool clear_segment(const SoftObject& object, double r, const Vec3& a, const Vec3& b);

/// Hand impedance typical of a person holding a stylus (stiffness 0.4-0.8 N/mm, damping ratio
/// 0.6-0.9 with device + hand mass).
HandParams random_hand(Rng& rng, const DeviceParams& device);

struct SurfaceSpot {
  Vec3 center;  ///< probe centre touching the surface from above, mm
  Vec3 normal;  ///< outward normal there
};
/// Probe-centre touch point straight above (x, y), if the probe hits the object there.
std::optional<SurfaceSpot> spot_at(const SoftObject& object, double probe_radius, const Vec2& xy);
/// Uniform point of the region's disk.
Vec2 random_in_region(Rng& rng, const Region& region, double shrink = 1.0);
/// Top of the object above the region centre (probe centre), for resting positions.
Vec3 rest_point(const Scene& scene, double probe_radius, double clearance);

}  // namespace inhap::lab::detail
