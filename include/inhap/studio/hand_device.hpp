// inhap studio: the virtual lab as the studio's device (`--device lab:SCENE`).
//  - LabHandDevice: a lab::SimDevice held by a lab::HandOperator (the simulated tapping operator
//    for sampling, or MouseOperator), ticked like lab::OperatedDevice but without the truth log
//    (a studio session runs for hours). `speed` > 1 makes the servo loop tick faster than the
//    device's clock (simulated time runs `speed` times wall time), so a tapping session of 50
//    taps takes seconds instead of a minute.
//  - MouseOperator: the simulated hand follows a target the page sets (the mouse), read by the
//    servo thread through a seqlock (TargetMailbox: no lock, no allocation); the hand target
//    moves towards it at most `max_speed_mm_s`, as an arm would.
// Units: mm, N, s.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

#include "inhap/core/device.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::studio {

/// One writer (the server), one reader (the servo thread). Lock-free.
class TargetMailbox {
 public:
  void write(const Vec3& target, std::uint64_t seq) noexcept;
  /// False when no target was written yet or the writer was mid-write (keep the last one).
  bool read(Vec3& target, std::uint64_t& seq) const noexcept;

 private:
  std::atomic<std::uint64_t> version_{0};
  std::atomic<double> x_{0}, y_{0}, z_{0};
  std::atomic<std::uint64_t> seq_{0};
};

class MouseOperator final : public lab::HandOperator {
 public:
  MouseOperator(const TargetMailbox& mailbox, const Vec3& start, double max_speed_mm_s = 400.0);
  std::string name() const override { return "mouse"; }
  void begin(lab::SimDevice& device) override;
  void step(lab::SimDevice& device) override;
  /// The seq of the last target the servo thread applied (for the page's latency measurement).
  std::uint64_t applied_seq() const noexcept { return applied_.load(std::memory_order_acquire); }

 private:
  const TargetMailbox& mailbox_;
  Vec3 goal_, current_;
  double max_speed_;
  std::atomic<std::uint64_t> applied_{0};
};

class LabHandDevice final : public Device {
 public:
  LabHandDevice(lab::SoftObject object, const lab::DeviceParams& params,
                std::unique_ptr<lab::HandOperator> op, double speed = 1.0);
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return device_->time(); }
  Vec3 position() const override { return device_->position(); }
  Vec3 force_sensor() const override { return device_->force_sensor(); }
  void command_force(const Vec3& force) override { device_->command_force(force); }
  void tick() override {
    op_->step(*device_);
    device_->tick();
  }
  /// The device's own description (its true servo rate), for force compensation.
  const DeviceInfo& device_info() const { return device_->info(); }
  const lab::SimDevice& device() const { return *device_; }
  lab::HandOperator& op() { return *op_; }

 private:
  std::unique_ptr<lab::SimDevice> device_;
  std::unique_ptr<lab::HandOperator> op_;
  DeviceInfo info_;
};

/// A soft object far below everything the studio renders: the probe of an explore or experiment
/// session touches only the rendered mesh (the renderer's force), never the lab's own object.
lab::SoftObject out_of_the_way_object();

}  // namespace inhap::studio
