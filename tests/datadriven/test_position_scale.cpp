// The standardisation of the proxy position (TrainParams::isotropic_positions), on synthetic data
// with a known answer.
//
// A flat object (normal +z) whose stiffness varies across it, k(x) = 0.4 (1 + 0.6 sin(x / 4 mm))
// N/mm^1.5, with the friction law of dd_fixtures.hpp. The proxies lie on an estimated surface:
// the true height 0 plus an estimation error of 0.1 mm (standard deviation), independent between
// the training and the test recording, as when both proxies come from a surface fitted to the
// recordings. The force does not depend on that height. Standardised per coordinate, the height
// (spread 0.1 mm) weighs as much as the 12 mm spread across the object (40 mm wide), so the test
// proxies' heights pull every query away from the training samples that share its place; with one
// scale for the three coordinates the height errors are what they are: a tenth of a millimetre.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dd_fixtures.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {
namespace position_scale {

constexpr double kHeightError = 0.1;  // mm (standard deviation of the estimated surface)

Vec3 law(const Vec3& q, const Vec3& u) {
  return (1.0 + 0.6 * std::sin(q.x() / 4.0)) * test::friction_law(u);
}

// A proxy on the estimated surface and an elastic displacement (tangential 1.5 mm at most,
// 0.5-4 mm deep).
std::pair<Vec3, Vec3> draw(Rng& rng) {
  const Vec3 q(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.normal(0.0, kHeightError));
  return {q, Vec3(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(0.5, 4.0))};
}

// RMS error (N, all axes) over test states drawn as the training ones, with their own height
// errors (`exact`: with none).
double test_error(const ForceModel& m, bool exact) {
  Rng rng(77);
  double sq = 0;
  const int n = 1500;
  for (int i = 0; i < n; ++i) {
    auto [q, u] = draw(rng);
    if (exact) q.z() = 0;
    sq += (model_force(m, q - u, Vec3::Zero(), q, Vec3::UnitZ()) - law(q, u)).squaredNorm();
  }
  return std::sqrt(sq / n);
}

TrainParams params(bool isotropic) {
  TrainParams p = test::local_params(400, {1.0, 3.0, 0.5}, 4);  // the default weights
  p.isotropic_positions = isotropic;
  return p;
}

TEST(PositionScale, AnEstimatedSurfacesHeightNoiseDoesNotDrownThePlace) {
  const TrainingSet s = test::flat_set(
      2, 4000, draw, [](const Vec3& q, const Vec3& u) { return law(Vec3(q.x(), q.y(), 0), u); });
  const ForceModel per_axis = train_force_model(s, params(false));
  const ForceModel isotropic = train_force_model(s, params(true));
  // The height's scale equals the other two coordinates' with the option, a tenth of theirs
  // and less without it.
  const auto& b = isotropic.bins.front();
  EXPECT_DOUBLE_EQ(b.scale[5], b.scale[3]);
  EXPECT_DOUBLE_EQ(b.scale[4], b.scale[3]);
  EXPECT_LT(per_axis.bins.front().scale[5], 0.1 * per_axis.bins.front().scale[3]);
  const double e0 = test_error(per_axis, false), e1 = test_error(isotropic, false);
  const double x0 = test_error(per_axis, true), x1 = test_error(isotropic, true);
  std::printf(
      "RMS error (N), test heights with errors / exact: per coordinate %.3f / %.3f, "
      "isotropic %.3f / %.3f\n",
      e0, x0, e1, x1);
  // Measured: per coordinate 0.478 / 0.409 N, isotropic 0.281 / 0.281 N. The isotropic model
  // does not see a tenth of a millimetre of height error; the other one sees it in training too.
  EXPECT_LT(e1, 0.75 * e0);
  EXPECT_LT(x1, 0.75 * x0);
  EXPECT_LT(std::abs(e1 - x1), 0.05 * x1);
}

}  // namespace position_scale
}  // namespace inhap::datadriven
