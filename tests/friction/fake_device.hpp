// A tiny simulated device for the friction tests: a point-mass probe above the plane z = 0 (the
// probe-centre contact surface, outward normal +z) with an ideal linear spring contact and a
// tangential anchor that slides by Coulomb's law with viscous creep. Its answers are known:
//   normal force k_n * depth, tangential spring k_t * (p_t - a), sliding limit mu * f_N,
//   anchor speed (k_t |p_t - a| - mu f_N) / creep when beyond the limit.
// Units: mm, N, s, kg.
#pragma once

#include <cmath>
#include <functional>

#include "inhap/core/device.hpp"
#include "inhap/core/random.hpp"

namespace inhap::test {

struct FakeContactParams {
  double k_normal = 1.0;      ///< N/mm
  double c_normal = 0.02;     ///< N s/mm (contact damping)
  double k_tangential = 0.8;  ///< N/mm
  double mu = 0.5;
  double creep = 0.05;              ///< N s/mm: viscous sliding (0: ideal Coulomb)
  double mass = 0.05;               ///< kg
  double device_damping = 0.002;    ///< N s/mm
  Vec3 sensor_bias = Vec3::Zero();  ///< N, constant offset of the force sensor
  double sensor_noise = 0.0;        ///< N, standard deviation
  double encoder = 0.0;             ///< mm, position quantisation (0: none)
  int substeps = 10;
  /// Optional friction field mu(x) (position of the anchor); overrides mu when set.
  std::function<double(const Vec3&)> mu_field;
};

class FakeContactDevice final : public Device {
 public:
  explicit FakeContactDevice(FakeContactParams prm = {}, Vec3 start = Vec3(0, 0, 5))
      : prm_(prm), p_(start), rng_(7) {
    info_.name = "fake";
    info_.max_force_n = 6.2;
    anchor_ = Vec3(p_.x(), p_.y(), 0.0);
    update_outputs();
  }
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return t_; }
  Vec3 position() const override { return measured_p_; }
  Vec3 force_sensor() const override { return sensor_; }
  void command_force(const Vec3& f) override {
    const double m = f.norm();
    cmd_ = m > info_.max_force_n ? Vec3(f * (info_.max_force_n / m)) : f;
  }
  void tick() override {
    const double dt = 1e-3 / prm_.substeps;
    for (int i = 0; i < prm_.substeps; ++i) {
      const Vec3 fe = environment(dt);
      const Vec3 acc = (cmd_ + fe - prm_.device_damping * v_) / (prm_.mass * 1e-3);  // mm/s^2
      v_ += acc * dt;
      p_ += v_ * dt;
    }
    t_ += 1e-3;
    update_outputs();
  }
  /// Ground truth: the tangential anchor (the true proxy), on the plane.
  Vec3 anchor() const { return anchor_; }
  bool in_contact() const { return p_.z() < 0; }
  Vec3 true_position() const { return p_; }
  Vec3 true_force() const { return fe_; }
  const FakeContactParams& params() const { return prm_; }

 private:
  Vec3 environment(double dt) {
    Vec3 f = Vec3::Zero();
    const double depth = -p_.z();
    if (depth <= 0) {
      anchor_ = Vec3(p_.x(), p_.y(), 0.0);
      fe_ = f;
      return f;
    }
    const double fn_el = prm_.k_normal * depth;
    const double fn = std::max(0.0, fn_el - prm_.c_normal * v_.z());
    Vec3 d(p_.x() - anchor_.x(), p_.y() - anchor_.y(), 0.0);
    const double mu = prm_.mu_field ? prm_.mu_field(anchor_) : prm_.mu;
    const double limit = mu * fn_el;
    const double spring = prm_.k_tangential * d.norm();
    if (spring > limit && d.norm() > 0) {
      const Vec3 dir = d / d.norm();
      if (prm_.creep > 0) {
        const double speed = (spring - limit) / prm_.creep;
        const double step = std::min(speed * dt, d.norm() - limit / prm_.k_tangential);
        anchor_ += step * dir;
      } else {
        anchor_ = Vec3(p_.x(), p_.y(), 0.0) - (limit / prm_.k_tangential) * dir;
      }
      d = Vec3(p_.x() - anchor_.x(), p_.y() - anchor_.y(), 0.0);
    }
    f = Vec3(0, 0, fn) - prm_.k_tangential * d;
    fe_ = f;
    return f;
  }
  void update_outputs() {
    measured_p_ = p_;
    if (prm_.encoder > 0)
      for (int i = 0; i < 3; ++i) measured_p_[i] = prm_.encoder * std::round(p_[i] / prm_.encoder);
    sensor_ = fe_ + prm_.sensor_bias;
    if (prm_.sensor_noise > 0)
      for (int i = 0; i < 3; ++i) sensor_[i] += prm_.sensor_noise * rng_.normal();
  }

  FakeContactParams prm_;
  DeviceInfo info_;
  double t_ = 0;
  Vec3 p_, v_ = Vec3::Zero(), cmd_ = Vec3::Zero(), anchor_, fe_ = Vec3::Zero();
  Vec3 measured_p_, sensor_ = Vec3::Zero();
  Rng rng_;
};

}  // namespace inhap::test
