// Force error metrics (eq. 4.27-4.31) on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/metrics.hpp"

namespace inhap::datadriven {
namespace {

TEST(Metrics, AbsoluteAndRelativeErrorUseTheMaxDenominator) {
  EXPECT_DOUBLE_EQ(absolute_error(Vec3(3, 4, 0), Vec3::Zero()), 5.0);
  EXPECT_DOUBLE_EQ(relative_error(Vec3(3, 4, 0), Vec3::Zero()), 1.0);  // not infinite
  EXPECT_DOUBLE_EQ(relative_error(Vec3(1, 0, 0), Vec3(2, 0, 0)), 0.5);
  EXPECT_DOUBLE_EQ(relative_error(Vec3(2, 0, 0), Vec3(1, 0, 0)), 0.5);  // symmetric
  EXPECT_DOUBLE_EQ(relative_error(Vec3(1, 2, 3), Vec3(1, 2, 3)), 0.0);
  EXPECT_DOUBLE_EQ(relative_error(Vec3::Zero(), Vec3::Zero()), 0.0);
  EXPECT_DOUBLE_EQ(relative_error(-1.0, 1.0), 2.0);
  EXPECT_DOUBLE_EQ(relative_error(0.0, 0.0), 0.0);
}

TEST(Metrics, QuantilesInterpolateLinearly) {
  EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_DOUBLE_EQ(quantile({4, 1, 3, 2}, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(quantile({4, 1, 3, 2}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(median({7}), 7.0);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(Metrics, BoxStatsFlagOutliersBeyondOneAndAHalfIqr) {
  const BoxStats b = box_stats({1, 2, 3, 4, 100});
  EXPECT_DOUBLE_EQ(b.q1, 2.0);
  EXPECT_DOUBLE_EQ(b.median, 3.0);
  EXPECT_DOUBLE_EQ(b.q3, 4.0);
  EXPECT_EQ(b.outliers, 1u);  // fence at 4 + 1.5 * 2 = 7
  EXPECT_DOUBLE_EQ(b.whisker_high, 4.0);
  EXPECT_DOUBLE_EQ(b.whisker_low, 1.0);
  EXPECT_DOUBLE_EQ(b.max, 100.0);
  EXPECT_DOUBLE_EQ(b.mean, 22.0);
}

TEST(Metrics, ForceErrorsOnAHandComputedSeries) {
  const std::vector<Vec3> r{{1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  const std::vector<Vec3> m{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const ForceErrors e = force_errors(r, m, 1.0);
  EXPECT_EQ(e.n, 3u);
  EXPECT_DOUBLE_EQ(e.rmse[0], std::sqrt(1.0 / 3));
  EXPECT_DOUBLE_EQ(e.rmse[1], std::sqrt(1.0 / 3));
  EXPECT_DOUBLE_EQ(e.rmse[2], std::sqrt(4.0 / 3));
  EXPECT_DOUBLE_EQ(e.ae_mean, (1 + 1 + 2) / 3.0);
  EXPECT_DOUBLE_EQ(e.ae_median, 1.0);
  // RE: 1/1, 1/2, 2/3
  EXPECT_DOUBLE_EQ(e.re_mean, (1.0 + 0.5 + 2.0 / 3) / 3);
  EXPECT_DOUBLE_EQ(e.re_median, 2.0 / 3);
  // Per axis x: RE_x = {1, 0, 0}
  EXPECT_DOUBLE_EQ(e.re_axis_mean[0], 1.0 / 3);
  EXPECT_DOUBLE_EQ(e.ae_axis_median[2], 0.0);
  // Fig. 4.13 bins of 1 N: |f_m| = 0 -> [0,1), 1 and 1 -> [1,2)
  ASSERT_EQ(e.re_by_magnitude.size(), 2u);
  EXPECT_EQ(e.re_by_magnitude[0].n, 1u);
  EXPECT_EQ(e.re_by_magnitude[1].n, 2u);
  EXPECT_DOUBLE_EQ(e.re_by_magnitude[1].re_mean, (0.5 + 2.0 / 3) / 2);
}

TEST(Metrics, RejectsMismatchedInput) {
  EXPECT_THROW(force_errors({Vec3::Zero()}, {}), Error);
  EXPECT_THROW(force_errors({}, {}), Error);
}

}  // namespace
}  // namespace inhap::datadriven
