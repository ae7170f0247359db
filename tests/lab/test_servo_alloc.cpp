// Servo-loop code must not allocate: the contact law, the simulated device's tick, the
// compensator and the controllers' steps run under a counting global operator new.
#include <gtest/gtest.h>

#include "inhap/contact/compensation.hpp"
#include "inhap/lab/control.hpp"
#include "inhap/lab/sim_device.hpp"
#include "support/alloc_counter.hpp"

namespace inhap::lab {
namespace {

SoftObject blob_plate() {
  return SoftObject(CylinderShape{Vec3::Zero(), 50, 25}, ContactLaw{},
                    {{Vec3(0, 0, 19), 10, 0.4, 1.2}});
}

TEST(ServoAlloc, DeviceTickContactCompensationAndControllersDoNotAllocate) {
  SimDevice dev(blob_plate());
  dev.place(Vec3(-3, 0, 33.5));
  dev.attach_hand(HandParams{});
  CompensatorConfig cfg = CompensatorConfig::from(dev.info());
  CompensatorState cs;
  PidPositionControl pid(
      dev.info(), [](double t) { return Vec3(-3 + 5 * t, 0, 30); }, 10.0);
  ForceProfileControl fpc(
      dev.info(), [](double) { return Vec3(0, 0, -2); }, 10.0, 20.0);
  const long probe = test::heap_allocations();
  ::operator delete(::operator new(16));           // (a new-expression could be elided)
  ASSERT_EQ(test::heap_allocations() - probe, 1);  // the counter sees allocations
  const long before = test::heap_allocations();
  for (int i = 0; i < 3000; ++i) {
    const Vec3 f = compensate_step(cfg, cs, dev.position(), dev.force_sensor());
    const Vec3 a = pid.step(dev.time(), dev.position(), dev.force_sensor());
    const Vec3 b = fpc.step(dev.time(), dev.position(), dev.force_sensor());
    dev.set_hand_target(Vec3(-3 + 0.01 * i, 0, 30));
    dev.command_force(0.5 * (a + b) + 0 * f);
    dev.tick();
  }
  EXPECT_EQ(test::heap_allocations() - before, 0);
  EXPECT_TRUE(dev.contact().in_contact);  // the loop really exercised the contact law
}

}  // namespace
}  // namespace inhap::lab
