// Friction-cone guard (TrainParams::friction_cone) on synthetic data with a known law: a flat
// surface (normal +z), f_n = k d^1.5, f_t = mu f_n tanh(u_t / 0.5 mm) along the tangential
// displacement u_t, mu = 0.8. Trained on u_t up to 2 mm, the cone must come out as mu (the law
// saturates there) and hold the rendered force inside it where the RBFs extrapolate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dd_fixtures.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"

namespace inhap::datadriven {
namespace {

using test::friction_law;
constexpr double kMu = test::kLawMu;

TrainingSet drag_set(std::uint64_t seed, std::size_t n) {
  return test::flat_set(
      seed, n,
      [](Rng& rng) {
        const Vec3 q(rng.uniform(-20, 20), rng.uniform(-20, 20), 0.0);
        const double a = rng.uniform(0.0, 2 * M_PI), ut = rng.uniform(0.0, 2.0);
        return std::pair{q, Vec3(ut * std::cos(a), ut * std::sin(a), rng.uniform(0.5, 5.0))};
      },
      [](const Vec3&, const Vec3& u) { return friction_law(u); });
}

TrainParams cone_params(bool cone) {
  TrainParams p = test::local_params(120, {1.0, 0.3, 0.5}, 5);
  p.box_margin = 1.0;  // let the expansions extrapolate far
  p.friction_cone = cone;
  return p;
}

TEST(FrictionCone, IsTheLawsFrictionCoefficientAndBoundsExtrapolation) {
  const TrainingSet s = drag_set(1, 4000);
  const ForceModel plain = train_force_model(s, cone_params(false));
  const ForceModel guarded = train_force_model(s, cone_params(true));
  EXPECT_EQ(plain.friction_cone, 0.0);
  // 99.5 % quantile of mu tanh(u_t / 0.5) over u_t uniform in [0, 2] mm: mu tanh(3.98) = 0.7995.
  EXPECT_NEAR(guarded.friction_cone, kMu, 0.01);
  // Drags 1.5-2.5x longer than any in training (the law is saturated: |f_t| = mu f_n).
  Rng rng(9);
  double sq0 = 0, sq1 = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Vec3 q(rng.uniform(-15, 15), rng.uniform(-15, 15), 0.0);
    const Vec3 u(rng.uniform(3.0, 5.0), 0.0, rng.uniform(1.0, 4.5));
    const Vec3 f0 = model_force(plain, q - u, Vec3::Zero(), q, Vec3::UnitZ());
    const Vec3 f1 = model_force(guarded, q - u, Vec3::Zero(), q, Vec3::UnitZ());
    EXPECT_LE(f1.head<2>().norm(),
              guarded.friction_cone * std::max(f1.z(), kConeFloorN) * (1 + 1e-12));
    sq0 += (f0 - friction_law(u)).head<2>().squaredNorm();
    sq1 += (f1 - friction_law(u)).head<2>().squaredNorm();
  }
  const double e0 = std::sqrt(sq0 / n), e1 = std::sqrt(sq1 / n);
  std::printf("long drags, tangential RMS error: %.3f N plain, %.3f N with the cone\n", e0, e1);
  EXPECT_LT(e1, e0);
  const ForceModel back = force_model_from_json(force_model_to_json(guarded), "mem");
  EXPECT_EQ(back.friction_cone, guarded.friction_cone);
}

TEST(FrictionCone, NeedsLocalFeatures) {
  TrainParams p = cone_params(true);
  p.features = FeatureSet::kDisplacementProxyVelocity;
  EXPECT_THROW(p.validate(), Error);
}

}  // namespace
}  // namespace inhap::datadriven
