// Loading profile, palpation protocol and elastic border on a device whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "friction/fake_device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/loading_profile.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"

namespace inhap::friction {
namespace {

TEST(LoadingProfile, SineRampsPlateauAndDurations) {
  ProfileRates rates;
  rates.normal_rate = 10.0;
  rates.tangential_rate = 5.0;
  const LoadingProfile p(3.0, 1.0, 0.6, rates);
  EXPECT_DOUBLE_EQ(p.t_normal(), 0.3);
  EXPECT_DOUBLE_EQ(p.t_tangential(), 0.2);
  EXPECT_DOUBLE_EQ(p.duration(), 2 * 0.3 + 2 * 0.2 + 0.6);
  EXPECT_DOUBLE_EQ(p.t_measurement(), 0.3 + 0.2 + 0.09);
  // Half-way up each ramp the sine profile is at half force, with zero slope at the ends.
  EXPECT_NEAR(p.normal(0.15), 1.5, 1e-12);
  EXPECT_NEAR(p.tangential(0.3), 0.0, 1e-12);
  EXPECT_NEAR(p.tangential(0.4), 0.5, 1e-12);
  EXPECT_NEAR(p.normal(1e-4), 3.0 * 0.5 * (1 - std::cos(std::numbers::pi * 1e-4 / 0.3)), 1e-15);
  // Plateau: both at their maxima; the normal force stays up while f_T unloads.
  for (double t = 0.5; t <= 1.1; t += 0.05) {
    EXPECT_DOUBLE_EQ(p.normal(t), 3.0);
    EXPECT_DOUBLE_EQ(p.tangential(t), 1.0);
  }
  EXPECT_NEAR(p.tangential(1.2), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(p.normal(1.3), 3.0);
  EXPECT_NEAR(p.normal(1.45), 1.5, 1e-12);
  EXPECT_DOUBLE_EQ(p.normal(1.6), 0.0);
  EXPECT_DOUBLE_EQ(p.tangential(-1.0), 0.0);
  // Fixed rates: twice the force, twice the ramp.
  const LoadingProfile q(6.0, 2.0, 0.1, rates);
  EXPECT_DOUBLE_EQ(q.t_normal(), 0.6);
  EXPECT_DOUBLE_EQ(q.t_tangential(), 0.4);
  // Measurement clamped into a short plateau.
  EXPECT_DOUBLE_EQ(LoadingProfile(1, 1, 0.05, rates).t_measurement(), 0.1 + 0.2 + 0.05);
}

TEST(TangentBasis, OrthonormalAndFollowsReference) {
  Vec3 t0, t1;
  const Vec3 n = Vec3(0.2, -0.3, 1.0).normalized();
  tangent_basis(n, Vec3::UnitX(), t0, t1);
  EXPECT_NEAR(t0.dot(n), 0, 1e-12);
  EXPECT_NEAR(t1.dot(n), 0, 1e-12);
  EXPECT_NEAR(t0.norm(), 1, 1e-12);
  EXPECT_NEAR(t0.cross(t1).dot(n), 1, 1e-12);
  EXPECT_GT(t0.x(), 0.9);
  tangent_basis(Vec3::UnitX(), Vec3::UnitX(), t0, t1);  // reference parallel to n: fallback
  EXPECT_NEAR(t0.dot(Vec3::UnitX()), 0, 1e-12);
  EXPECT_NEAR(t0.norm(), 1, 1e-12);
}

PalpationConfig small_config() {
  PalpationConfig c;
  c.normal_forces = {1.0};
  c.directions = 1;
  c.tangential_step = 0.3;  // a single step: f_T = 0.3 N
  c.max_ratio = 0.3;
  c.plateaus = {0.1};
  return c;
}

TEST(Palpation, SingleElasticCycleMeasuresTheKnownSpring) {
  test::FakeContactParams prm;
  prm.sensor_bias = Vec3(0.05, -0.02, 0.1);  // removed by the tare at the hover point
  test::FakeContactDevice dev(prm, Vec3(3, -2, 10));
  PalpationProtocol proto(small_config(), dev.info(), 4, Vec3(0, 0, 0), Vec3::UnitZ());
  const long ticks = run_protocol(dev, proto, 200000);
  ASSERT_TRUE(proto.done());
  ASSERT_FALSE(proto.failed()) << proto.error();
  EXPECT_LT(ticks, 5000);
  ASSERT_EQ(proto.cycles().size(), 1u);
  const CycleRecord& c = proto.cycles()[0];
  EXPECT_EQ(c.point, 4);
  EXPECT_EQ(c.status, CycleStatus::kOk);
  EXPECT_NEAR(c.pc.z(), 0.0, 0.1);  // touched the plane
  EXPECT_NEAR(c.pc.x(), 0.0, 0.1);
  // Loaded 1 N into the plane and 0.3 N along t_0 = x: known spring answers.
  EXPECT_NEAR(c.f_meas.z(), 1.0, 0.03);
  EXPECT_NEAR(c.f_meas.x(), -0.3, 0.03);
  EXPECT_NEAR(-c.u_meas.z(), 1.0 / prm.k_normal, 0.05);
  EXPECT_NEAR(c.u_meas.x(), 0.3 / prm.k_tangential, 0.03);
  // Below mu f_N: no slip, the probe returns to p_c.
  EXPECT_LT(c.up_tangential(), 0.01);
  // The protocol ends hovering above the reference point.
  EXPECT_NEAR(dev.true_position().z(), 2.0, 0.1);
}

TEST(Palpation, SlidingCycleLeavesPlasticDisplacementGrowingWithPlateau) {
  PalpationConfig cfg = small_config();
  cfg.tangential_step = 0.8;  // mu = 0.5: sliding
  cfg.max_ratio = 0.8;
  cfg.half_step = false;
  cfg.plateaus = {0.1, 0.6};
  test::FakeContactDevice dev;
  PalpationProtocol proto(cfg, dev.info(), 0, Vec3(0, 0, 0), Vec3::UnitZ());
  run_protocol(dev, proto, 200000);
  ASSERT_EQ(proto.cycles().size(), 2u);
  const double u100 = proto.cycles()[0].up_tangential(), u600 = proto.cycles()[1].up_tangential();
  EXPECT_GT(u100, 0.3);
  // Viscous sliding at (f_T - mu f_N) / (creep + damping) for the extra 0.5 s of plateau.
  const double speed = (0.8 - 0.5) / (0.05 + cfg.load_damping + 0.002);
  EXPECT_NEAR(u600 - u100, 0.5 * speed, 0.15 * 0.5 * speed);
}

TEST(Palpation, NoSurfaceFailsCleanly) {
  test::FakeContactDevice dev;
  PalpationProtocol proto(small_config(), dev.info(), 0, Vec3(0, 0, 20), Vec3::UnitZ());
  run_protocol(dev, proto, 100000);
  EXPECT_TRUE(proto.done());
  EXPECT_TRUE(proto.failed());
  ASSERT_EQ(proto.cycles().size(), 1u);
  EXPECT_EQ(proto.cycles()[0].status, CycleStatus::kNoContact);
}

TEST(Palpation, NanReadingStops) {
  PalpationProtocol proto(small_config(), DeviceInfo{}, 0, Vec3::Zero(), Vec3::UnitZ());
  const Vec3 f = proto.step(0.0, Vec3(NAN, 0, 0), Vec3::Zero());
  EXPECT_EQ(f, Vec3::Zero());
  EXPECT_TRUE(proto.done());
  EXPECT_TRUE(proto.failed());
}

TEST(Palpation, RejectsBadConfig) {
  PalpationConfig c = small_config();
  c.tangential_step = -0.1;
  EXPECT_THROW(PalpationProtocol(c, DeviceInfo{}, 0, Vec3::Zero(), Vec3::UnitZ()), Error);
  EXPECT_THROW(PalpationProtocol(small_config(), DeviceInfo{}, 0, Vec3::Zero(), Vec3::Zero()),
               Error);
}

// The known answer of the whole pipeline: on a uniform Coulomb object every fitted elastic
// limit equals mu * f_N.
TEST(Palpation, FullSweepOnUniformCoulombFitsMuTimesFn) {
  test::FakeContactParams prm;
  prm.mu = 0.45;
  prm.encoder = 0.005;
  prm.sensor_noise = 0.005;
  test::FakeContactDevice dev(prm);
  PalpationConfig cfg;  // 1, 3, 5 N x 8 directions x f_T steps x 2 plateaus
  PalpationProtocol proto(cfg, dev.info(), 0, Vec3(0, 0, 0), Vec3::UnitZ());
  run_protocol(dev, proto, 5'000'000);
  ASSERT_TRUE(proto.done());
  ASSERT_FALSE(proto.failed()) << proto.error();
  const SysModel m = fit_sys(proto.cycles());
  ASSERT_EQ(m.points.size(), 1u);
  ASSERT_EQ(m.f_normal_levels.size(), 3u);
  ASSERT_EQ(m.angles.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_NEAR(m.angles[k], k * std::numbers::pi / 4, 1e-6);
  double worst = 0;
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t k = 0; k < 8; ++k) {
      const SysBorder& b = m.border(0, j, k);
      const double truth = prm.mu * b.f_normal;
      const double rel = std::abs(b.result.f_limit - truth) / truth;
      worst = std::max(worst, rel);
      EXPECT_LT(rel, 0.05) << "f_N " << b.f_normal << " dir " << k << " f_limit "
                           << b.result.f_limit;
      // Elastic limit displacement: depth f_N / k_n, tangential mu f_N / k_t.
      EXPECT_NEAR(b.result.depth, b.f_normal / prm.k_normal, 0.05 * b.f_normal);
      EXPECT_NEAR(b.result.radius, truth / prm.k_tangential, 0.08 * truth / prm.k_tangential);
    }
  // Creep: growth = 0.5 s * excess / (c_v + device damping + load damping).
  EXPECT_NEAR(m.points[0].creep_viscosity, prm.creep + prm.device_damping, 0.1 * prm.creep);
  EXPECT_NEAR(m.points[0].tangential_stiffness, prm.k_tangential, 0.05 * prm.k_tangential);
  RecordProperty("worst_limit_rel_error", std::to_string(worst));
  RecordProperty("cycles", std::to_string(proto.cycles().size()));
}

}  // namespace
}  // namespace inhap::friction

namespace inhap::friction {
namespace {

// mu = 0.9: at 5 N the border (4.5 N) lies beyond the device (|f_l| <= 6 N allows f_T <= 3.3 N);
// the fit extrapolates it from the 1 N level with the same ratio.
TEST(Palpation, BorderBeyondTheForceRangeIsExtrapolated) {
  test::FakeContactParams prm;
  prm.mu = 0.9;
  test::FakeContactDevice dev(prm);
  PalpationConfig cfg;
  cfg.normal_forces = {1.0, 5.0};
  cfg.directions = 2;
  PalpationProtocol proto(cfg, dev.info(), 0, Vec3(0, 0, 0), Vec3::UnitZ());
  run_protocol(dev, proto, 5'000'000);
  const SysModel m = fit_sys(proto.cycles());
  for (std::size_t k = 0; k < 2; ++k) {
    const BorderResult& lo = m.border(0, 0, k).result;
    const BorderResult& hi = m.border(0, 1, k).result;
    EXPECT_FALSE(lo.no_sliding);
    EXPECT_NEAR(lo.f_limit, 0.9, 0.05 * 0.9);
    EXPECT_TRUE(hi.no_sliding);
    EXPECT_TRUE(hi.extrapolated);
    EXPECT_NEAR(hi.f_limit, 4.5, 0.05 * 4.5);
    EXPECT_NEAR(hi.radius, 4.5 / prm.k_tangential, 0.06 * 4.5 / prm.k_tangential);
  }
}

}  // namespace
}  // namespace inhap::friction
