// Adapters behind haptics::Renderer (servo.hpp): CBA and TCA-MESH (rendering module, thesis 5)
// and the composed data-driven renderer (data_driven.hpp). Units: s, mm, N.
//
// Each adapter holds a reference to an immutable model (it must outlive the adapter) and its own
// state; step() allocates nothing, throws nothing and does no I/O.
#pragma once

#include "inhap/haptics/data_driven.hpp"
#include "inhap/haptics/servo.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::haptics {

/// One tick of the god-object renderer through the common interface (CBA or TCA-MESH).
ServoOutput step(const rendering::Model& model, rendering::State& state,
                 rendering::Algorithm algorithm, const ServoInput& input) noexcept;

/// CBA or TCA-MESH on a mesh with a stiffness map.
class MeshRenderer final : public Renderer {
 public:
  MeshRenderer(const rendering::Model& model, rendering::Algorithm algorithm)
      : model_(model), algorithm_(algorithm) {}
  ServoOutput step(const ServoInput& input) noexcept override {
    return haptics::step(model_, state_, algorithm_, input);
  }
  /// Warms the caches along the local search toward next.p_mm (rendering::prefetch).
  void prefetch(const ServoInput& next) noexcept override {
    rendering::prefetch(model_, state_, next.p_mm);
  }
  bool reads_ahead() const noexcept override { return true; }
  void reset() noexcept override { state_ = rendering::State{}; }
  const char* name() const noexcept override {
    return algorithm_ == rendering::Algorithm::kTCA ? "tca-mesh" : "cba";
  }
  const rendering::State& state() const { return state_; }

 private:
  const rendering::Model& model_;
  rendering::Algorithm algorithm_;
  rendering::State state_;
};

/// The data-driven renderer (FOAW -> proxy -> RBF force).
class DataDrivenRenderer final : public Renderer {
 public:
  explicit DataDrivenRenderer(const DataDrivenModel& model) : model_(model) {}
  ServoOutput step(const ServoInput& input) noexcept override {
    return haptics::step(model_, state_, input);
  }
  void reset() noexcept override { state_.reset(); }
  const char* name() const noexcept override { return "data-driven"; }
  const DataDrivenState& state() const { return state_; }

 private:
  const DataDrivenModel& model_;
  DataDrivenState state_;
};

/// No rendering: zero force, never in contact (recording a device, or a protocol that commands
/// its own forces).
class NullRenderer final : public Renderer {
 public:
  ServoOutput step(const ServoInput& input) noexcept override {
    ServoOutput out;
    out.hip_mm = input.p_mm;
    out.ihip_mm = input.p_mm;
    out.cihip_mm = input.p_mm;
    return out;
  }
  void reset() noexcept override {}
  const char* name() const noexcept override { return "none"; }
};

}  // namespace inhap::haptics
