// Force-sensor compensation (thesis 3.2.1): removes the tool's own weight and inertia from a
// raw force-sensor reading, leaving the contact force the environment exerts on the probe.
//
// Units: positions mm, forces N, masses kg, accelerations mm/s^2, time s.
//
// The sensor sits between the device and the tool (probe tip or sphere) of mass m beyond it.
// Newton on the tool gives the reading r = f_contact + m g - m a, hence
//
//     f_contact = R r - m g + m a        (m g and m a in N: kg * mm/s^2 * 1e-3)
//
// where R rotates sensor-frame readings into the device frame. inhap::Device::force_sensor()
// already returns device-frame readings (DeviceInfo::sensor_rotation is applied by the device
// adapter), so CompensatorConfig::from(DeviceInfo) leaves R = identity; set R only for logs
// written in the sensor frame.
//
// The acceleration a is estimated causally from the encoder position stream: a moving average
// of the last `smooth` positions (kills encoder quantisation), then a second difference with
// step `span` samples over the averaged track:
//
//     a(n) = (m(n) - 2 m(n - span) + m(n - 2 span)) / (span T)^2
//
// which is the acceleration about (smooth - 1) / 2 + span samples ago (about 8 ms with the
// defaults). With 0.01 mm encoder steps at 1 kHz the noise of m*a stays below 1 mN for a 10 g
// tool; the lag error is m * jerk * delay, a few mN for hand motion. Until enough samples have
// been seen, a = 0.
//
// The servo version (compensate_step) is allocation-free, exception-free and resets itself on
// non-finite input (and returns a zero force then), as the house rules require.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/types.hpp"

namespace inhap {

struct CompensatorConfig {
  double tool_mass_kg = 0.0;          ///< mass beyond the sensor, kg
  Vec3 gravity_mm_s2{0, 0, -9810.0};  ///< gravity in the device frame, mm/s^2
  Mat3 rotation = Mat3::Identity();   ///< sensor frame -> device frame (identity for Device)
  double sample_rate_hz = 1000.0;     ///< rate of the position/force stream, Hz
  bool gravity = true;                ///< remove the tool weight
  bool inertia = true;                ///< remove the tool inertia (needs the position stream)
  int smooth = 5;                     ///< moving-average length, samples (1..16)
  int span = 6;                       ///< second-difference step, samples (1..24)

  /// Tool mass, gravity and rate from a device (readings already in the device frame).
  static CompensatorConfig from(const DeviceInfo& info);
  /// Delay of the acceleration estimate, samples: (smooth - 1) / 2 + span.
  double delay_samples() const { return 0.5 * (smooth - 1) + span; }
};

/// Running state of the causal compensator (fixed size, no allocation).
struct CompensatorState {
  static constexpr int kRing = 64;
  std::array<Vec3, kRing> positions{};  ///< last raw positions
  std::array<Vec3, kRing> averages{};   ///< last moving averages
  long count = 0;                       ///< samples seen since the last reset
  Vec3 acceleration = Vec3::Zero();     ///< last estimate, mm/s^2
  void reset() {
    count = 0;
    acceleration.setZero();
  }
};

/// One servo step: returns the compensated contact force, N. Non-finite input -> zero force
/// and a state reset.
Vec3 compensate_step(const CompensatorConfig& config, CompensatorState& state, const Vec3& position,
                     const Vec3& raw_force);

/// Batch compensation of a whole stream. With `centered`, the acceleration estimate is taken
/// delay_samples() later so it is centred on each sample (zero lag, offline only); otherwise
/// the output equals compensate_step applied sample by sample.
std::vector<Vec3> compensate(const CompensatorConfig& config, std::span<const Vec3> positions,
                             std::span<const Vec3> raw_forces, bool centered = false);

/// Compensates a recording whose raw sensor reading is in extra columns rfx,rfy,rfz (the
/// virtual lab's and a real logger's layout): returns a copy with f replaced. Throws Error when
/// the raw columns are missing.
Recording compensate_recording(const CompensatorConfig& config, const Recording& rec,
                               bool centered = false);

}  // namespace inhap
