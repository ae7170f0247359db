// Local shear prior (TrainParams::shear_prior) on synthetic data with a known law: a flat surface
// (normal +z), f_n = 0.4 d^1.5 and a linear tangential spring f_t = k_t(q) u_t along the
// tangential displacement u_t of u = q - p, with k_t(q) = 0.5 (1 - 0.5 exp(-|q - c|^2 /
// (8 mm)^2)) N/mm (a soft spot at c), as in the virtual lab's contact law.
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

const Vec3 kSoft(-6.0, 3.0, 0.0);  // centre of the soft spot

double shear_stiffness(const Vec3& q) {
  return 0.5 * (1.0 - 0.5 * std::exp(-(q - kSoft).squaredNorm() / 64.0));
}

Vec3 law(const Vec3& q, const Vec3& u) {
  const double kt = shear_stiffness(q);
  return Vec3(kt * u.x(), kt * u.y(), 0.4 * std::pow(std::max(u.z(), 0.0), 1.5));
}

/// Samples over [-25, 25]^2 with tangential displacements of at most `max_shear` mm.
TrainingSet shear_set(std::uint64_t seed, std::size_t n, double max_shear) {
  return test::flat_set(
      seed, n,
      [&](Rng& rng) {
        const Vec3 q(rng.uniform(-25, 25), rng.uniform(-25, 25), 0.0);
        const double a = rng.uniform(0.0, 2 * M_PI), ut = rng.uniform(0.0, max_shear);
        return std::pair{q, Vec3(ut * std::cos(a), ut * std::sin(a), rng.uniform(0.5, 5.0))};
      },
      law);
}

TrainParams shear_params(bool prior) {
  TrainParams p = test::local_params(120, {1.0, 5.0, 0.5}, 4);
  p.shear_prior = prior;
  return p;
}

TEST(ShearPrior, RecoversTheLocalShearStiffness) {
  const ForceModel m = train_force_model(shear_set(1, 20000, 2.0), shear_params(true));
  ASSERT_FALSE(m.shear.empty());
  EXPECT_NEAR(m.shear.exponent, 1.0, 0.02);  // a linear spring
  // ln k_t smoothed over 1.5 mm: within 3 % at the soft spot, 1 % far from it.
  EXPECT_NEAR(std::exp(m.shear.log_stiffness(kSoft)) / shear_stiffness(kSoft), 1.0, 0.03);
  const Vec3 far(15.0, -12.0, 0.0);
  EXPECT_NEAR(std::exp(m.shear.log_stiffness(far)) / shear_stiffness(far), 1.0, 0.01);
  EXPECT_TRUE(m.prior.empty());  // the stiffness prior is a separate option
}

/// RMS error of the tangential force of drags 2.5-4 mm long within 4 mm of the soft spot.
double long_drag_error(const ForceModel& m) {
  return test::rms_on_disc(11, 300, kSoft, 4.0, [&](Rng& rng, const Vec3& q) {
    const double b = rng.uniform(0.0, 2 * M_PI), ut = rng.uniform(2.5, 4.0);
    const Vec3 u(ut * std::cos(b), ut * std::sin(b), rng.uniform(1.0, 4.0));
    const Vec3 f = model_force(m, q - u, Vec3::Zero(), q, Vec3::UnitZ());
    return (f - law(q, u)).head<2>().squaredNorm();
  });
}

TEST(ShearPrior, ExtrapolatesTheSpringToLongerDrags) {
  // Trained on drags up to 1 mm only; the expansions are frozen beyond their box (50 % margin).
  const TrainingSet s = shear_set(2, 6000, 1.0);
  const ForceModel plain = train_force_model(s, shear_params(false));
  const TrainedForceModel trained = train_with_provenance(s, shear_params(true));
  const ForceModel& prior = trained.model;
  ASSERT_TRUE(plain.shear.empty());
  test::expect_prior_gain("long drags on the soft spot, tangential RMS error",
                          long_drag_error(plain), long_drag_error(prior), 0.1);
  // Saved and loaded, the prior renders the same forces.
  const ForceModel back =
      test::expect_same_force_after_save(prior, kSoft - Vec3(1.5, -0.7, 3.0), kSoft);
  EXPECT_FALSE(back.shear.empty());
  EXPECT_TRUE(trained_force_model_from_json(force_model_to_json(trained), "mem")
                  .provenance.params.shear_prior);  // the file's provenance says so
}

TEST(ShearPrior, IgnoresSamplesWhoseForceDoesNotOpposeTheDisplacement) {
  // A quarter of the samples carry a tangential force at right angles to u_t (e.g. a sensor
  // offset or a rubbing transient): the fit must leave them out and still find the spring.
  TrainingSet s = shear_set(3, 20000, 2.0);
  for (std::size_t i = 0; i < s.size(); i += 4) {
    const Vec3 t = s.f[i];
    s.f[i].x() = -t.y(), s.f[i].y() = t.x();
  }
  const ForceModel m = train_force_model(s, shear_params(true));
  const Vec3 far(15.0, -12.0, 0.0);
  EXPECT_NEAR(std::exp(m.shear.log_stiffness(far)) / shear_stiffness(far), 1.0, 0.01);
  EXPECT_NEAR(m.shear.exponent, 1.0, 0.02);
}

TEST(ShearPrior, NeedsLocalFeaturesAndValidParameters) {
  TrainParams p = shear_params(true);
  p.features = FeatureSet::kDisplacementProxyVelocity;
  EXPECT_THROW(p.validate(), Error);
  p = shear_params(true);
  p.shear.sigma = 0;
  EXPECT_THROW(p.validate(), Error);
  // A shear map in a world-frame model file is rejected on loading, naming the map.
  ForceModel m = train_force_model(shear_set(4, 3000, 1.0), shear_params(true));
  std::string text = force_model_to_json(m);
  const std::string local = "\"features\": \"local\"";
  const auto at = text.find(local);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, local.size(), "\"features\": \"ue_q_v\"");
  try {
    force_model_from_json(text, "mem");
    ADD_FAILURE() << "a world-frame model with a shear map was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shear_prior"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace inhap::datadriven
