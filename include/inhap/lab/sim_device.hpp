// Virtual lab: a simulated 3-DOF impedance haptic device (PHANToM-like) with a force sensor in
// the probe, touching one soft object. Implements inhap::Device.
//
// Units: positions mm, velocities mm/s, forces N, masses kg, time s.
//
// Physics (semi-implicit Euler, `substeps` per 1 kHz servo tick, 20 -> 20 kHz):
//   (m_dev + m_hand) dv/dt = f_motor + f_contact + f_hand - b v - f_c sign(v)
// f_motor: the commanded force (zero-order hold over the tick), saturated to max_force_n by
// vector norm; b v: viscous joint friction; f_c: Coulomb joint friction (isotropic, solved
// implicitly so the probe sticks when the other forces cannot overcome it). The device is
// gravity-balanced (counterweights), so only the force sensor sees gravity.
// f_hand: an attached simulated hand is an impedance pulling the probe toward the operator's
// desired point: K_h (x_d - x) + B_h (xdot_d - v); x_d is interpolated linearly over the tick.
//
// Readings at each tick: position() = probe centre quantised to the encoder resolution;
// force_sensor() = f_contact + noise (Gaussian, per axis) + m_tool g - m_tool a (each
// switchable), a = mean probe acceleration over the tick (sensor anti-aliasing).
// DeviceInfo exports tool mass, gravity and probe radius so compensation can undo them.
#pragma once

#include <cstdint>
#include <memory>

#include "inhap/core/device.hpp"
#include "inhap/core/random.hpp"
#include "inhap/lab/physics.hpp"
#include "inhap/lab/soft_contact.hpp"

namespace inhap::lab {

enum class ProbeKind { kSphere, kTip };

struct ProbeSpec {
  ProbeKind kind = ProbeKind::kSphere;
  double radius_mm = 8.0;  ///< 8 mm sphere (thesis ch. 4); 0 for the sharp tip (ch. 3)
  static ProbeSpec sphere(double radius_mm = 8.0) { return {ProbeKind::kSphere, radius_mm}; }
  static ProbeSpec tip() { return {ProbeKind::kTip, 0.0}; }
};

struct DeviceParams {
  double mass_kg = 0.075;              ///< apparent mass at the tip, kg
  double viscous_n_s_per_mm = 0.0005;  ///< viscous joint friction b, N s/mm
  double coulomb_n = 0.04;             ///< Coulomb (backdrive) friction f_c, N
  int substeps = 20;                   ///< physics substeps per servo tick (>= 10)
  double servo_rate_hz = 1000.0;
  double encoder_resolution_mm = 0.01;
  double max_force_n = 6.2;       ///< continuous force saturation, N
  double tool_mass_kg = 0.01;     ///< probe mass beyond the sensor, kg
  double sensor_noise_n = 0.005;  ///< sigma per axis, N
  bool noise = true;              ///< sensor noise in the raw reading
  bool gravity = true;            ///< tool weight in the raw reading
  bool inertia = true;            ///< tool inertia in the raw reading
  Vec3 gravity_mm_s2{0, 0, -9810.0};
  ProbeSpec probe;
  std::uint64_t seed = 1;  ///< sensor-noise stream
  /// Contact physics: builtin (soft_contact.hpp) or mujoco (physics.hpp, docs/lab-mujoco.md;
  /// one MuJoCo step per physics substep).
  Physics physics = Physics::kBuiltin;
  MujocoParams mujoco;  ///< settings of the MuJoCo backend
};

/// Simulated operator hand holding the stylus (above the force sensor).
struct HandParams {
  double stiffness_n_per_mm = 0.6;  ///< K_h, human arm/hand stiffness 0.3-1 N/mm
  double damping_n_s_per_mm = 0.012;
  double mass_kg = 0.1;  ///< hand mass moving with the stylus, kg
};

/// Ground truth of the device at the current tick (noise-free, unquantised); the contact's
/// truth (proxy, noise-free force, episode) is SimDevice::contact().
struct DeviceTruth {
  double time = 0;
  Vec3 position = Vec3::Zero();      ///< probe centre, mm
  Vec3 velocity = Vec3::Zero();      ///< mm/s
  Vec3 acceleration = Vec3::Zero();  ///< mean over the last tick, mm/s^2
  Vec3 motor_force = Vec3::Zero();   ///< saturated command output during the last tick, N
  Vec3 hand_force = Vec3::Zero();    ///< at the end of the last tick, N
};

class MujocoContact;

class SimDevice final : public Device {
 public:
  /// Throws inhap::Error on bad parameters, or when params.physics is mujoco and this build has
  /// no MuJoCo or the shape cannot be represented there.
  SimDevice(SoftObject object, DeviceParams params = {});
  ~SimDevice() override;
  SimDevice(const SimDevice&) = delete;
  SimDevice& operator=(const SimDevice&) = delete;

  // --- inhap::Device ---
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return static_cast<double>(ticks_) / params_.servo_rate_hz; }
  Vec3 position() const override { return encoder_; }
  Vec3 force_sensor() const override { return sensor_; }
  void command_force(const Vec3& force) override;
  void tick() override;

  // --- lab extras ---
  const SoftObject& object() const { return object_; }
  const DeviceParams& params() const { return params_; }
  double probe_radius() const { return params_.probe.radius_mm; }
  long ticks() const { return ticks_; }

  /// Teleports the probe (velocity zero, contact cleared, sensor re-read); time continues.
  void place(const Vec3& position);
  void attach_hand(const HandParams& hand);
  void detach_hand();
  bool hand_attached() const { return hand_attached_; }
  const HandParams& hand() const { return hand_; }
  /// Where the hand wants the probe at the end of the coming tick (mm).
  void set_hand_target(const Vec3& target);

  const DeviceTruth& truth() const { return truth_; }
  const ContactState& contact() const { return contact_; }

 private:
  void substep(double dt, const Vec3& target, const Vec3& target_vel);
  void read_sensor();

  SoftObject object_;
  DeviceParams params_;
  std::unique_ptr<MujocoContact> mujoco_;  ///< set when params_.physics == Physics::kMujoco
  DeviceInfo info_;
  Rng rng_;
  long ticks_ = 0;
  Vec3 x_ = Vec3::Zero(), v_ = Vec3::Zero();
  Vec3 command_ = Vec3::Zero();
  Vec3 contact_force_ = Vec3::Zero();
  ContactState contact_;
  bool hand_attached_ = false;
  HandParams hand_;
  Vec3 hand_from_ = Vec3::Zero(), hand_to_ = Vec3::Zero();
  Vec3 encoder_ = Vec3::Zero(), sensor_ = Vec3::Zero();
  DeviceTruth truth_;
};

}  // namespace inhap::lab
