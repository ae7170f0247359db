#include "inhap/contact/compensation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/error.hpp"

namespace inhap {

namespace {

constexpr double kKgMmS2ToN = 1e-3;  // kg * mm/s^2 -> N

int clamp_smooth(int s) {
  return std::clamp(s, 1, 16);
}
int clamp_span(int s) {
  return std::clamp(s, 1, 24);
}

}  // namespace

CompensatorConfig CompensatorConfig::from(const DeviceInfo& info) {
  CompensatorConfig c;
  c.tool_mass_kg = info.tool_mass_kg;
  c.gravity_mm_s2 = info.gravity_mm_s2;
  c.rotation = Mat3::Identity();  // Device readings are already in the device frame
  c.sample_rate_hz = info.servo_rate_hz;
  return c;
}

Vec3 compensate_step(const CompensatorConfig& config, CompensatorState& state, const Vec3& position,
                     const Vec3& raw_force) {
  if (!all_finite(position) || !all_finite(raw_force)) {
    state.reset();
    return Vec3::Zero();
  }
  const int smooth = clamp_smooth(config.smooth);
  const int span = clamp_span(config.span);
  constexpr int R = CompensatorState::kRing;
  const long n = state.count;
  const int i = static_cast<int>(n % R);
  state.positions[i] = position;
  if (n + 1 >= smooth) {
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < smooth; ++k) sum += state.positions[(i - k + R) % R];
    state.averages[i] = sum / smooth;
  }
  if (n + 1 >= smooth + 2 * span) {
    const double h = span / config.sample_rate_hz;
    const Vec3& m0 = state.averages[i];
    const Vec3& m1 = state.averages[(i - span + R) % R];
    const Vec3& m2 = state.averages[(i - 2 * span + R) % R];
    state.acceleration = (m0 - 2.0 * m1 + m2) / (h * h);
  } else {
    state.acceleration.setZero();
  }
  ++state.count;

  Vec3 f = config.rotation * raw_force;
  if (config.gravity) f -= config.tool_mass_kg * kKgMmS2ToN * config.gravity_mm_s2;
  if (config.inertia) f += config.tool_mass_kg * kKgMmS2ToN * state.acceleration;
  if (!all_finite(f)) {
    state.reset();
    return Vec3::Zero();
  }
  return f;
}

std::vector<Vec3> compensate(const CompensatorConfig& config, std::span<const Vec3> positions,
                             std::span<const Vec3> raw_forces, bool centered) {
  if (positions.size() != raw_forces.size())
    throw Error(fmt::format("compensate: {} positions but {} force samples", positions.size(),
                            raw_forces.size()));
  const std::size_t n = positions.size();
  std::vector<Vec3> out(n);
  CompensatorState state;
  if (!centered) {
    for (std::size_t k = 0; k < n; ++k)
      out[k] = compensate_step(config, state, positions[k], raw_forces[k]);
    return out;
  }
  // Causal estimates first, then shift them back by the estimator delay.
  std::vector<Vec3> acc(n);
  CompensatorConfig no_inertia = config;
  no_inertia.inertia = false;
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = compensate_step(no_inertia, state, positions[k], raw_forces[k]);
    acc[k] = state.acceleration;
  }
  if (!config.inertia || n == 0) return out;
  const double delay = 0.5 * (clamp_smooth(config.smooth) - 1) + clamp_span(config.span);
  const auto lo = static_cast<std::size_t>(std::floor(delay));
  const double frac = delay - std::floor(delay);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = std::min(k + lo, n - 1), b = std::min(k + lo + 1, n - 1);
    const Vec3 ak = (1.0 - frac) * acc[a] + frac * acc[b];
    out[k] += config.tool_mass_kg * kKgMmS2ToN * ak;
  }
  return out;
}

Recording compensate_recording(const CompensatorConfig& config, const Recording& rec,
                               bool centered) {
  const auto* rx = rec.find_extra("rfx");
  const auto* ry = rec.find_extra("rfy");
  const auto* rz = rec.find_extra("rfz");
  if (!rx || !ry || !rz)
    throw Error("compensate_recording: expected raw sensor columns rfx,rfy,rfz in the recording");
  std::vector<Vec3> raw(rec.size());
  for (std::size_t k = 0; k < rec.size(); ++k) raw[k] = Vec3((*rx)[k], (*ry)[k], (*rz)[k]);
  Recording out = rec;
  out.f = compensate(config, rec.p, raw, centered);
  return out;
}

}  // namespace inhap
