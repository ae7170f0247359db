#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "inhap/contact/offline_compensation.hpp"
#include "inhap/core/random.hpp"

using namespace inhap;

TEST(OfflineCompensation, AccelerationOfAParabolaIsExact) {
  std::vector<double> t;
  std::vector<Vec3> p;
  for (int i = 0; i < 50; ++i) {
    const double s = 0.3 + 1e-3 * i + (i % 3) * 1e-5;  // slightly irregular sampling
    t.push_back(s);
    p.emplace_back(0.5 * 800.0 * s * s, -2.0 * s, 3.0 - 0.5 * 120.0 * s * s);
  }
  const auto a = estimate_acceleration(t, p, 5);
  for (const Vec3& v : a) {
    EXPECT_NEAR(v.x(), 800.0, 1e-5);
    EXPECT_NEAR(v.y(), 0.0, 1e-5);
    EXPECT_NEAR(v.z(), -120.0, 1e-5);
  }
}

TEST(OfflineCompensation, RecoversToolMassOffsetAndContactForce) {
  // Tool of 25 g, sensor bias, an oscillating free motion (up to 4 m/s^2) and contact pulses.
  const double m = 0.025;
  const Vec3 g(0, 0, -9810.0), bias(0.03, -0.02, 0.05);
  Rng rng(5);
  std::vector<double> t;
  std::vector<Vec3> p, raw, f_true;
  for (int i = 0; i < 6000; ++i) {
    const double s = 1e-3 * i, w = 2 * std::numbers::pi * 3.0;
    const Vec3 pos(20 * std::sin(w * s), 10 * std::cos(0.7 * w * s), 30 * std::sin(0.5 * w * s));
    const Vec3 acc(-20 * w * w * std::sin(w * s), -10 * 0.49 * w * w * std::cos(0.7 * w * s),
                   -30 * 0.25 * w * w * std::sin(0.5 * w * s));
    const bool contact = (i / 500) % 3 == 1;  // a third of the time in contact
    const Vec3 f = contact ? Vec3(0.2, 0.1, 1.5 + std::sin(0.01 * i)) : Vec3::Zero();
    const Vec3 noise(0.004 * rng.normal(), 0.004 * rng.normal(), 0.004 * rng.normal());
    t.push_back(s);
    p.push_back(pos + Vec3(1e-3 * rng.normal(), 0, 0));  // encoder noise
    raw.push_back(f + 1e-3 * m * (g - acc) + bias + noise);
    f_true.push_back(f);
  }
  const OfflineCompensation c = fit_offline_compensation(t, p, raw);
  EXPECT_NEAR(c.mass_kg, m, 5e-4);
  EXPECT_LT((c.offset - (1e-3 * m * g + bias)).norm(), 2e-3);
  EXPECT_NEAR(static_cast<double>(c.free_samples), 4000.0, 200.0);
  const auto f = apply_offline_compensation(raw, estimate_acceleration(t, p, 8), c);
  double worst = 0;
  for (std::size_t i = 20; i + 20 < f.size(); ++i) {
    if (i % 500 < 20 || i % 500 > 480) continue;  // the force steps themselves
    worst = std::max(worst, (f[i] - f_true[i]).norm());
  }
  EXPECT_LT(worst, 0.03);
}
