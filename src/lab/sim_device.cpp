#include "inhap/lab/sim_device.hpp"

#include <fmt/format.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "mujoco_contact.hpp"

namespace inhap::lab {

namespace {

constexpr double kKgMmS2ToN = 1e-3;  // kg * mm/s^2 -> N

void check_params(const DeviceParams& p) {
  auto pos = [](double v) { return std::isfinite(v) && v > 0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0; };
  std::string bad;
  if (!pos(p.mass_kg))
    bad = "mass_kg > 0";
  else if (!nonneg(p.viscous_n_s_per_mm))
    bad = "viscous_n_s_per_mm >= 0";
  else if (!nonneg(p.coulomb_n))
    bad = "coulomb_n >= 0";
  else if (p.substeps < 1 || p.substeps > 1000)
    bad = "substeps in 1..1000";
  else if (!pos(p.servo_rate_hz))
    bad = "servo_rate_hz > 0";
  else if (!nonneg(p.encoder_resolution_mm))
    bad = "encoder_resolution_mm >= 0";
  else if (!pos(p.max_force_n) || p.max_force_n > kForceCeilingN)
    bad = fmt::format("max_force_n in (0, {}] N (the ceiling for any device profile)",
                      kForceCeilingN);
  else if (!nonneg(p.tool_mass_kg))
    bad = "tool_mass_kg >= 0";
  else if (!nonneg(p.sensor_noise_n))
    bad = "sensor_noise_n >= 0";
  else if (!all_finite(p.gravity_mm_s2))
    bad = "finite gravity_mm_s2";
  else if (!nonneg(p.probe.radius_mm))
    bad = "probe radius >= 0";
  if (!bad.empty()) throw Error(fmt::format("simulated device: expected {}", bad));
}

}  // namespace

SimDevice::SimDevice(SoftObject object, DeviceParams params)
    : object_(std::move(object)), params_(params), rng_(params.seed) {
  check_params(params_);
  info_.name = "inhap virtual lab: simulated 3-DOF device";
  info_.servo_rate_hz = params_.servo_rate_hz;
  info_.max_force_n = params_.max_force_n;
  info_.tool_mass_kg = params_.tool_mass_kg;
  info_.gravity_mm_s2 = params_.gravity_mm_s2;
  info_.sensor_rotation = Mat3::Identity();
  info_.probe_radius_mm = params_.probe.radius_mm;
  if (params_.physics == Physics::kMujoco) {
    info_.name = "inhap virtual lab: simulated 3-DOF device, MuJoCo contact";
    mujoco_ = std::make_unique<MujocoContact>(object_, params_.probe.radius_mm,
                                              1.0 / (params_.servo_rate_hz * params_.substeps),
                                              params_.mujoco);
  }
  const Box3 b = object_.shape().bounds();
  const Vec3 start =
      b.empty() ? Vec3(0, 0, 50)
                : Vec3(b.center().x(), b.center().y(), b.max.z() + params_.probe.radius_mm + 30.0);
  place(start);
}

SimDevice::~SimDevice() = default;

void SimDevice::command_force(const Vec3& force) {
  if (!all_finite(force)) {
    command_.setZero();  // NaN/inf command: zero force (and nothing else to reset)
    return;
  }
  const double n = force.norm();
  command_ = n > params_.max_force_n ? Vec3(force * (params_.max_force_n / n)) : force;
}

void SimDevice::place(const Vec3& position) {
  x_ = all_finite(position) ? position : Vec3::Zero();
  v_.setZero();
  const auto episode = contact_.episode;
  contact_.reset();
  contact_.episode = episode;
  if (mujoco_) {
    mujoco_->place(x_, contact_, time());
    contact_force_.setZero();
  } else {
    contact_force_ = contact_step(object_, probe_radius(), contact_, x_, v_, time(), 0.0);
  }
  hand_from_ = hand_to_ = x_;
  truth_.acceleration.setZero();
  truth_.hand_force.setZero();
  truth_.motor_force.setZero();
  read_sensor();
}

void SimDevice::attach_hand(const HandParams& hand) {
  hand_ = hand;
  hand_attached_ = true;
  hand_from_ = hand_to_ = x_;
}

void SimDevice::detach_hand() {
  hand_attached_ = false;
  truth_.hand_force.setZero();
}

void SimDevice::set_hand_target(const Vec3& target) {
  if (all_finite(target)) hand_to_ = target;
}

void SimDevice::substep(double dt, const Vec3& target, const Vec3& target_vel) {
  const double m = params_.mass_kg + (hand_attached_ ? hand_.mass_kg : 0.0);
  Vec3 f = command_ + contact_force_;
  if (hand_attached_) {
    truth_.hand_force =
        hand_.stiffness_n_per_mm * (target - x_) + hand_.damping_n_s_per_mm * (target_vel - v_);
    f += truth_.hand_force;
  }
  // Forces are in N, mass in kg: dv [mm/s] = dt * F / m * 1e3.
  const double gain = dt * 1e3 / m;
  const double visc = 1.0 + gain * params_.viscous_n_s_per_mm;
  Vec3 v = (v_ + gain * f) / visc;  // implicit viscous friction
  const double stick = gain * params_.coulomb_n / visc;
  const double speed = v.norm();
  v = speed <= stick ? Vec3::Zero() : Vec3(v * (1.0 - stick / speed));  // implicit Coulomb
  v_ = v;
  x_ += dt * v_;
}

void SimDevice::tick() {
  const int n = params_.substeps;
  const double period = 1.0 / params_.servo_rate_hz;
  const double dt = period / n;
  const double t0 = time();
  const Vec3 v_start = v_;
  const Vec3 target_vel = (hand_to_ - hand_from_) / period;
  for (int s = 0; s < n; ++s) {
    const Vec3 target = hand_from_ + (double(s + 1) / n) * (hand_to_ - hand_from_);
    substep(dt, target, target_vel);
    const double t = t0 + (s + 1) * dt;
    contact_force_ = mujoco_ ? mujoco_->step(x_, v_, t, contact_)
                             : contact_step(object_, probe_radius(), contact_, x_, v_, t, dt);
  }
  ++ticks_;
  hand_from_ = hand_to_;
  truth_.motor_force = command_;
  truth_.acceleration = (v_ - v_start) / period;
  if (!all_finite(x_) || !all_finite(v_)) place(Vec3::Zero());  // cannot happen; never NaN
  command_.setZero();                                           // a command lasts one tick
  read_sensor();
}

void SimDevice::read_sensor() {
  const double res = params_.encoder_resolution_mm;
  encoder_ = res > 0 ? Vec3(((x_ / res).array().round() * res).matrix()) : x_;
  Vec3 r = contact_force_;
  if (params_.noise && params_.sensor_noise_n > 0)
    for (int k = 0; k < 3; ++k) r[k] += params_.sensor_noise_n * rng_.normal();
  if (params_.gravity) r += params_.tool_mass_kg * kKgMmS2ToN * params_.gravity_mm_s2;
  if (params_.inertia) r -= params_.tool_mass_kg * kKgMmS2ToN * truth_.acceleration;
  sensor_ = r;
  truth_.time = time();
  truth_.position = x_;
  truth_.velocity = v_;
}

}  // namespace inhap::lab
