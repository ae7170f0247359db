// eval/shape_study reached without the program: the foam ball (a 35 mm sphere) tapped 200
// times all over (as `eval shape --quick`) is reconstructed within a fraction of a millimetre of
// its exact surface from the estimated contact points, no worse than from thresholding, and the
// same seed gives the same numbers. Units: mm, N, s.
#include <gtest/gtest.h>

#include <string>

#include "inhap/eval/shape_study.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {
namespace {

TEST(ShapeStudy, FoamBallIsReconstructedCloseToItsSphere) {
  const lab::Scene scene = lab::builtin_scene("foam-ball");
  ShapeObjectOptions o;
  o.taps = 200;
  o.seed = 1;
  o.tap.whole_object = true;
  o.coverage_samples = 5000;
  o.count_entry_sides = true;
  double last = 0;
  std::string last_what;
  o.progress = [&](const std::string& what, double f, double) {
    EXPECT_GE(f, last);
    last = f;
    last_what = what;
  };
  const ShapeObjectResult r = run_shape_object(scene, o);
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_EQ(last_what, "done");
  EXPECT_EQ(r.estimate.points, 200u);
  EXPECT_EQ(r.threshold.points, 200u);
  // Every reference vertex lies on the exact sphere (centre (0, 0, 35), radius 35 mm).
  for (const Vec3& v : r.reference.positions) EXPECT_NEAR((v - Vec3(0, 0, 35)).norm(), 35.0, 1e-6);
  // Thesis sec. 3.3.2: mean distance below 1 mm; the estimate beats plain thresholding.
  EXPECT_GT(r.estimate.cmp.mean, 0.0);
  EXPECT_LT(r.estimate.cmp.mean, 0.2);
  EXPECT_LT(r.estimate.cmp.hausdorff, 1.5);
  EXPECT_LE(r.estimate.cmp.mean, r.threshold.cmp.mean);
  EXPECT_GT(r.coverage, 0.8);
  EXPECT_LE(r.coverage, 1.0);
  EXPECT_GT(r.taps_per_minute, 20.0);
  EXPECT_GT(r.recording_s, 0.0);
  EXPECT_GE(r.sides.episodes, 200u);

  o.progress = {};
  const ShapeObjectResult again = run_shape_object(scene, o);
  EXPECT_DOUBLE_EQ(again.estimate.cmp.hausdorff, r.estimate.cmp.hausdorff);
  EXPECT_DOUBLE_EQ(again.coverage, r.coverage);
}

}  // namespace
}  // namespace inhap::eval
