// Tangentially mirrored training (TrainParams::tangent_mirror) and the support diagnostic
// (support_check), on synthetic data with known answers.
//
// Mirror: a flat surface (normal +z) with an isotropic law f_n = k d^1.5, f_t = mu f_n
// tanh(u_t / 0.5 mm) along the tangential displacement u_t (pointing from p to q). The training
// set only ever drags one way (u_t along +x, 0..2 mm); the test asks for drags the other way.
// An isotropic material answers with the mirrored force; the mirrored training set contains
// those states, the plain one has to extrapolate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dd_fixtures.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {
namespace {

using test::friction_law;  // k = 0.4 N/mm^1.5, mu = 0.8

TrainingSet one_sided_set(std::uint64_t seed, std::size_t n) {
  return test::flat_set(
      seed, n,
      [](Rng& rng) {
        const Vec3 q(rng.uniform(-20, 20), rng.uniform(-20, 20), 0.0);
        return std::pair{
            q, Vec3(rng.uniform(0.0, 2.0), rng.uniform(-0.2, 0.2), rng.uniform(0.5, 5.0))};
      },
      [](const Vec3&, const Vec3& u) { return friction_law(u); });
}

TrainParams mirror_params(bool mirror) {
  // Location weight 0.3: the law does not depend on the location.
  TrainParams p = test::local_params(150, {1.0, 0.3, 0.5}, 3);
  p.tangent_mirror = mirror;
  return p;
}

/// RMS error of the tangential force over drags the other way (u_t along -x, 0.3..1.8 mm).
double reversed_drag_error(const ForceModel& m) {
  Rng rng(99);
  double sq = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const Vec3 q(rng.uniform(-15, 15), rng.uniform(-15, 15), 0.0);
    const Vec3 u(-rng.uniform(0.3, 1.8), 0.0, rng.uniform(1.0, 4.5));
    const Vec3 f = model_force(m, q - u, Vec3::Zero(), q, Vec3::UnitZ());
    sq += (f - friction_law(u)).head<2>().squaredNorm();
  }
  return std::sqrt(sq / n);
}

TEST(TangentMirror, IsotropicMaterialAnswersDragsItWasNotShown) {
  const TrainingSet s = one_sided_set(1, 3000);
  const ForceModel plain = train_force_model(s, mirror_params(false));
  const ForceModel mirrored = train_force_model(s, mirror_params(true));
  const double e0 = reversed_drag_error(plain), e1 = reversed_drag_error(mirrored);
  // Typical tangential force of those states: mu * k * 2.75^1.5 * tanh(2) ~ 1.4 N.
  std::printf("reversed drags, tangential RMS error: %.3f N plain, %.3f N mirrored\n", e0, e1);
  // Within about 10 % of that (measured: 0.124 N; 0.085 N with the location standardised per
  // coordinate, --no-isotropic-positions, whose other scale gives k-means another start).
  EXPECT_LT(e1, 0.15);
  EXPECT_GT(e0, 5 * e1);
  EXPECT_EQ(mirrored.bins[0].samples + mirrored.bins[1].samples, 2 * s.size());
}

TEST(SupportCheck, ExcessIsTheDistanceBeyondTheTrainingRangeInUnitsOfIt) {
  // Training locations x in [-20, 20] (range 40 mm): a query at x = 26 lies 6 mm = 0.15 of the
  // range beyond it, whatever the normalisation; inside queries have no excess.
  const TrainingSet s = one_sided_set(3, 1500);
  TrainParams p = mirror_params(false);
  p.bins = 1;
  const ForceModel m = train_force_model(s, p);
  double xmin = 1e9, xmax = -1e9;
  for (const Vec3& q : s.q) xmin = std::min(xmin, q.x()), xmax = std::max(xmax, q.x());
  const Vec3 u(1.0, 0.0, 2.0);
  const Vec3 q_in(0.0, 0.0, 0.0), q_out(xmax + 6.0, 0.0, 0.0);
  const double mg = p.box_margin;
  const SupportCheck in = support_check(m, mg, q_in - u, Vec3::Zero(), q_in, Vec3::UnitZ());
  const SupportCheck out = support_check(m, mg, q_out - u, Vec3::Zero(), q_out, Vec3::UnitZ());
  EXPECT_EQ(in.bin, 0);
  EXPECT_EQ(in.excess[0], 0.0);
  EXPECT_EQ(in.excess[1], 0.0);
  EXPECT_NEAR(out.excess[1], 6.0 / (xmax - xmin), 1e-9);
  EXPECT_EQ(out.excess[0], 0.0);
  EXPECT_GT(out.nearest, in.nearest);
  const SupportCheck bad = support_check(m, mg, Vec3(NAN, 0, 0), Vec3::Zero(), q_in, Vec3::UnitZ());
  EXPECT_EQ(bad.bin, -1);
}

}  // namespace
}  // namespace inhap::datadriven
