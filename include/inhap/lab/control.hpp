// Virtual lab: device-side controllers as TickProtocols (usable on any inhap::Device, real or
// simulated) and the palpation executor that runs a protocol on the simulated device with the
// hand detached, as the thesis' computer-controlled palpation (4.3.2) does.
//
// Units: positions mm, forces N, time s; gains kp N/mm, ki N/(mm s), kd N s/mm.
// Sign convention: command_force() is the force the device applies to the probe; pressing an
// object lying below the probe means a command with negative z. The force sensor reads the
// force the object exerts on the probe (positive z while pressing down on a top surface).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "inhap/contact/compensation.hpp"
#include "inhap/core/device.hpp"
#include "inhap/lab/recorder.hpp"

namespace inhap::lab {

struct PidGains {
  double kp = 0.4;                   ///< N/mm
  double ki = 2.0;                   ///< N/(mm s)
  double kd = 0.008;                 ///< N s/mm
  double i_limit = 3;                ///< |integral term| limit per axis, N
  double velocity_cutoff_hz = 60.0;  ///< low-pass on the encoder velocity
};

/// PID position control toward a trajectory x_d(t) (t = protocol time since the first step),
/// on the axes selected by `selection` (a diagonal 0/1 matrix for hybrid force/position
/// control; identity by default). Output clamped to the device's max force. Done after
/// `duration_s` (infinite: never).
class PidPositionControl : public TickProtocol {
 public:
  using Trajectory = std::function<Vec3(double t)>;
  PidPositionControl(const DeviceInfo& info, Trajectory trajectory, double duration_s,
                     PidGains gains = {}, Mat3 selection = Mat3::Identity());
  /// Holds a fixed target.
  PidPositionControl(const DeviceInfo& info, const Vec3& target, double duration_s,
                     PidGains gains = {});
  Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) override;
  bool done() const override { return elapsed_ >= duration_; }
  double elapsed() const { return elapsed_; }
  Vec3 target() const { return target_; }

 private:
  DeviceInfo info_;
  Trajectory traj_;
  double duration_;
  PidGains g_;
  Mat3 sel_;
  double t0_ = 0, elapsed_ = 0, dt_;
  bool started_ = false;
  Vec3 integral_ = Vec3::Zero(), prev_pos_ = Vec3::Zero(), vel_ = Vec3::Zero();
  Vec3 target_ = Vec3::Zero();
};

/// Applies a loading-force profile f_l(t) to the object (t = protocol time): the command is
/// f_l(t) plus, when `ki` > 0, an integral correction that drives the compensated sensor
/// reading toward -f_l(t) on the selected axes (contact force = minus the loading force).
class ForceProfileControl : public TickProtocol {
 public:
  using Profile = std::function<Vec3(double t)>;
  ForceProfileControl(const DeviceInfo& info, Profile loading_force, double duration_s,
                      double ki = 0.0, Mat3 selection = Mat3::Identity());
  Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) override;
  bool done() const override { return elapsed_ >= duration_; }
  /// Last compensated sensor reading (contact force on the probe), N.
  const Vec3& contact_force() const { return contact_; }

 private:
  DeviceInfo info_;
  Profile profile_;
  double duration_, ki_;
  Mat3 sel_;
  CompensatorConfig comp_cfg_;
  CompensatorState comp_;
  double t0_ = 0, elapsed_ = 0, dt_;
  bool started_ = false;
  Vec3 integral_ = Vec3::Zero(), contact_ = Vec3::Zero();
};

/// Runs several protocols at once and sums their commands (e.g. force along z + PID in x, y).
/// Done when all are done.
class CompositeProtocol : public TickProtocol {
 public:
  explicit CompositeProtocol(std::vector<std::unique_ptr<TickProtocol>> parts);
  Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) override;
  bool done() const override;

 private:
  std::vector<std::unique_ptr<TickProtocol>> parts_;
};

class SimDevice;

/// Palpation executor: detaches the hand and runs `protocol` through the Device interface for
/// at most `max_seconds`, logging every tick (recording + ground truth).
LabRecording run_palpation(SimDevice& device, TickProtocol& protocol, double max_seconds);

}  // namespace inhap::lab
