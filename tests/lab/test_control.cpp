// Device-side controllers and the palpation executor.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/lab/control.hpp"
#include "inhap/lab/operators.hpp"

namespace inhap::lab {
namespace {

SoftObject plate() {
  ContactLaw l;
  l.k = 0.35, l.k_t = 0.5, l.mu = 1.2;
  return SoftObject(CylinderShape{Vec3::Zero(), 50, 25}, l);
}

TEST(Control, PidBringsTheProbeToItsTargetWithinTheForceLimit) {
  SimDevice dev(plate());
  dev.place(Vec3(0, 0, 60));
  const Vec3 target(15, -10, 70);
  PidPositionControl pid(dev.info(), target, 2.0);
  double max_cmd = 0;
  while (!pid.done()) {
    const Vec3 f = pid.step(dev.time(), dev.position(), dev.force_sensor());
    max_cmd = std::max(max_cmd, f.norm());
    dev.command_force(f);
    dev.tick();
  }
  EXPECT_LE(max_cmd, 6.2 + 1e-12);
  // The integral term removes the offset joint friction would leave: only the encoder's
  // resolution remains.
  EXPECT_LT((dev.truth().position - target).norm(), 0.02);
  EXPECT_LT(dev.truth().velocity.norm(), 1.0);
}

TEST(Control, PidFollowsATrajectoryAndResetsOnGarbage) {
  SimDevice dev(plate());
  dev.place(Vec3(-20, 0, 60));
  PidPositionControl pid(
      dev.info(), [](double t) { return Vec3(-20 + 10 * t, 0, 60); }, 3.0);
  double worst = 0;
  while (!pid.done()) {
    dev.command_force(pid.step(dev.time(), dev.position(), dev.force_sensor()));
    dev.tick();
    if (pid.elapsed() > 1.0) worst = std::max(worst, (dev.truth().position - pid.target()).norm());
  }
  EXPECT_LT(worst, 0.2);  // ramp tracking lag with the default gains, mm
  EXPECT_EQ(pid.step(dev.time(), Vec3(NAN, 0, 0), Vec3::Zero()), Vec3::Zero());
}

TEST(Control, ForceControlHoldsTheContactForce) {
  SimDevice dev(plate());
  dev.place(Vec3(5, 5, 33.2));
  ForceProfileControl ctl(
      dev.info(), [](double t) { return Vec3(0, 0, -2.0 * std::min(1.0, t / 0.3)); }, 1.5, 20.0);
  const LabRecording lab = run_palpation(dev, ctl, 5.0);
  EXPECT_EQ(lab.rec.size(), 1501u);  // stops when the protocol is done
  double truth = 0, sensed = 0;
  for (std::size_t i = lab.rec.size() - 500; i < lab.rec.size(); ++i)
    truth += lab.truth.force[i].z() / 500, sensed += lab.rec.f[i].z() / 500;
  EXPECT_NEAR(truth, 2.0, 0.01);
  EXPECT_NEAR(sensed, 2.0, 0.01);
  EXPECT_NEAR(ctl.contact_force().z(), 2.0, 0.05);
}

TEST(Control, PalpationDetachesTheHand) {
  SimDevice dev(plate());
  dev.attach_hand(HandParams{});
  dev.set_hand_target(Vec3(0, 0, 100));
  std::vector<std::unique_ptr<TickProtocol>> none;
  none.push_back(std::make_unique<ForceProfileControl>(
      dev.info(), [](double) { return Vec3::Zero(); }, 0.2));
  CompositeProtocol idle(std::move(none));
  const Vec3 before = dev.truth().position;
  run_palpation(dev, idle, 1.0);
  EXPECT_FALSE(dev.hand_attached());
  EXPECT_TRUE(idle.done());
  EXPECT_NEAR((dev.truth().position - before).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace inhap::lab
