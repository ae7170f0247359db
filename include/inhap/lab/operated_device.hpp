// The virtual lab as one inhap::Device for a servo loop (`inhap serve --device lab:SCENE`): a
// simulated device held by one of the lab's simulated operators, who moves the hand every tick
// as in `inhap lab record` (same device and operator for the same scene, spec and seed). The
// forces a renderer commands act on the device on top of the scene's soft object.
//
// Units: mm, N, s. The ground truth of every tick is logged (TickLogger) for the truth sidecar.
#pragma once

#include <cstddef>

#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"

namespace inhap::lab {

class OperatedDevice final : public Device {
 public:
  /// `reserve_ticks`: ticks the truth log reserves up front (no allocation until then).
  OperatedDevice(const Scene& scene, const RecordSpec& spec, std::size_t reserve_ticks = 0);

  const DeviceInfo& info() const override { return setup_.device->info(); }
  double time() const override { return setup_.device->time(); }
  Vec3 position() const override { return setup_.device->position(); }
  Vec3 force_sensor() const override { return setup_.device->force_sensor(); }
  void command_force(const Vec3& force) override { setup_.device->command_force(force); }
  /// Logs the tick's truth, lets the operator move the hand, advances the device.
  void tick() override;

  const SimDevice& device() const { return *setup_.device; }
  /// The recording and truth logged so far (moves them out).
  LabRecording take_log();

 private:
  Scene scene_;
  RecordSpec spec_;
  RecordSetup setup_;
  TickLogger log_;
};

}  // namespace inhap::lab
