// Weighted k-means and elastic-border detection against known answers.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/friction/elastic_border.hpp"

namespace inhap::friction {
namespace {

TEST(WeightedKMeans, SeparatesTwoKnownClusters) {
  std::vector<Vec2> x = {{0, 0}, {0.1, 0}, {0, 0.1}, {5, 5}, {5.1, 5}, {5, 5.2}};
  std::vector<Vec2> c = {x[0], x[5]};
  const auto lab = weighted_kmeans(x, {}, Vec2(1, 1), c);
  EXPECT_EQ(lab, (std::vector<int>{0, 0, 0, 1, 1, 1}));
  EXPECT_NEAR(c[0].x(), 0.1 / 3, 1e-12);
  EXPECT_NEAR(c[1].y(), 15.2 / 3, 1e-12);
}

TEST(WeightedKMeans, FeatureWeightsDecideTheSplit) {
  // Two groupings are possible: by the first or by the second coordinate.
  std::vector<Vec2> x = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
  std::vector<Vec2> c1 = {{0, 0}, {1, 1}};
  EXPECT_EQ(weighted_kmeans(x, {}, Vec2(10, 1), c1), (std::vector<int>{0, 0, 1, 1}));
  std::vector<Vec2> c2 = {{0, 0}, {1, 1}};
  EXPECT_EQ(weighted_kmeans(x, {}, Vec2(1, 10), c2), (std::vector<int>{0, 1, 0, 1}));
}

TEST(WeightedKMeans, SampleWeightsPullTheCentroid) {
  std::vector<Vec2> x = {{0, 0}, {1, 0}, {10, 0}};
  std::vector<Vec2> c = {{0, 0}, {10, 0}};
  const std::vector<double> w = {1.0, 3.0, 1.0};
  weighted_kmeans(x, w, Vec2(1, 1), c);
  EXPECT_NEAR(c[0].x(), 0.75, 1e-12);
}

// Thesis Table 4.1 (f_N = 1 N): the text puts the border after f_T = 1.19 N.
TEST(ElasticBorder, ThesisTable41BorderAfter119N) {
  const double ft[] = {0.09, 0.27, 0.47, 0.70, 1.00, 1.19, 1.33, 1.43, 1.54, 1.66};
  const double u100[] = {0.087, 0.18, 0.35, 0.45, 0.56, 0.94, 1.21, 1.20, 1.74, 2.27};
  const double u600[] = {0.08, 0.18, 0.35, 0.46, 0.58, 0.95, 1.34, 1.53, 2.23, 3.43};
  std::vector<BorderStep> s;
  for (int i = 0; i < 10; ++i) {
    BorderStep b;
    b.f_tangential = ft[i];
    b.u_short = u100[i];
    b.u_long = u600[i];
    b.radius = 0.5 * ft[i];
    b.depth = 1.0;
    s.push_back(b);
  }
  const BorderResult r = find_elastic_border(s);
  EXPECT_EQ(r.split, 6u);  // 1.33 N is the first sliding step
  EXPECT_GT(r.f_limit, 1.19);
  EXPECT_LT(r.f_limit, 1.33);
  EXPECT_FALSE(r.no_sliding);
  EXPECT_NEAR(r.radius, 0.5 * r.f_limit, 1e-12);
  EXPECT_DOUBLE_EQ(r.depth, 1.0);
}

std::vector<BorderStep> creep_sweep(double limit, double step, int n, double noise_seed = 0) {
  // Viscous creep past the limit: growth = 0.5 s * (f_T - limit) / c, u100 grows too.
  std::vector<BorderStep> s;
  for (int i = 1; i <= n; ++i) {
    BorderStep b;
    b.f_tangential = step * i;
    const double excess = std::max(0.0, b.f_tangential - limit);
    const double wiggle = noise_seed * ((i * 7919) % 13 - 6) / 6.0;  // deterministic +-noise
    b.u_short = 0.3 * excess / 0.05 + 0.01 * b.f_tangential + wiggle;
    b.u_long = b.u_short + 0.5 * excess / 0.05 + wiggle;
    b.depth = 2.0;
    b.radius = std::min(b.f_tangential, limit) / 0.8 + 0.3 * excess / 0.05;
    s.push_back(b);
  }
  return s;
}

TEST(ElasticBorder, LinearCreepGivesTheExactLimit) {
  for (double limit : {0.23, 0.45, 0.61, 1.37}) {
    const auto s = creep_sweep(limit, 0.1, 20);
    const BorderResult r = find_elastic_border(s);
    EXPECT_NEAR(r.f_limit, limit, 1e-9) << limit;
    EXPECT_NEAR(r.radius, limit / 0.8, 1e-9);  // elastic tangential displacement at the limit
    EXPECT_EQ(s[r.split].f_tangential, std::ceil(limit / 0.1 - 1e-9) * 0.1);
  }
}

TEST(ElasticBorder, RobustToSmallNoise) {
  const auto s = creep_sweep(0.45, 0.1, 12, 0.005);
  const BorderResult r = find_elastic_border(s);
  EXPECT_NEAR(r.f_limit, 0.45, 0.02);
}

TEST(ElasticBorder, NoSlidingIsALowerBound) {
  const auto s = creep_sweep(5.0, 0.1, 10, 0.004);
  const BorderResult r = find_elastic_border(s);
  EXPECT_TRUE(r.no_sliding);
  EXPECT_EQ(r.split, s.size());
  EXPECT_DOUBLE_EQ(r.f_limit, 1.0);
}

TEST(ElasticBorder, AllSlidingExtrapolatesBelowTheFirstStep) {
  const auto s = creep_sweep(0.05, 0.1, 6);
  const BorderResult r = find_elastic_border(s);
  EXPECT_TRUE(r.all_sliding);
  EXPECT_EQ(r.split, 0u);
  EXPECT_NEAR(r.f_limit, 0.05, 1e-9);
}

TEST(ElasticBorder, RejectsUnorderedOrEmpty) {
  EXPECT_THROW(find_elastic_border({}), Error);
  auto s = creep_sweep(0.5, 0.1, 4);
  std::swap(s[0], s[1]);
  EXPECT_THROW(find_elastic_border(s), Error);
}

}  // namespace
}  // namespace inhap::friction
