#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "inhap/contact/knee.hpp"
#include "inhap/core/random.hpp"

using namespace inhap;

namespace {

struct Signal {
  std::vector<double> t, f;
};

/// Flat (level a) until tk, then a ramp of `slope` N/s; 1 kHz samples from t0; Gaussian noise.
Signal two_slope(double t0, int n, double tk, double a, double slope, double sigma,
                 std::uint64_t seed) {
  Signal s;
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const double t = t0 + 1e-3 * i;
    s.t.push_back(t);
    s.f.push_back(a + (t > tk ? slope * (t - tk) : 0.0) + sigma * rng.normal());
  }
  return s;
}

/// Brute force: least squares on the hat basis with Eigen's QR for the knee at tc.
double brute_sse(const Signal& s, double tc, Vec3* g) {
  const int n = static_cast<int>(s.t.size());
  const double t0 = s.t.front(), td = s.t.back();
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double t = s.t[i];
    if (t <= tc) {
      phi(i, 0) = (tc - t) / (tc - t0);
      phi(i, 1) = (t - t0) / (tc - t0);
    } else {
      phi(i, 1) = (td - t) / (td - tc);
      phi(i, 2) = (t - tc) / (td - tc);
    }
    y[i] = s.f[i];
  }
  const Eigen::Vector3d sol = phi.colPivHouseholderQr().solve(y);
  if (g) *g = sol;
  return (phi * sol - y).squaredNorm();
}

}  // namespace

TEST(Knee, RecoversNonIntegerKinkOfNoiselessSignal) {
  const Signal s = two_slope(2.0, 101, 2.0 + 0.0637, 0.01, 8.0, 0.0, 1);
  const KneeFit fit = fit_knee(s.t, s.f);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.tc, 2.0637, 1e-6);
  EXPECT_NEAR(fit.g0, 0.01, 1e-6);
  EXPECT_NEAR(fit.gc, 0.01, 1e-6);
  EXPECT_NEAR(fit.gd, 0.01 + 8.0 * (0.1 - 0.0637), 1e-6);
  EXPECT_NEAR(fit.sse, 0.0, 1e-12);
  EXPECT_EQ(fit.index, 63u);
}

TEST(Knee, DiscreteMinimumIsOnASampleWithoutRefinement) {
  const Signal s = two_slope(0.0, 101, 0.0637, 0.0, 8.0, 0.0, 1);
  KneeOptions o;
  o.refine = false;
  const KneeFit fit = fit_knee(s.t, s.f, o);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.tc, 0.064, 1e-12);  // the sample nearest the kink wins here
}

TEST(Knee, RecoversKinkUnderNoiseWithinASample) {
  // Noise 0.01 N, ramp 10 N/s (0.01 N per sample), i.e. a soft object's force onset.
  int within = 0;
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    const double tk = 0.0403 + 0.0011 * static_cast<double>(seed);
    const Signal s = two_slope(0.0, 101, tk, 0.0, 10.0, 0.005, seed);
    const KneeFit fit = fit_knee(s.t, s.f);
    ASSERT_TRUE(fit.valid);
    worst = std::max(worst, std::abs(fit.tc - tk));
    within += std::abs(fit.tc - tk) < 2e-3;
  }
  EXPECT_GE(within, 45) << "worst " << worst;
  EXPECT_LT(worst, 6e-3);
}

TEST(Knee, ClosedFormMatchesBruteForceLeastSquaresAtEveryKnee) {
  const Signal s = two_slope(10.0, 60, 10.031, 0.05, 5.0, 0.02, 7);
  for (std::size_t k = 1; k + 1 < s.t.size(); ++k) {
    for (double frac : {0.0, 0.37}) {
      const double tc = s.t[k] + frac * (s.t[k + 1] - s.t[k]);
      Vec3 g_fast, g_brute;
      const double fast = knee_sse_at(s.t, s.f, tc, &g_fast);
      const double brute = brute_sse(s, tc, &g_brute);
      ASSERT_NEAR(fast, brute, 1e-9 * (1 + brute)) << "k=" << k;
      ASSERT_LT((g_fast - g_brute).norm(), 1e-8) << "k=" << k;
    }
  }
}

TEST(Knee, FitIsTheGlobalMinimumOfBruteForceOverAFineGrid) {
  const Signal s = two_slope(0.0, 101, 0.05123, 0.0, 6.0, 0.01, 11);
  const KneeFit fit = fit_knee(s.t, s.f);
  ASSERT_TRUE(fit.valid);
  double best = 1e300, best_t = 0;
  for (double tc = s.t[1]; tc < s.t[s.t.size() - 2]; tc += 1e-5) {
    const double e = brute_sse(s, tc, nullptr);
    if (e < best) best = e, best_t = tc;
  }
  EXPECT_LE(fit.sse, best + 1e-12);
  EXPECT_NEAR(fit.tc, best_t, 2e-5);
  EXPECT_NEAR(fit.sse, brute_sse(s, fit.tc, nullptr), 1e-12);
}

TEST(Knee, RejectsDegenerateInput) {
  std::vector<double> t{0, 1, 2}, f{0, 0, 1};
  EXPECT_FALSE(fit_knee(t, f).valid);
  std::vector<double> t2{0, 1, 1, 2, 3}, f2{0, 0, 1, 2, 3};
  EXPECT_FALSE(fit_knee(t2, f2).valid);
  std::vector<double> t3{0, 1, 2, 3, 4}, f3{0, 0, NAN, 2, 3};
  EXPECT_FALSE(fit_knee(t3, f3).valid);
}

TEST(Knee, ConstantSignalStillGivesAFiniteFit) {
  std::vector<double> t, f;
  for (int i = 0; i < 20; ++i) t.push_back(i * 1e-3), f.push_back(0.3);
  const KneeFit fit = fit_knee(t, f);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.sse, 0.0, 1e-20);
  EXPECT_GT(fit.tc, t.front());
  EXPECT_LT(fit.tc, t.back());
}
