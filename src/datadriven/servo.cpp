// Servo-rate rendering of the data-driven force model (see servo.hpp).
#include "inhap/datadriven/servo.hpp"

#include <cmath>

namespace inhap::datadriven {

namespace {
bool sane(const Vec3& v) {
  return v.allFinite() && v.lpNorm<Eigen::Infinity>() < kAbsurdPositionMm;
}
}  // namespace

Vec3 servo_step(const ForceModel& model, ServoState& state, const Vec3& p, const Vec3& q,
                bool contact) {
  return servo_step(model, state, p, q, Vec3::UnitZ(), contact);
}

Vec3 servo_step(const ForceModel& model, ServoState& state, const Vec3& p, const Vec3& q,
                const Vec3& normal, bool contact) {
  return servo_step(model, model.foaw, state, p, q, normal, contact);
}

Vec3 servo_step(const ForceModel& model, const FoawParams& foaw, ServoState& state, const Vec3& p,
                const Vec3& q, const Vec3& normal, bool contact) {
  if (!sane(p) || (contact && !sane(q))) {
    state.reset();
    return Vec3::Zero();
  }
  if (state.foaw.head >= 0 &&
      (p - state.foaw.buffer[static_cast<std::size_t>(state.foaw.head)]).norm() >= kMaxJumpMm) {
    // A tracking glitch: the filter's history (and the velocity it would give) is meaningless
    // across it. Zero force; start afresh from this sample, as a new state would.
    state.reset();
    state.velocity = foaw_step(foaw, state.foaw, p);
    state.contact = contact;
    return Vec3::Zero();
  }
  state.velocity = foaw_step(foaw, state.foaw, p);
  const double moved = contact && state.contact ? (q - state.q).norm() : 0.0;
  state.slip = moved > kSlidingStepMm ? moved / foaw.dt_s : 0.0;
  state.contact = contact;
  if (contact) state.q = q;
  if (!contact || model.bins.empty()) {
    state.bin = -1;
    state.force.setZero();
    return state.force;
  }
  state.bin = model.bin_of((q - p).norm());
  state.force = model_force(model, p, state.velocity, q, normal, state.slip);  // finite and clamped
  return state.force;
}

}  // namespace inhap::datadriven
