// The composed data-driven servo step (see data_driven.hpp).
#include "inhap/haptics/data_driven.hpp"

namespace inhap::haptics {

ServoOutput step(const DataDrivenModel& model, DataDrivenState& state,
                 const ServoInput& input) noexcept {
  const Vec3& p = input.p_mm;
  const double dt = state.has_prev ? input.t_s - state.t_prev_s : 0.0;
  state.t_prev_s = input.t_s;
  state.has_prev = true;
  const friction::ProxyOutput o = friction::proxy_step(model.proxy, state.proxy, p, dt);
  ServoOutput out;
  out.contact = o.contact && o.q.allFinite();
  const Vec3 q = out.contact ? o.q : p;
  const Vec3 n = out.contact ? o.n : Vec3::UnitZ();
  // dd::servo_step is servo-safe (no allocation, no exceptions) although not declared noexcept.
  out.force_n =
      model.force ? dd::servo_step(*model.force, state.servo, p, q, n, out.contact) : Vec3::Zero();
  out.hip_mm = p;
  out.ihip_mm = q;
  out.cihip_mm = q;
  return out;
}

}  // namespace inhap::haptics
