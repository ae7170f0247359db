#include "operator_common.hpp"

#include <fmt/format.h>

#include "inhap/core/error.hpp"

namespace inhap::lab::detail {

Tremor::Tremor(Rng& rng) {
  for (int k = 0; k < 3; ++k) {
    amp_fast_[k] = rng.uniform(0.015, 0.04);
    f_fast_[k] = rng.uniform(8.0, 12.0);
    ph_fast_[k] = rng.uniform(0, 2 * M_PI);
    amp_slow_[k] = rng.uniform(0.1, 0.4);
    f_slow_[k] = rng.uniform(0.2, 0.6);
    ph_slow_[k] = rng.uniform(0, 2 * M_PI);
  }
}

Vec3 Tremor::at(double t) const {
  const double fade = smoothstep((t - t0_) / 0.5);
  if (fade <= 0) return Vec3::Zero();
  Vec3 out;
  for (int k = 0; k < 3; ++k)
    out[k] = amp_fast_[k] * std::sin(2 * M_PI * f_fast_[k] * t + ph_fast_[k]) +
             amp_slow_[k] * std::sin(2 * M_PI * f_slow_[k] * t + ph_slow_[k]);
  return fade * out;
}

Perception::Perception(double delay_s, double rate_hz)
    : buf_(static_cast<std::size_t>(std::max(1.0, std::round(delay_s * rate_hz))) + 1, 0.0) {}

void Perception::push(double normal_force) {
  head_ = (head_ + 1) % buf_.size();
  buf_[head_] = normal_force;
}

void Path::reset(const Vec3& start) {
  pts_.assign(1, start);
  ends_.clear();
}

void Path::add(const Vec3& to, double peak_speed, double min_s) {
  const double dist = (to - pts_.back()).norm();
  if (dist < 1e-9) return;
  const double t = std::max(min_s, 1.875 * dist / peak_speed);  // min-jerk peak = 1.875 mean
  ends_.push_back(duration() + t);
  pts_.push_back(to);
}

Vec3 Path::at(double tau) const {
  for (std::size_t i = 0; i < ends_.size(); ++i)
    if (tau < ends_[i]) {
      const double t0 = i ? ends_[i - 1] : 0.0;
      return pts_[i] + min_jerk((tau - t0) / (ends_[i] - t0)) * (pts_[i + 1] - pts_[i]);
    }
  return pts_.back();
}

double safe_height(const SoftObject& object, double r, double margin) {
  const Box3 b = object.shape().bounds();
  return (b.empty() ? 0.0 : b.max.z()) + r + margin;
}

Path over_path(const SoftObject& object, double r, const Vec3& from, const Vec3& to,
               double peak_speed) {
  Path p;
  p.reset(from);
  if (clear_segment(object, r, from, to)) {
    p.add(to, peak_speed);
    return p;
  }
  const double z = std::max({safe_height(object, r), from.z(), to.z()});
  p.add(Vec3(from.x(), from.y(), z), peak_speed);
  p.add(Vec3(to.x(), to.y(), z), peak_speed);
  p.add(to, peak_speed);
  return p;
}

bool clear_segment(const SoftObject& object, double r, const Vec3& a, const Vec3& b) {
  const int n = 1 + static_cast<int>((b - a).norm() / 0.5);
  for (int i = 0; i <= n; ++i)
    if (object.query(a + (double(i) / n) * (b - a)).distance <= r) return false;
  return true;
}

HandParams random_hand(Rng& rng, const DeviceParams& device) {
  HandParams h;
  h.stiffness_n_per_mm = rng.uniform(0.4, 0.8);
  h.mass_kg = 0.1;
  const double zeta = rng.uniform(0.6, 0.9);
  const double m = device.mass_kg + h.mass_kg;                                 // kg
  const double b_si = 2.0 * zeta * std::sqrt(h.stiffness_n_per_mm * 1e3 * m);  // N s/m
  h.damping_n_s_per_mm = b_si * 1e-3;
  return h;
}

std::optional<SurfaceSpot> spot_at(const SoftObject& object, double probe_radius, const Vec2& xy) {
  const auto c = object.shape().drop(xy.x(), xy.y(), probe_radius);
  if (!c) return std::nullopt;
  return SurfaceSpot{*c, object.query(*c).normal};
}

Vec2 random_in_region(Rng& rng, const Region& region, double shrink) {
  const double r = region.radius * shrink * std::sqrt(rng.uniform());
  const double a = rng.uniform(0, 2 * M_PI);
  return region.center + r * Vec2(std::cos(a), std::sin(a));
}

Vec3 rest_point(const Scene& scene, double probe_radius, double clearance) {
  const auto s = spot_at(scene.object, probe_radius, scene.region.center);
  if (s) return s->center + Vec3(0, 0, clearance);
  const Box3 b = scene.object.shape().bounds();
  return Vec3(scene.region.center.x(), scene.region.center.y(),
              (b.empty() ? 0.0 : b.max.z()) + probe_radius + clearance);
}

}  // namespace inhap::lab::detail
