// The god-object renderer (CBA, TCA-MESH) through the common servo interface (renderers.hpp).
#include "inhap/haptics/renderers.hpp"

namespace inhap::haptics {

ServoOutput step(const rendering::Model& model, rendering::State& state,
                 rendering::Algorithm algorithm, const ServoInput& input) noexcept {
  ServoOutput out;
  out.force_n = rendering::step(model, state, input.p_mm, algorithm);
  out.contact = state.collision;
  out.hip_mm = input.p_mm;
  out.ihip_mm = state.collision ? state.ihip.point : input.p_mm;
  out.cihip_mm = state.collision ? state.cihip : input.p_mm;
  return out;
}

}  // namespace inhap::haptics
