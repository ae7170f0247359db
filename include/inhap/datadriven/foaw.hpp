// First-order adaptive windowing (FOAW) velocity estimation, best-fit variant
// (Janabi-Sharifi, Hayward and Chen, IEEE TCST 8(6), 2000), used for pdot in thesis sec. 4.4.1.
//
// Units: positions mm, velocities mm/s, time s.
//
// For each new sample y_k the window length n grows from 1 up to the cap; the slope b_n is the
// least-squares slope of the n+1 samples y_{k-n..k}; the window is accepted while every
// intermediate sample lies within the noise bound d of the line through y_k with that slope,
// |y_{k-j} - (y_k - b_n j T)| < d for j = 1..n-1 (strictly: a sample exactly on the band's
// edge, common when d is a multiple of the encoder quantum, is outside; deviations within 1e-12
// relative of d count as equal). The estimate is the slope of the longest accepted window. Each
// axis has its own window.
//
// Model/state split: FoawParams is immutable; FoawState is a fixed-size ring buffer (no heap);
// foaw_step() is servo-safe: no allocation, no exceptions, no I/O.
#pragma once

#include <array>
#include <cstddef>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

/// Largest window the state can hold (samples); FoawParams::max_window must not exceed it.
inline constexpr int kFoawMaxWindow = 64;

struct FoawParams {
  double dt_s = 1e-3;            ///< sample period, s
  int max_window = 16;           ///< window cap n_max (samples, 1..kFoawMaxWindow-1)
  double noise_bound_mm = 0.01;  ///< d: allowed deviation of a sample from the fitted line, mm
  /// Throws inhap::Error when dt_s <= 0, max_window out of range or noise_bound_mm < 0.
  void validate() const;
  /// The same filter for samples `period_s` apart: the window cap keeps its length in seconds
  /// (max_window x dt_s, at least one sample, at most kFoawMaxWindow - 1). A model trained on a
  /// 66 Hz recording and run in a 1 kHz servo loop otherwise takes each 1 ms step for 15 ms
  /// (velocities 15x too small), and the reverse 15x too large. A period within 1 % of dt_s, or
  /// one that is not a positive finite number, gives *this. Servo-safe.
  FoawParams at_period(double period_s) const noexcept;
};

struct FoawState {
  std::array<Vec3, kFoawMaxWindow> buffer{};  ///< ring buffer of positions, mm
  int head = -1;                              ///< index of the newest sample, -1 when empty
  int count = 0;                              ///< samples held (<= kFoawMaxWindow)
  Vec3 velocity = Vec3::Zero();               ///< last estimate, mm/s
  std::array<int, 3> window{};  ///< window length used per axis at the last step (samples)

  void reset() { *this = FoawState{}; }
};

/// Pushes position `p` (mm) and returns the velocity estimate (mm/s). The first sample gives
/// zero. A non-finite `p` resets the state and returns zero.
Vec3 foaw_step(const FoawParams& params, FoawState& state, const Vec3& p);

}  // namespace inhap::datadriven
