// Servo renderer: contact gating, guards, replay consistency and zero allocation per step.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "dd_fixtures.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/servo.hpp"
#include "support/alloc_counter.hpp"

namespace inhap::datadriven {
namespace test_servo {

const ForceModel& model() {
  static const ForceModel m = [] {
    const TrainingSet s = test::take(test::synthetic_set(2, 8000), 0, 2);
    TrainParams p = test::small_params();
    p.design = Design::kRegression;
    return train_force_model(s, p);
  }();
  return m;
}

TEST(Servo, ZeroForceOutOfContactAndModelForceInContact) {
  ServoState st;
  for (int i = 0; i < 20; ++i) {
    const Vec3 f = servo_step(model(), st, Vec3(0, 0, 1.0 - 0.001 * i), Vec3::Zero(), false);
    EXPECT_EQ(f, Vec3::Zero());
    EXPECT_EQ(st.bin, -1);
  }
  const Vec3 p(1, 2, -2), q(1.5, 2, 0);
  const Vec3 f = servo_step(model(), st, p, q, true);
  EXPECT_EQ(f, model_force(model(), p, st.velocity, q));
  EXPECT_GT(f.z(), 0.5);  // pressed 2 mm into the synthetic object
  EXPECT_GE(st.bin, 0);
}

TEST(Servo, BadInputGivesZeroAndResets) {
  ServoState st;
  servo_step(model(), st, Vec3(0, 0, -1), Vec3::Zero(), true);
  EXPECT_EQ(servo_step(model(), st, Vec3(std::nan(""), 0, 0), Vec3::Zero(), true), Vec3::Zero());
  EXPECT_EQ(st.resets, 1u);
  EXPECT_EQ(servo_step(model(), st, Vec3(0, 0, -1), Vec3(0, 0, 1e9), true), Vec3::Zero());
  EXPECT_EQ(st.resets, 2u);
  EXPECT_EQ(st.foaw.count, 0);
}

TEST(Servo, BoundedFarOutsideTheTrainingRange) {
  ServoState st;
  Rng rng(4);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-100, 0));
    const Vec3 q = p + Vec3(rng.uniform(-80, 80), rng.uniform(-80, 80), rng.uniform(0, 80));
    const Vec3 f = servo_step(model(), st, p, q, true);  // also absurd velocities
    ASSERT_TRUE(f.allFinite());
    ASSERT_LE(f.norm(), model().force_limit_n + 1e-12);
  }
}

TEST(Servo, ReplayMatchesFoawAndModelForce) {
  SyntheticParams sp;
  sp.samples = 3000;
  sp.seed = 9;
  const Recording rec = synthetic_recording(sp);
  const ProxyTrack track = proxy_from_columns(rec, "synthetic");
  const std::vector<Vec3> out = replay(model(), rec, track);
  const std::vector<Vec3> v = foaw_velocities(rec.p, model().foaw);
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Vec3 expect =
        track.contact[i] ? model_force(model(), rec.p[i], v[i], track.q[i]) : Vec3::Zero();
    ASSERT_EQ(out[i], expect) << i;
  }
}

TEST(Servo, NoHeapAllocationPerStep) {
  ServoState st;
  const ForceModel& m = model();
  Rng rng(1);
  std::vector<Vec3> ps, qs;
  for (int i = 0; i < 5000; ++i) {
    ps.emplace_back(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-4, 1));
    qs.emplace_back(ps.back().x() + rng.uniform(-3, 3), ps.back().y(), 0.0);
  }
  double sink = 0;
  const long probe = inhap::test::heap_allocations();
  ::operator delete(::operator new(16));  // the counter sees allocations
  ASSERT_EQ(inhap::test::heap_allocations() - probe, 1);
  const long before = inhap::test::heap_allocations();
  for (int i = 0; i < 5000; ++i)
    sink += servo_step(m, st, ps[static_cast<std::size_t>(i)], qs[static_cast<std::size_t>(i)],
                       ps[static_cast<std::size_t>(i)].z() < 0)
                .norm();
  servo_step(m, st, Vec3(std::nan(""), 0, 0), Vec3::Zero(), true);  // reset path too
  EXPECT_EQ(inhap::test::heap_allocations() - before, 0);
  EXPECT_GT(sink, 0.0);
}

TEST(Servo, EntryProxyHoldsTheContactOnsetPoint) {
  EntryProxyState s;
  EXPECT_EQ(entry_proxy(s, Vec3(1, 1, 1), false), Vec3(1, 1, 1));
  EXPECT_EQ(entry_proxy(s, Vec3(2, 2, 0), true), Vec3(2, 2, 0));
  EXPECT_EQ(entry_proxy(s, Vec3(5, 2, -3), true), Vec3(2, 2, 0));
  entry_proxy(s, Vec3(5, 2, 1), false);
  EXPECT_EQ(entry_proxy(s, Vec3(6, 2, 0), true), Vec3(6, 2, 0));
}

}  // namespace test_servo
}  // namespace inhap::datadriven
