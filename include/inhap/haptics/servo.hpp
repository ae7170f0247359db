// The common servo interface (thesis 4.4-4.5 and 5): one input and one output for every
// renderer, so a device loop runs CBA, TCA-MESH and the data-driven renderer alike.
//
// Units: time s, positions mm, forces N.
//
// Two levels:
//   - free functions step(model, state, input) -> output, one per renderer, with the model/state
//     split of the house (immutable model shared by many states; no allocation, no exceptions,
//     no I/O in a step). These are what a tight loop or a benchmark calls: no virtual call.
//   - Renderer, a thin virtual interface holding one model reference and one state, for a device
//     loop that picks the renderer at run time (one virtual call per tick).
#pragma once

#include "inhap/core/types.hpp"

namespace inhap::haptics {

/// What the device gives every tick.
struct ServoInput {
  double t_s = 0;                      ///< time stamp, s (monotonic)
  Vec3 p_mm = Vec3::Zero();            ///< probe (HIP) position, mm
  Vec3 sensor_force_n = Vec3::Zero();  ///< raw force-sensor reading, N (when has_sensor)
  bool has_sensor = false;             ///< the device has a force sensor
};

/// What a renderer gives back every tick: the force to command and the points a viewer draws.
struct ServoOutput {
  Vec3 force_n = Vec3::Zero();  ///< force to command, N (finite, clamped by the renderer)
  bool contact = false;         ///< in contact this tick
  Vec3 hip_mm = Vec3::Zero();   ///< haptic interface point: the probe position, mm
  /// IHIP / proxy: the god-object point q on the surface (CBA, TCA-MESH) or the sliding proxy q
  /// (data-driven); the HIP when out of contact, mm.
  Vec3 ihip_mm = Vec3::Zero();
  /// CIHIP: the compensated IHIP q' = q + s n of TCA-MESH; equal to ihip_mm for the others, mm.
  Vec3 cihip_mm = Vec3::Zero();
};

/// A renderer with its state, behind one virtual call per tick (see the adapters in
/// renderers.hpp). step() is servo-safe: no allocation, no exceptions, no I/O.
class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual ServoOutput step(const ServoInput& input) noexcept = 0;
  /// Called in the idle part of a period, after the force of step() has gone to the device, with
  /// a prediction of the next input: a renderer whose step is bound by memory latency reads
  /// ahead what the next step will read, so the next force is not delayed by cache misses. Must
  /// not change any output; servo-safe like step(). Default: nothing.
  virtual void prefetch(const ServoInput& /*next*/) noexcept {}
  /// True when prefetch() does something (the loop then schedules time for it).
  virtual bool reads_ahead() const noexcept { return false; }
  /// Back to the state of a freshly made renderer (same model).
  virtual void reset() noexcept = 0;
  virtual const char* name() const noexcept = 0;
};

}  // namespace inhap::haptics
