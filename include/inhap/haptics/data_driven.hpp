// The data-driven renderer of thesis 4.4-4.5 composed in one servo step: probe position p ->
// FOAW velocity -> sliding-yield-surface proxy q (friction::proxy_step, with creep) -> RBF force
// g(p, pdot, q) (datadriven::servo_step).
//
// Units: time s, positions mm, velocities mm/s, forces N.
//
// Model = {sliding yield surfaces, shape, force model} (+ the proxy estimator's options), all
// immutable and not owned: they must outlive the model. State = {proxy state, FOAW/servo state,
// previous time stamp}. step() gives exactly the forces of the pieces run by hand in the same
// order (friction::proxy_track, then datadriven::replay with that track), tick for tick; it
// allocates nothing, throws nothing and does no I/O.
#pragma once

#include "inhap/datadriven/servo.hpp"
#include "inhap/friction/proxy_estimator.hpp"
#include "inhap/haptics/servo.hpp"

namespace inhap::haptics {

struct DataDrivenModel {
  /// Sliding yield surfaces and shape (friction::ProxyModel::sys, ::shape) and the return
  /// mapping's options (creep on by default, as in the evaluations).
  friction::ProxyModel proxy;
  const datadriven::ForceModel* force = nullptr;  ///< RBF force model (not owned)

  DataDrivenModel() = default;
  DataDrivenModel(const friction::SysModel& sys, const friction::ShapeQuery& shape,
                  const datadriven::ForceModel& force_model)
      : proxy{&sys, &shape}, force(&force_model) {}
};

struct DataDrivenState {
  friction::ProxyState proxy;    ///< proxy estimator (contact, q, frame, g_s at q)
  datadriven::ServoState servo;  ///< FOAW buffer, last velocity, bin and force
  double t_prev_s = 0;           ///< time stamp of the previous tick, s
  bool has_prev = false;         ///< t_prev_s valid
  /// The ticks' period, s: a running mean of t - t_prev (0 before the second tick). The force
  /// model's velocity filter runs at it (FoawParams::at_period), not at the training's rate.
  double period_s = 0;

  /// Back to the initial state.
  void reset() noexcept { *this = DataDrivenState{}; }
};

/// One servo tick. dt for the proxy's creep = t - t_prev (0 on the first tick). Zero force out of
/// contact and without a force model; the sensor force is not used. Inline, so a loop calling it
/// compiles to the same code as the pieces written out by hand (bench/bench_servo.cpp).
inline ServoOutput step(const DataDrivenModel& model, DataDrivenState& state,
                        const ServoInput& input) noexcept {
  const Vec3& p = input.p_mm;
  const double dt = state.has_prev ? input.t_s - state.t_prev_s : 0.0;
  state.t_prev_s = input.t_s;
  state.has_prev = true;
  if (dt > 0 && dt < 1.0)  // a pause or a clock jump does not count
    state.period_s = state.period_s > 0 ? state.period_s + 0.02 * (dt - state.period_s) : dt;
  const friction::ProxyOutput o = friction::proxy_step(model.proxy, state.proxy, p, dt);
  ServoOutput out;
  out.contact = o.contact && o.q.allFinite();
  const Vec3 q = out.contact ? o.q : p;
  // datadriven::servo_step is servo-safe (no allocation, no exceptions) although not declared
  // noexcept.
  out.force_n = model.force ? datadriven::servo_step(
                                  *model.force, model.force->foaw.at_period(state.period_s),
                                  state.servo, p, q, out.contact ? o.n : Vec3::UnitZ(), out.contact)
                            : Vec3::Zero();
  out.hip_mm = p;
  out.ihip_mm = q;
  out.cihip_mm = q;
  return out;
}

}  // namespace inhap::haptics
