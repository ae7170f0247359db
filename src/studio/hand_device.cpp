#include "inhap/studio/hand_device.hpp"

#include <algorithm>

namespace inhap::studio {

void TargetMailbox::write(const Vec3& target, std::uint64_t seq) noexcept {
  const std::uint64_t v = version_.load(std::memory_order_relaxed);
  version_.store(v + 1, std::memory_order_relaxed);  // odd: writing
  std::atomic_thread_fence(std::memory_order_release);
  x_.store(target.x(), std::memory_order_relaxed);
  y_.store(target.y(), std::memory_order_relaxed);
  z_.store(target.z(), std::memory_order_relaxed);
  seq_.store(seq, std::memory_order_relaxed);
  version_.store(v + 2, std::memory_order_release);
}

bool TargetMailbox::read(Vec3& target, std::uint64_t& seq) const noexcept {
  const std::uint64_t v1 = version_.load(std::memory_order_acquire);
  if (v1 == 0 || (v1 & 1u)) return false;
  const Vec3 t(x_.load(std::memory_order_relaxed), y_.load(std::memory_order_relaxed),
               z_.load(std::memory_order_relaxed));
  const std::uint64_t s = seq_.load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  if (version_.load(std::memory_order_relaxed) != v1) return false;
  target = t;
  seq = s;
  return true;
}

MouseOperator::MouseOperator(const TargetMailbox& mailbox, const Vec3& start, double max_speed_mm_s)
    : mailbox_(mailbox), goal_(start), current_(start), max_speed_(max_speed_mm_s) {}

void MouseOperator::begin(lab::SimDevice& device) {
  device.attach_hand(lab::HandParams{});
  device.place(current_);
  device.set_hand_target(current_);
}

void MouseOperator::step(lab::SimDevice& device) {
  Vec3 t;
  std::uint64_t seq = 0;
  if (mailbox_.read(t, seq)) {
    goal_ = t;
    applied_.store(seq, std::memory_order_release);
  }
  const double max_step = max_speed_ / device.info().servo_rate_hz;
  const Vec3 d = goal_ - current_;
  const double n = d.norm();
  current_ = n <= max_step ? goal_ : Vec3(current_ + d * (max_step / n));
  device.set_hand_target(current_);
}

LabHandDevice::LabHandDevice(lab::SoftObject object, const lab::DeviceParams& params,
                             std::unique_ptr<lab::HandOperator> op, double speed)
    : device_(std::make_unique<lab::SimDevice>(std::move(object), params)), op_(std::move(op)) {
  op_->begin(*device_);
  info_ = device_->info();
  info_.servo_rate_hz *= std::clamp(speed, 0.1, 20.0);
}

lab::SoftObject out_of_the_way_object() {
  return lab::SoftObject(lab::SphereShape{Vec3(0, 0, -1.0e5), 1.0}, lab::ContactLaw{});
}

}  // namespace inhap::studio
