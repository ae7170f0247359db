// Sensor compensation against synthetic streams whose true contact force is known (zero in
// free air, a constant in static contact).
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/contact/compensation.hpp"
#include "inhap/core/random.hpp"

namespace inhap {
namespace {

constexpr double kMass = 0.01;  // kg
const Vec3 kG(0, 0, -9810.0);

/// Hand-like free motion: sums of sinusoids (0.5-3 Hz, tens of mm), with its exact
/// acceleration.
struct Motion {
  Vec3 amp[3], freq[3], phase[3];
  explicit Motion(Rng& rng) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        amp[i][k] = rng.uniform(3.0, 15.0);
        freq[i][k] = rng.uniform(0.5, 3.0);
        phase[i][k] = rng.uniform(0, 2 * M_PI);
      }
  }
  Vec3 pos(double t) const {
    Vec3 p(0, 0, 50);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        p[k] += amp[i][k] * std::sin(2 * M_PI * freq[i][k] * t + phase[i][k]);
    return p;
  }
  Vec3 acc(double t) const {
    Vec3 a = Vec3::Zero();
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        const double w = 2 * M_PI * freq[i][k];
        a[k] -= amp[i][k] * w * w * std::sin(w * t + phase[i][k]);
      }
    return a;
  }
};

Vec3 quantise(const Vec3& p) {
  return Vec3(((p / 0.01).array().round() * 0.01).matrix());
}

TEST(Compensation, StaticToolReadsZeroAfterGravityRemoval) {
  CompensatorConfig cfg;
  cfg.tool_mass_kg = kMass;
  CompensatorState st;
  const Vec3 raw = kMass * 1e-3 * kG;  // tool weight only: -0.0981 N in z
  for (int i = 0; i < 100; ++i) {
    const Vec3 f = compensate_step(cfg, st, Vec3(1, 2, 3), raw);
    EXPECT_NEAR(f.norm(), 0.0, 1e-15);
  }
}

TEST(Compensation, AccelerationEstimateMatchesAnalyticMotion) {
  Rng rng(7);
  Motion m(rng);
  CompensatorConfig cfg;
  cfg.tool_mass_kg = kMass;
  CompensatorState st;
  const double delay = cfg.delay_samples() * 1e-3;
  double worst = 0;
  for (int i = 0; i < 5000; ++i) {
    const double t = i * 1e-3;
    compensate_step(cfg, st, m.pos(t), Vec3::Zero());
    if (i > 50) worst = std::max(worst, (st.acceleration - m.acc(t - delay)).norm());
  }
  // Unquantised positions: only the estimator's smoothing error remains (mm/s^2).
  EXPECT_LT(worst, 60.0);
}

TEST(Compensation, SixtySecondsOfFreeMotionReadBelow50mN) {
  Rng rng(11);
  Motion m(rng);
  CompensatorConfig cfg;
  cfg.tool_mass_kg = kMass;
  cfg.gravity_mm_s2 = kG;
  CompensatorState st;
  double worst_comp = 0, worst_raw = 0, peak_inertia = 0;
  for (int i = 0; i < 60000; ++i) {
    const double t = i * 1e-3;
    const Vec3 a = m.acc(t);
    Vec3 noise(rng.normal(0, 0.005), rng.normal(0, 0.005), rng.normal(0, 0.005));
    const Vec3 raw = noise + kMass * 1e-3 * (kG - a);  // no contact: true force is zero
    const Vec3 f = compensate_step(cfg, st, quantise(m.pos(t)), raw);
    if (i >= 20) worst_comp = std::max(worst_comp, f.norm());
    worst_raw = std::max(worst_raw, raw.norm());
    peak_inertia = std::max(peak_inertia, kMass * 1e-3 * a.norm());
  }
  EXPECT_GT(peak_inertia, 0.02);  // the motion really shakes the tool
  EXPECT_LT(worst_comp, 0.05);
  EXPECT_GT(worst_raw, 0.09);
  std::printf("free motion: max |f| compensated %.4f N, raw %.4f N, peak m*a %.4f N\n", worst_comp,
              worst_raw, peak_inertia);
}

TEST(Compensation, NonFiniteInputGivesZeroAndResets) {
  CompensatorConfig cfg;
  cfg.tool_mass_kg = kMass;
  CompensatorState st;
  for (int i = 0; i < 30; ++i) compensate_step(cfg, st, Vec3(i, 0, 0), Vec3::Zero());
  EXPECT_GT(st.count, 0);
  const Vec3 f = compensate_step(cfg, st, Vec3(NAN, 0, 0), Vec3(1, 1, 1));
  EXPECT_EQ(f, Vec3::Zero());
  EXPECT_EQ(st.count, 0);
  EXPECT_EQ(compensate_step(cfg, st, Vec3::Zero(), Vec3(INFINITY, 0, 0)), Vec3::Zero());
}

TEST(Compensation, BatchEqualsStepsAndCenteredRemovesLag) {
  Rng rng(3);
  Motion m(rng);
  CompensatorConfig cfg;
  cfg.tool_mass_kg = 0.05;
  std::vector<Vec3> p, raw;
  for (int i = 0; i < 3000; ++i) {
    const double t = i * 1e-3;
    p.push_back(m.pos(t));
    raw.push_back(0.05 * 1e-3 * (cfg.gravity_mm_s2 - m.acc(t)));
  }
  const auto causal = compensate(cfg, p, raw, false);
  const auto centered = compensate(cfg, p, raw, true);
  CompensatorState st;
  double err_causal = 0, err_centered = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(causal[i], compensate_step(cfg, st, p[i], raw[i]));
    if (i > 50 && i + 50 < p.size()) {
      err_causal = std::max(err_causal, causal[i].norm());
      err_centered = std::max(err_centered, centered[i].norm());
    }
  }
  EXPECT_LT(err_centered, 0.3 * err_causal);
}

}  // namespace
}  // namespace inhap
