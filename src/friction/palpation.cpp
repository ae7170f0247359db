#include "inhap/friction/palpation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"

namespace inhap::friction {

Vec3 tangent_direction(const Vec3& n, const Vec3& reference, double angle) {
  Vec3 t0, t1;
  tangent_basis(n, reference, t0, t1);
  return std::cos(angle) * t0 + std::sin(angle) * t1;
}

const char* to_string(CycleStatus s) {
  switch (s) {
    case CycleStatus::kOk:
      return "ok";
    case CycleStatus::kNoContact:
      return "no_contact";
    case CycleStatus::kSaturated:
      return "saturated";
    case CycleStatus::kUnsettled:
      return "unsettled";
    case CycleStatus::kSlipCapped:
      return "slip_capped";
    case CycleStatus::kBadInput:
      return "bad_input";
  }
  return "unknown";
}

double CycleRecord::up_tangential() const {
  const Vec3 u = up();
  return (u - u.dot(nc) * nc).norm();
}

PalpationProtocol::PalpationProtocol(const PalpationConfig& config, const DeviceInfo& device,
                                     int point_id, const Vec3& reference, const Vec3& normal,
                                     const ShapeQuery* shape)
    : cfg_(config),
      info_(device),
      shape_(shape),
      point_(point_id),
      c_(reference),
      schedule_(cfg_, device.max_force_n) {
  if (!(info_.servo_rate_hz > 0)) throw Error("palpation: expected a servo rate > 0 Hz");
  if (!reference.allFinite() || !normal.allFinite() || !(normal.norm() > 0.5))
    throw Error("palpation: expected a finite reference point and a non-zero normal");
  n_ = normal.normalized();
  tangent_basis(n_, cfg_.tangent_reference, t0_, t1_);
  weight_ = cfg_.gravity_feedforward ? Vec3(1e-3 * info_.tool_mass_kg * info_.gravity_mm_s2)
                                     : Vec3::Zero();
  cycles_.reserve(schedule_.max_cycles());
}

void PalpationProtocol::begin_move(double time, const Vec3& from, const Vec3& to, double speed) {
  move_from_ = from;
  move_to_ = to;
  // Smooth (sine) time scaling peaks at pi/2 times the mean speed.
  move_dur_ = std::max(0.02, std::numbers::pi / 2 * (to - from).norm() / speed);
  phase_t0_ = time;
}

void PalpationProtocol::begin_cycle(double time, const Vec3& position) {
  cur_ = CycleRecord{};
  cur_.point = point_;
  cur_.reference = c_;
  cur_.f_normal = schedule_.f_normal();
  cur_.f_tangential = schedule_.f_tangential();
  cur_.t_plateau = schedule_.plateau();
  cur_.direction = schedule_.direction();
  cur_.angle = 2.0 * std::numbers::pi * schedule_.direction() / cfg_.directions;
  cur_.tdir = std::cos(cur_.angle) * t0_ + std::sin(cur_.angle) * t1_;
  cur_.nc = n_;
  cur_.t_start = time;
  saturated_ = measured_ = slip_capped_ = false;
  begin_lift(time, position);
}

void PalpationProtocol::begin_lift(double time, const Vec3& position) {
  const double height = (position - c_).dot(n_);
  const Vec3 lifted = position + std::max(0.0, cfg_.hover - height) * n_;
  begin_move(time, position, lifted, cfg_.travel_speed);
  travel_to_ = c_ + cfg_.hover * n_;
  phase_ = Phase::kLift;
}

Vec3 PalpationProtocol::clamp_force(const Vec3& f) const {
  const double m = f.norm();
  return m > info_.max_force_n ? Vec3(f * (info_.max_force_n / m)) : f;
}

Vec3 PalpationProtocol::pid(const Vec3& position, const Vec3& target, const Vec3& target_velocity,
                            double dt) {
  const Vec3 e = target - position;
  integral_ += e * dt;
  if (cfg_.ki > 0) {
    const double lim = cfg_.integral_limit / cfg_.ki;
    const double m = integral_.norm();
    if (m > lim) integral_ *= lim / m;
  }
  return clamp_force(cfg_.kp * e + cfg_.ki * integral_ + cfg_.kd * (target_velocity - vel_) -
                     weight_);
}

Vec3 PalpationProtocol::hold_zero_load() const {
  return clamp_force(-weight_ - cfg_.load_damping * vel_);
}

Vec3 PalpationProtocol::fail(const char* why, CycleStatus status, const Vec3& position) {
  failed_ = true;
  error_ = why;
  cur_.status = status;
  cur_.pr = position.allFinite() ? position : Vec3::Zero();
  if (cycles_.size() < cycles_.capacity()) cycles_.push_back(cur_);
  phase_ = Phase::kDone;
  return Vec3::Zero();
}

Vec3 PalpationProtocol::finish_cycle(double time, const Vec3& position) {
  cur_.pr = position;
  if (cycles_.size() < cycles_.capacity()) cycles_.push_back(cur_);
  if (schedule_.next(cur_.up_tangential()) && cycles_.size() < cycles_.capacity()) {
    begin_cycle(time, position);
  } else {
    finishing_ = true;
    begin_lift(time, position);  // lift and travel back to the hover point, then stop
  }
  return hold_zero_load();
}

Vec3 PalpationProtocol::step(double time, const Vec3& position, const Vec3& sensor_force) {
  if (phase_ == Phase::kDone) return Vec3::Zero();
  if (!std::isfinite(time) || !position.allFinite() || !sensor_force.allFinite())
    return fail("non-finite device reading", CycleStatus::kBadInput, position);
  double dt = have_last_ ? time - last_time_ : 0.0;
  if (!(dt > 0)) dt = 1.0 / info_.servo_rate_hz;
  if (have_last_) {
    const double alpha = 1.0 - std::exp(-2.0 * std::numbers::pi * cfg_.velocity_cutoff * dt);
    vel_ += alpha * ((position - last_p_) / dt - vel_);
  }
  have_last_ = true;
  last_time_ = time;
  last_p_ = position;
  const Tick k{time, time - phase_t0_, dt, position, sensor_force};
  switch (phase_) {
    case Phase::kStart:
      if (schedule_.done()) {
        phase_ = Phase::kDone;
        return Vec3::Zero();
      }
      begin_cycle(time, position);
      return hold_zero_load();
    case Phase::kLift:
    case Phase::kTravel:
      return move_step(k);
    case Phase::kTare:
      return tare_step(k);
    case Phase::kApproach:
      return approach_step(k);
    case Phase::kDrop:
      if (k.tau >= cfg_.drop_time) {
        cur_.pc = position;
        profile_ = LoadingProfile(cur_.f_normal, cur_.f_tangential, cur_.t_plateau, cfg_.rates);
        phase_ = Phase::kLoad;
        phase_t0_ = time;
      }
      return hold_zero_load();
    case Phase::kLoad:
      return load_step(k);
    case Phase::kRelease:
      return release_step(k);
    case Phase::kDone:
      break;
  }
  return Vec3::Zero();
}

Vec3 PalpationProtocol::move_step(const Tick& k) {
  const double s = std::min(1.0, k.tau / move_dur_);
  const double blend = smooth_ramp(s);
  const double rate =
      s < 1.0 ? 0.5 * std::numbers::pi * std::sin(std::numbers::pi * s) / move_dur_ : 0.0;
  const Vec3 target = move_from_ + blend * (move_to_ - move_from_);
  const Vec3 f = pid(k.position, target, rate * (move_to_ - move_from_), k.dt);
  if (s >= 1.0) {
    if (phase_ == Phase::kLift) {
      begin_move(k.time, move_to_, travel_to_, cfg_.travel_speed);
      phase_ = Phase::kTravel;
    } else {
      phase_ = Phase::kTare;
      phase_t0_ = k.time;
      bias_sum_.setZero();
      bias_n_ = 0;
    }
  }
  return f;
}

Vec3 PalpationProtocol::tare_step(const Tick& k) {
  if (k.tau >= 0.5 * cfg_.tare_time) {
    bias_sum_ += k.sensor;
    ++bias_n_;
  }
  const Vec3 f = pid(k.position, travel_to_, Vec3::Zero(), k.dt);
  if (k.tau >= cfg_.tare_time) {
    if (bias_n_ > 0) bias_ = bias_sum_ / bias_n_;
    if (finishing_) {
      phase_ = Phase::kDone;
      return Vec3::Zero();
    }
    phase_ = Phase::kApproach;
    phase_t0_ = k.time;
    contact_run_ = 0;
  }
  return f;
}

Vec3 PalpationProtocol::approach_step(const Tick& k) {
  const double depth = cfg_.approach_speed * k.tau;
  if (depth > cfg_.hover + cfg_.approach_extra)
    return fail("no contact found below the reference point", CycleStatus::kNoContact, k.position);
  const double fn = (k.sensor - bias_).dot(n_);
  contact_run_ = fn > cfg_.contact_force ? contact_run_ + 1 : 0;
  if (contact_run_ >= cfg_.contact_ticks) {
    phase_ = Phase::kDrop;
    phase_t0_ = k.time;
    return hold_zero_load();
  }
  return pid(k.position, travel_to_ - depth * n_, -cfg_.approach_speed * n_, k.dt);
}

Vec3 PalpationProtocol::load_step(const Tick& k) {
  Vec3 n = n_, t = cur_.tdir;
  if (shape_) {  // the frame of the surface under the probe
    Vec3 c, nn;
    if (shape_->closest(k.position, c, nn) && nn.allFinite() && nn.dot(n_) > 0.5) {
      n = nn;
      const Vec3 tt = t - t.dot(n) * n;
      if (tt.norm() > 0.5) t = tt.normalized();
    }
  }
  const Vec3 load = -profile_.normal(k.tau) * n + profile_.tangential(k.tau) * t;
  if (load.norm() > info_.max_force_n) saturated_ = true;
  const Vec3 u = k.position - cur_.pc;
  const double ut = (u - u.dot(n_) * n_).norm();
  const double unload_t = profile_.t_normal() + profile_.t_tangential() + profile_.t_plateau();
  if (k.tau < profile_.plateau_start()) plateau_ut_ = ut;
  const bool measure_now = !measured_ && k.tau >= profile_.t_measurement();
  if (k.tau < unload_t && (ut - plateau_ut_ > cfg_.max_slip || ut > cfg_.max_displacement)) {
    // Sliding away: jump to the start of the tangential unloading ramp.
    slip_capped_ = true;
    phase_t0_ = k.time - unload_t;
    if (!measured_) measure(k);
  }
  if (measure_now && !measured_) measure(k);
  if (k.tau >= profile_.duration()) {
    phase_ = Phase::kRelease;
    phase_t0_ = k.time;
    settle_run_ = 0;
  }
  return clamp_force(load - weight_ - cfg_.load_damping * vel_);
}

void PalpationProtocol::measure(const Tick& k) {
  cur_.f_meas = k.sensor - bias_;
  cur_.u_meas = k.position - cur_.pc;
  cur_.t_measurement_s = k.tau - profile_.plateau_start();
  measured_ = true;
}

Vec3 PalpationProtocol::release_step(const Tick& k) {
  if (k.tau >= cfg_.settle_min)
    settle_run_ = vel_.norm() < cfg_.settle_speed ? settle_run_ + k.dt : 0.0;
  const bool settled = settle_run_ >= cfg_.settle_window;
  if (settled || k.tau >= cfg_.settle_max) {
    if (saturated_)
      cur_.status = CycleStatus::kSaturated;
    else if (slip_capped_)
      cur_.status = CycleStatus::kSlipCapped;
    else if (!settled)
      cur_.status = CycleStatus::kUnsettled;
    return finish_cycle(k.time, k.position);
  }
  return hold_zero_load();
}

}  // namespace inhap::friction
