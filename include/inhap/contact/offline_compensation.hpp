// Offline (non-causal) compensation of a raw force-sensor stream for the tool's weight and
// inertia, self-calibrated from the recording itself (thesis sec. 3.2.1). Units: time s,
// positions mm, accelerations mm/s^2, forces N, mass kg.
//
// The sensor sits between the stylus and a tool of mass m; it reads
//   raw = f + m (g - a) = f + b - 1e-3 m a     (b = m g + sensor bias, constant in the frame
//                                                of a 3-DOF device whose sensor keeps its
//                                                orientation)
// where f is the contact force and a the probe acceleration (mm/s^2, hence 1e-3 for N). The
// acceleration is estimated from the position stream by a centred quadratic (Savitzky-Golay)
// fit, which has no lag. b and m are fitted by least squares on the free-motion samples, found
// by iteratively discarding samples whose residual is large (contact forces): no device
// parameters are needed, so any recording with raw columns works. The causal, parameter-based
// compensator for servo use lives in compensation.hpp.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {

/// Acceleration (mm/s^2) by a least-squares parabola over samples [i - h, i + h] (clamped at
/// the ends) around each sample.
std::vector<Vec3> estimate_acceleration(std::span<const double> t, std::span<const Vec3> p,
                                        std::size_t half_window);

struct OfflineCompensationOptions {
  std::size_t half_window = 8;  ///< acceleration fit half-width, samples
  std::size_t iterations = 6;   ///< robust refits
  double reject_sigmas = 4.0;   ///< free-motion residual cut (robust sigmas)
  double min_reject_n = 0.02;   ///< never cut residuals below this, N
};

struct OfflineCompensation {
  Vec3 offset = Vec3::Zero();  ///< b, N
  double mass_kg = 0;          ///< m, kg
  std::size_t free_samples = 0;
  double residual_rms = 0;  ///< of the free-motion samples after the fit, N
};

OfflineCompensation fit_offline_compensation(std::span<const double> t, std::span<const Vec3> p,
                                             std::span<const Vec3> raw,
                                             const OfflineCompensationOptions& options = {});

/// f = raw - b + 1e-3 m a.
std::vector<Vec3> apply_offline_compensation(std::span<const Vec3> raw,
                                             std::span<const Vec3> acceleration,
                                             const OfflineCompensation& c);

}  // namespace inhap
