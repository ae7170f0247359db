// FOAW: a sample whose deviation from the fitted line equals the noise bound d is outside the
// band (the window ends there); one strictly inside keeps the window.
#include <gtest/gtest.h>

#include "inhap/datadriven/foaw.hpp"

namespace inhap::datadriven {
namespace {

// Pushes y0, y1, y2 along x (1 kHz) and returns the state after the last one.
FoawState three_samples(double y0, double y1, double y2, const FoawParams& prm) {
  FoawState st;
  for (double y : {y0, y1, y2}) foaw_step(prm, st, Vec3(y, 0, 0));
  return st;
}

// For y_{k-2} = y_k the best-fit slope of the 3-sample window is 0, so the middle sample
// deviates from the line by exactly y_{k-1} - y_k; the 1-sample window's slope is
// (y_k - y_{k-1}) / T.
TEST(FoawTies, DeviationEqualToTheBoundEndsTheWindow) {
  FoawParams prm;
  prm.noise_bound_mm = 0.01;
  const FoawState st = three_samples(0.0, 0.01, 0.0, prm);
  EXPECT_EQ(st.window[0], 1);
  EXPECT_NEAR(st.velocity.x(), -0.01 / prm.dt_s, 1e-9);
}

TEST(FoawTies, TieOfQuantisedPositionsAwayFromZeroEndsTheWindow) {
  // 5.01 - 5.00 is 0.00999999999999979 in doubles: still a tie with d = 0.01.
  FoawParams prm;
  prm.noise_bound_mm = 0.01;
  const FoawState st = three_samples(5.00, 5.01, 5.00, prm);
  EXPECT_EQ(st.window[0], 1);
  EXPECT_NEAR(st.velocity.x(), -0.01 / prm.dt_s, 1e-6);
}

TEST(FoawTies, DeviationBelowTheBoundKeepsTheWindow) {
  FoawParams prm;
  prm.noise_bound_mm = 0.01;
  const FoawState st = three_samples(0.0, 0.0099, 0.0, prm);
  EXPECT_EQ(st.window[0], 2);
  EXPECT_NEAR(st.velocity.x(), 0.0, 1e-9);
}

}  // namespace
}  // namespace inhap::datadriven
