#include "inhap/lab/control.hpp"

#include <cmath>
#include <limits>

#include "inhap/lab/sim_device.hpp"

namespace inhap::lab {

namespace {

Vec3 clamp_norm(const Vec3& f, double max) {
  if (!all_finite(f)) return Vec3::Zero();
  const double n = f.norm();
  return n > max ? Vec3(f * (max / n)) : f;
}

}  // namespace

PidPositionControl::PidPositionControl(const DeviceInfo& info, Trajectory trajectory,
                                       double duration_s, PidGains gains, Mat3 selection)
    : info_(info),
      traj_(std::move(trajectory)),
      duration_(duration_s),
      g_(gains),
      sel_(selection),
      dt_(1.0 / info.servo_rate_hz) {}

PidPositionControl::PidPositionControl(const DeviceInfo& info, const Vec3& target,
                                       double duration_s, PidGains gains)
    : PidPositionControl(
          info, [target](double) { return target; }, duration_s, gains) {}

Vec3 PidPositionControl::step(double time, const Vec3& position, const Vec3& /*sensor*/) {
  if (!std::isfinite(time) || !all_finite(position)) {  // reset on garbage
    started_ = false;
    integral_.setZero();
    vel_.setZero();
    return Vec3::Zero();
  }
  if (!started_) {
    started_ = true;
    t0_ = time;
    prev_pos_ = position;
    vel_.setZero();
  }
  elapsed_ = time - t0_;
  target_ = traj_(elapsed_);
  if (!all_finite(target_)) return Vec3::Zero();
  // Encoder velocity through a first-order low-pass (quantisation steps are 10 mm/s).
  const double a = 1.0 - std::exp(-2.0 * M_PI * g_.velocity_cutoff_hz * dt_);
  vel_ += a * ((position - prev_pos_) / dt_ - vel_);
  prev_pos_ = position;
  const Vec3 err = target_ - position;
  integral_ += g_.ki * dt_ * err;
  integral_ = integral_.cwiseMax(-g_.i_limit).cwiseMin(g_.i_limit);
  const Vec3 f = g_.kp * err + integral_ - g_.kd * vel_;
  return clamp_norm(sel_ * f, info_.max_force_n);
}

ForceProfileControl::ForceProfileControl(const DeviceInfo& info, Profile loading_force,
                                         double duration_s, double ki, Mat3 selection)
    : info_(info),
      profile_(std::move(loading_force)),
      duration_(duration_s),
      ki_(ki),
      sel_(selection),
      comp_cfg_(CompensatorConfig::from(info)),
      dt_(1.0 / info.servo_rate_hz) {}

Vec3 ForceProfileControl::step(double time, const Vec3& position, const Vec3& sensor_force) {
  contact_ = compensate_step(comp_cfg_, comp_, position, sensor_force);
  if (!std::isfinite(time)) {
    started_ = false;
    integral_.setZero();
    return Vec3::Zero();
  }
  if (!started_) {
    started_ = true;
    t0_ = time;
  }
  elapsed_ = time - t0_;
  const Vec3 fl = profile_(elapsed_);
  if (!all_finite(fl)) return Vec3::Zero();
  Vec3 cmd = sel_ * fl;
  if (ki_ > 0) {
    // Contact force should equal -f_l: integrate the error (bounded by the device limit).
    integral_ += ki_ * dt_ * (sel_ * (-fl - contact_));
    integral_ = clamp_norm(integral_, info_.max_force_n);
    cmd -= integral_;
  }
  return clamp_norm(cmd, info_.max_force_n);
}

CompositeProtocol::CompositeProtocol(std::vector<std::unique_ptr<TickProtocol>> parts)
    : parts_(std::move(parts)) {}

Vec3 CompositeProtocol::step(double time, const Vec3& position, const Vec3& sensor_force) {
  Vec3 f = Vec3::Zero();
  for (auto& p : parts_)
    if (!p->done()) f += p->step(time, position, sensor_force);
  return f;
}

bool CompositeProtocol::done() const {
  for (const auto& p : parts_)
    if (!p->done()) return false;
  return true;
}

LabRecording run_palpation(SimDevice& device, TickProtocol& protocol, double max_seconds) {
  device.detach_hand();
  const long max_ticks =
      static_cast<long>(std::llround(std::max(0.0, max_seconds) * device.info().servo_rate_hz));
  TickLogger log(device, static_cast<std::size_t>(max_ticks));
  long n = 0;
  while (!protocol.done() && n < max_ticks) {
    log.sample();
    device.command_force(protocol.step(device.time(), device.position(), device.force_sensor()));
    device.tick();
    ++n;
  }
  return log.take();
}

}  // namespace inhap::lab
