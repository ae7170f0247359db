// The tick-based haptic device interface every closed-loop procedure uses (palpation,
// controllers, servo rendering, experiments). The virtual lab's simulated device implements it;
// so does an adapter around a real device loop (see docs/devices.md for CHAI3D and OpenHaptics).
//
// Units: positions mm, forces N, time s, masses kg, accelerations mm/s^2.
// One tick = one servo period (1 ms at 1 kHz). Within a tick the caller reads position() and
// force_sensor(), calls command_force() at most once, then tick() advances the device.
#pragma once

#include <string>

#include "inhap/core/types.hpp"

namespace inhap {

/// The force limit of the device profile inhap renders for (PHANToM Premium 1.5, continuous),
/// N. Rendered forces (data-driven model, CBA, TCA-MESH) never exceed it: a model file, a
/// rendering parameter or a flag may lower the limit, never raise it.
inline constexpr double kDeviceForceLimitN = 6.2;
/// Hard ceiling for the force limit of any device profile (DeviceInfo::max_force_n, a simulated
/// device's saturation), N. No file or flag raises a limit past it.
inline constexpr double kForceCeilingN = 40.0;
/// The clamp a renderer applies: `requested` (a model's or a flag's limit) capped by the device
/// profile's limit; a non-finite or non-positive request gets the device's limit.
constexpr double effective_force_limit(double requested, double device_limit = kDeviceForceLimitN) {
  const double dev =
      device_limit > 0 && device_limit <= kForceCeilingN ? device_limit : kDeviceForceLimitN;
  return requested > 0 && requested <= dev ? requested : dev;
}

/// What a compensation or control algorithm needs to know about the device and its tool.
struct DeviceInfo {
  std::string name = "device";
  double servo_rate_hz = 1000.0;
  double max_force_n =
      kDeviceForceLimitN;             ///< output saturation (continuous), N (<= kForceCeilingN)
  double tool_mass_kg = 0.0;          ///< mass of the tool beyond the force sensor, kg
  Vec3 gravity_mm_s2{0, 0, -9810.0};  ///< gravity in the device frame, mm/s^2
  /// Orientation of the force sensor frame in the device frame (readings are rotated by this
  /// into the device frame before they are returned; identity for the simulated device).
  Mat3 sensor_rotation = Mat3::Identity();
  double probe_radius_mm = 0.0;  ///< 0 for a sharp tip; position() is the probe centre
};

class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceInfo& info() const = 0;
  /// Time of the current tick, s.
  virtual double time() const = 0;
  /// Probe (centre) position at the current tick, mm (encoder resolution).
  virtual Vec3 position() const = 0;
  /// Raw force-sensor reading at the current tick, N, in the device frame: the force the
  /// environment exerts on the probe plus, on a real device, the tool's weight and inertia.
  virtual Vec3 force_sensor() const = 0;
  /// Force to output during the coming tick, N (saturated by the device to max_force_n).
  virtual void command_force(const Vec3& force) = 0;
  /// Advances one servo period.
  virtual void tick() = 0;
  /// True while the device cannot be trusted (a bridge client went silent, an amplifier fault):
  /// a servo loop commands zero force then. A simulated device never faults.
  virtual bool faulted() const { return false; }
  /// True if tick() itself waits for the device's next sample (a bridge paced by the device's
  /// own servo callback); false if the caller paces the ticks with its clock.
  virtual bool self_paced() const { return false; }
};

/// A procedure driven tick by tick (palpation protocol, position controller, experiment).
/// step() gets the current readings and returns the force to command for this tick.
class TickProtocol {
 public:
  virtual ~TickProtocol() = default;
  virtual Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) = 0;
  virtual bool done() const = 0;
};

/// Runs a protocol on a device until it is done or max_ticks elapsed; returns ticks run.
inline long run_protocol(Device& device, TickProtocol& protocol, long max_ticks) {
  long n = 0;
  while (!protocol.done() && n < max_ticks) {
    device.command_force(protocol.step(device.time(), device.position(), device.force_sensor()));
    device.tick();
    ++n;
  }
  return n;
}

}  // namespace inhap
