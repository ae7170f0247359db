// FOAW velocity estimation against analytic velocities.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/foaw.hpp"

namespace inhap::datadriven {
namespace {

double quantise(double y, double q) {
  return std::round(y / q) * q;
}

struct SineRun {
  double rms_foaw = 0, rms_fd = 0, amplitude_v = 0;
};

// Sine of amplitude `amp` mm and frequency `hz` along x, quantised to `q` mm, 1 kHz.
SineRun run_sine(double amp, double hz, double q, const FoawParams& prm) {
  FoawState st;
  const double w = 2 * std::numbers::pi * hz;
  double sf = 0, sd = 0, prev = 0;
  int n = 0;
  for (int k = 0; k < 5000; ++k) {
    const double t = k * prm.dt_s;
    const double y = quantise(amp * std::sin(w * t), q);
    const Vec3 v = foaw_step(prm, st, Vec3(y, 0, 0));
    const double truth = amp * w * std::cos(w * t);
    if (k >= 100) {  // after the window has filled
      sf += (v.x() - truth) * (v.x() - truth);
      const double fd = (y - prev) / prm.dt_s;
      sd += (fd - truth) * (fd - truth);
      ++n;
    }
    prev = y;
  }
  return {std::sqrt(sf / n), std::sqrt(sd / n), amp * w};
}

TEST(Foaw, QuantisedSineWithinFivePercentOfVelocityAmplitude) {
  FoawParams prm;
  prm.dt_s = 1e-3;
  prm.max_window = 16;
  prm.noise_bound_mm = 0.01;
  for (double hz : {0.5, 1.0, 2.0, 4.0}) {  // 10 mm amplitude: 31 to 251 mm/s peak velocity
    const SineRun r = run_sine(10.0, hz, 0.01, prm);
    SCOPED_TRACE(hz);
    EXPECT_LT(r.rms_foaw, 0.05 * r.amplitude_v);
    // At slow motion the plain finite difference misses the same bound on the same data.
    if (hz <= 1.0) {
      EXPECT_GT(r.rms_fd, 0.05 * r.amplitude_v);
    }
  }
}

TEST(Foaw, ConstantVelocityIsExactAndUsesTheLongestWindow) {
  FoawParams prm;
  prm.max_window = 20;
  prm.noise_bound_mm = 1e-9;
  FoawState st;
  const Vec3 v0(12.5, -3.0, 0.25);  // mm/s
  Vec3 v = Vec3::Zero();
  for (int k = 0; k < 50; ++k) v = foaw_step(prm, st, Vec3(1, 2, 3) + v0 * (k * prm.dt_s));
  EXPECT_NEAR((v - v0).norm(), 0.0, 1e-6);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(st.window[static_cast<std::size_t>(a)], 20);
}

TEST(Foaw, WindowShrinksAtAVelocityStep) {
  FoawParams prm;
  prm.max_window = 30;
  prm.noise_bound_mm = 1e-6;
  FoawState st;
  double y = 0;
  Vec3 v;
  for (int k = 0; k < 60; ++k) {  // 10 mm/s, then 50 mm/s from sample 40
    y += (k < 40 ? 10.0 : 50.0) * prm.dt_s;
    v = foaw_step(prm, st, Vec3(y, 0, 0));
    if (k == 45) {
      EXPECT_NEAR(v.x(), 50.0, 1e-3);  // only the post-step samples fit a line
      EXPECT_LE(st.window[0], 6);
    }
  }
  EXPECT_NEAR(v.x(), 50.0, 1e-3);
}

TEST(Foaw, NonFiniteInputResetsAndGivesZero) {
  FoawParams prm;
  FoawState st;
  for (int k = 0; k < 10; ++k) foaw_step(prm, st, Vec3(k * 0.01, 0, 0));
  const Vec3 v = foaw_step(prm, st, Vec3(std::nan(""), 0, 0));
  EXPECT_EQ(v, Vec3::Zero());
  EXPECT_EQ(st.count, 0);
  EXPECT_EQ(foaw_step(prm, st, Vec3(1, 1, 1)), Vec3::Zero());  // first sample after reset
}

TEST(Foaw, ValidateRejectsBadParameters) {
  FoawParams p;
  p.max_window = kFoawMaxWindow;
  EXPECT_THROW(p.validate(), Error);
  p = FoawParams{};
  p.dt_s = 0;
  EXPECT_THROW(p.validate(), Error);
  p = FoawParams{};
  p.noise_bound_mm = -1;
  EXPECT_THROW(p.validate(), Error);
  EXPECT_NO_THROW(FoawParams{}.validate());
}

// A filter trained at one rate, run at another: the window keeps its length in seconds and the
// velocity of a constant motion comes out right at the new rate (at the old dt it is off by the
// ratio of the rates).
TEST(Foaw, AtPeriodKeepsTheWindowInSecondsAndTheVelocity) {
  const FoawParams at66{1.0 / 66, 1, 0.01};
  const FoawParams at1k = at66.at_period(1e-3);
  EXPECT_DOUBLE_EQ(at1k.dt_s, 1e-3);
  EXPECT_EQ(at1k.max_window, 15);  // 15.2 ms
  EXPECT_EQ((FoawParams{1e-3, 16, 0.01}.at_period(1.0 / 66).max_window), 1);
  EXPECT_EQ((FoawParams{1e-3, 63, 0.01}.at_period(1e-5).max_window), kFoawMaxWindow - 1);
  for (double same : {1e-3 * 1.005, 1e-3 * 0.995, 0.0, -1.0, std::nan(""), HUGE_VAL}) {
    const FoawParams p = FoawParams{}.at_period(same);
    EXPECT_EQ(p.dt_s, FoawParams{}.dt_s) << same;
    EXPECT_EQ(p.max_window, FoawParams{}.max_window) << same;
  }
  // 12 mm/s sampled at 1 kHz.
  FoawState right, wrong;
  Vec3 v_right = Vec3::Zero(), v_wrong = Vec3::Zero();
  for (int i = 0; i < 100; ++i) {
    const Vec3 p(12.0 * i * 1e-3, 0, 0);
    v_right = foaw_step(at1k, right, p);
    v_wrong = foaw_step(at66, wrong, p);
  }
  EXPECT_NEAR(v_right.x(), 12.0, 1e-9);
  EXPECT_NEAR(v_wrong.x(), 12.0 * 66e-3, 1e-9);  // what a 66 Hz model saw before
}

}  // namespace
}  // namespace inhap::datadriven
