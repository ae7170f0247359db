// The force limit belongs to the device profile: no model file, rendering parameter or flag
// raises a rendered force past it (issue 20), and the data-driven servo has a jump guard.
#include <gtest/gtest.h>

#include <string>

#include "datadriven/dd_fixtures.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/servo.hpp"
#include "inhap/lab/sim_device.hpp"
#include "inhap/rendering/renderer.hpp"
#include "support/meshes.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

const datadriven::ForceModel& model() {
  static const datadriven::ForceModel m = [] {
    const datadriven::TrainingSet s =
        datadriven::test::take(datadriven::test::synthetic_set(2, 8000), 0, 2);
    datadriven::TrainParams p = datadriven::test::small_params();
    p.design = datadriven::Design::kRegression;
    return datadriven::train_force_model(s, p);
  }();
  return m;
}

TEST(ForceLimit, EffectiveLimitNeverAboveTheDevice) {
  EXPECT_EQ(effective_force_limit(3.0), 3.0);
  EXPECT_EQ(effective_force_limit(1e9), kDeviceForceLimitN);
  EXPECT_EQ(effective_force_limit(std::nan("")), kDeviceForceLimitN);
  EXPECT_EQ(effective_force_limit(-1), kDeviceForceLimitN);
  EXPECT_EQ(effective_force_limit(20, 30), 20);
  EXPECT_EQ(effective_force_limit(1e9, 1e9), kDeviceForceLimitN);  // profile over the ceiling
  EXPECT_LE(kDeviceForceLimitN, kForceCeilingN);
}

TEST(ForceLimit, ModelStructCannotRaiseTheClamp) {
  datadriven::ForceModel m = model();
  m.force_limit_n = 1e9;  // built in code, never validated
  // Far outside the training range the model's own force exceeds the device's limit; every
  // output stays within it and some reach it (the clamp, not the model, decided).
  Rng rng(4);
  double largest = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-100, 0));
    const Vec3 q = p + Vec3(rng.uniform(-80, 80), rng.uniform(-80, 80), rng.uniform(0, 80));
    const Vec3 v(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3));
    const double f = datadriven::model_force(m, p, v, q).norm();
    ASSERT_LE(f, kDeviceForceLimitN * (1 + 1e-12)) << i;
    largest = std::max(largest, f);
  }
  EXPECT_NEAR(largest, kDeviceForceLimitN, 1e-9);
  m.force_limit_n = 2.0;  // lowering works
  rng = Rng(4);
  double lowered = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-100, 0));
    const Vec3 q = p + Vec3(rng.uniform(-80, 80), rng.uniform(-80, 80), rng.uniform(0, 80));
    const Vec3 v(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3));
    lowered = std::max(lowered, datadriven::model_force(m, p, v, q).norm());
  }
  EXPECT_NEAR(lowered, 2.0, 1e-9);
}

TEST(ForceLimit, ModelFileAboveTheDeviceIsRejected) {
  test::TempDir dir;
  std::string text = datadriven::force_model_to_json(model());
  const std::string key = "\"force_limit_n\": ";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  const auto end = text.find_first_of(",\n", at);
  text.replace(at, end - at, key + "1000000000.0");
  write_file_atomic(dir.path("m.json"), text);
  try {
    datadriven::load_force_model(dir.path("m.json"));
    FAIL() << "a model file raised the force limit to 1e9 N";
  } catch (const ParseError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("m.json"), std::string::npos) << w;
    EXPECT_NE(w.find("force_limit_n"), std::string::npos) << w;
  }
  datadriven::ForceModel lower = model();
  lower.force_limit_n = 1.5;  // a model may lower the limit
  datadriven::save_force_model(dir.path("low.json"), lower);
  EXPECT_EQ(datadriven::load_force_model(dir.path("low.json")).force_limit_n, 1.5);
}

TEST(ForceLimit, RenderingParamsAndDeviceProfilesAreCapped) {
  rendering::Params prm;
  prm.force_limit_n = 1000;
  EXPECT_THROW((void)rendering::Model(test::make_grid_mesh(4, 4, 10.0), prm), Error);
  const lab::SoftObject block(lab::BoxShape{Vec3(0, 0, 10), Vec3(20, 20, 10)}, lab::ContactLaw{});
  lab::DeviceParams dp;
  dp.max_force_n = 1e6;
  EXPECT_THROW((void)lab::SimDevice(block, dp), Error);
  dp.max_force_n = kForceCeilingN;
  EXPECT_NO_THROW((void)lab::SimDevice(block, dp));
}

TEST(ForceLimit, TrainFlagAboveTheDeviceIsAFlagError) {
  const auto r =
      test::run_cli("model train --recording none.csv --out none.json --force-limit 1000");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error:", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("--force-limit"), std::string::npos) << r.out;
}

// --- the data-driven servo's jump guard ------------------------------------------------------

TEST(ServoJumpGuard, OneTickJumpGivesZeroAndAFreshState) {
  const Vec3 q(0, 0, 0);
  datadriven::ServoState st;
  Vec3 p(0, 0, -3);
  for (int i = 0; i < 50; ++i) datadriven::servo_step(model(), st, p, q, true);
  const Vec3 held = datadriven::servo_step(model(), st, p, q, true);
  ASSERT_GT(held.norm(), 0.1);
  const Vec3 far = p + Vec3(0, 0, -50);  // a 50 mm glitch in one tick
  EXPECT_EQ(datadriven::servo_step(model(), st, far, far + Vec3(0, 0, 3), true), Vec3::Zero());
  // Afterwards the servo renders as a new state fed the same samples from the glitch on.
  datadriven::ServoState fresh;
  datadriven::servo_step(model(), fresh, far, far + Vec3(0, 0, 3), true);
  for (int i = 1; i <= 20; ++i) {
    const Vec3 pi = far + Vec3(0.01 * i, 0, 0), qi = far + Vec3(0, 0, 3);
    const Vec3 a = datadriven::servo_step(model(), st, pi, qi, true);
    const Vec3 b = datadriven::servo_step(model(), fresh, pi, qi, true);
    ASSERT_EQ(a, b) << "tick " << i;
  }
  // Legal motion (1 mm per tick = 1 m/s) does not trip the guard.
  datadriven::ServoState legal;
  const std::uint32_t before = legal.resets;
  for (int i = 0; i < 30; ++i)
    datadriven::servo_step(model(), legal, Vec3(i * 1.0, 0, -3), q, true);
  EXPECT_EQ(legal.resets, before);
}

}  // namespace
}  // namespace inhap
