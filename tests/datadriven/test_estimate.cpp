// The surface, normals and friction estimated from a recording with no proxy, against the
// known answer of a synthetic continuous-palpation rig (tests/support/palpation_rig.hpp) at the
// rates of real rigs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/estimate.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "support/palpation_rig.hpp"
#include "support/relief_recording.hpp"

namespace inhap::datadriven {
namespace test_estimate {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct Errors {
  double surface_mm, normal_deg, mu_rel;
};

Errors estimate_errors(const inhap::test::PalpationRig& rig, double seconds) {
  const Recording rec = rig.record(seconds);
  const RecordingEstimate e = estimate_recording(rec, {}, "rig.csv");
  const friction::MeshSurface shape(e.mesh, 0.0);
  const SurfaceFrame fr = rig.frame();
  std::vector<double> dz, ang;
  for (std::size_t i = 0; i < rec.size(); i += 5) {
    // The true surface point under the probe: p moved back out along the normal by its depth.
    const double d = (rig.point - rec.p[i]).dot(fr.n);
    const Vec3 on = rec.p[i] + d * fr.n;
    Vec3 c, n;
    if (!shape.closest(on, c, n)) continue;
    dz.push_back(std::abs((on - c).dot(n)));
    ang.push_back(std::acos(std::clamp(n.dot(fr.n), -1.0, 1.0)) * 180 / std::numbers::pi);
  }
  return {median(dz), median(ang), std::abs(e.friction.mu - rig.mu) / rig.mu};
}

TEST(RecordingEstimate, SurfaceNormalsAndFrictionOfAPalpationRigAtRealRigRates) {
  for (double rate : {66.0, 200.0, 1000.0}) {
    inhap::test::PalpationRig rig;
    rig.rate_hz = rate;
    const Errors err = estimate_errors(rig, rate > 500 ? 40.0 : 120.0);
    SCOPED_TRACE(rate);
    EXPECT_LT(err.surface_mm, 0.2);  // depths of 0.2-2.5 mm
    EXPECT_LT(err.normal_deg, 3.0);
    EXPECT_LT(err.mu_rel, 0.15);
  }
}

TEST(RecordingEstimate, AFlatRecordingWithoutContactIsRefusedNamingTheFile) {
  Recording rec;
  for (int i = 0; i < 100; ++i) {
    rec.t.push_back(0.01 * i);
    rec.p.push_back(Vec3(i * 0.1, 0, 0));
    rec.f.push_back(Vec3::Zero());
  }
  try {
    estimate_recording(rec, {}, "air.csv");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("air.csv"), std::string::npos) << e.what();
  }
}

TEST(RecordingEstimate, ThePushAxisAndDepthLawFollowTheData) {
  inhap::test::PalpationRig rig;
  const Recording rec = rig.record(60.0);
  const SurfaceEstimate s = estimate_surface(rec, {}, "rig.csv");
  // The mean force leans towards -t0 by the friction of the sweeps (which cancel) only: the
  // axis is the plane's normal within a few degrees.
  EXPECT_GT(s.axis.dot(rig.frame().n), std::cos(3.0 * std::numbers::pi / 180));
  // d = f_n / k: gamma 1, b between 1 / k_inclusion and 1 / k.
  EXPECT_NEAR(s.gamma, 1.0, 0.051);
  EXPECT_GT(s.b_median, 1.0 / rig.k_inclusion);
  EXPECT_LT(s.b_median, 1.0 / rig.k * 1.05);
}

// A Hertzian material (f_n = k d^1.5, d = (f_n / k)^(2/3)) pressed 0.2-2.5 mm: the exponent is
// found near 2/3 and the surface extrapolated to zero force without a bias. A depth-force law
// fitted with gamma 1/2 would put the surface about 0.2 mm too high here (0.8 mm on the lab's
// silicone), and one fitted on the lighter forces alone cannot tell 1/2 from 2/3.
TEST(RecordingEstimate, AHertzianMaterialsSurfaceIsFoundWithoutABias) {
  for (double rate : {66.0, 1000.0}) {
    inhap::test::PalpationRig rig;
    // The lab's silicone: k = 0.33 N/mm^1.5, Hunt-Crossley damping 0.004 s/mm, pressed 0.2-4 mm.
    rig.exponent = 1.5;
    rig.k = 0.33, rig.k_inclusion = 0.6;
    rig.damping = 0.004;
    rig.depth_max = 4.0;
    rig.rate_hz = rate;
    SCOPED_TRACE(rate);
    const Recording rec = rig.record(rate > 500 ? 40.0 : 120.0);
    const SurfaceEstimate s = estimate_surface(rec, {}, "rig.csv");
    EXPECT_NEAR(s.gamma, 2.0 / 3.0, 0.051);
    const Errors err = estimate_errors(rig, rate > 500 ? 40.0 : 120.0);
    EXPECT_LT(err.surface_mm, 0.1);
    EXPECT_LT(err.normal_deg, 3.0);
  }
}

// A dome (sphere of radius 60 mm) pressed only within 12 mm of its apex: past the pressed
// region the surface is extrapolated. 5 mm past it (17 mm out, true tilt 16.5 degrees) cells
// filled by neighbour averages levelled off (normals 16.3 degrees off, median); filled front by
// front with the plane through the cells around, the slope carries on (9.9 degrees off: the
// cells at the data's edge are fitted as level blocks, so some of the slope is lost there).
TEST(RecordingEstimate, ACurvedSurfacesSlopeCarriesOnPastThePressedRegion) {
  constexpr double R = 60.0, k = 1.0;  // mm, N/mm (a linear law: gamma 1)
  const Vec3 centre(0, 0, -R);
  Recording rec;
  std::uint64_t state = 12345;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  for (int i = 0; i < 4000; ++i) {
    const double r = 12.0 * std::sqrt(uniform()), a = 2 * std::numbers::pi * uniform();
    const Vec3 on(r * std::cos(a), r * std::sin(a), std::sqrt(R * R - r * r) - R);
    const Vec3 n = (on - centre).normalized();
    const double d = 0.2 + 2.3 * uniform();
    rec.t.push_back(i / 66.0);
    rec.p.push_back(on - d * n);
    rec.f.push_back(k * d * n);
  }
  const SurfaceEstimate s = estimate_surface(rec, {}, "dome.csv");
  constexpr double r = 17.0;  // mm from the apex
  std::vector<double> deg;
  for (int j = 0; j < 72; ++j) {
    const double a = j * std::numbers::pi / 36;
    const Vec3 w(r * std::cos(a), r * std::sin(a), 0.0);
    const Vec3 d = w - s.origin;
    const double u = d.dot(s.e1), v = d.dot(s.e2), h = 1.0;
    const double du = (s.height_at(u + h, v) - s.height_at(u - h, v)) / (2 * h);
    const double dv = (s.height_at(u, v + h) - s.height_at(u, v - h)) / (2 * h);
    const Vec3 n = (s.axis - du * s.e1 - dv * s.e2).normalized();
    const Vec3 truth = (Vec3(w.x(), w.y(), std::sqrt(R * R - r * r) - R) - centre).normalized();
    deg.push_back(std::acos(std::clamp(n.dot(truth), -1.0, 1.0)) * 180 / std::numbers::pi);
  }
  EXPECT_LT(median(deg), 12.0);
}

// Samples pressing on a surface with 1 mm of relief every 8 mm (support/relief_recording.hpp):
// pressed 1.5-2.5 mm deep, the estimate holds them all (the surface is known to better than that
// depth). A force-controlled exploration at 0.2 N (0.2 mm deep; 20 % of the samples pressed
// 0.2-2.5 N so that the law can be fitted) leaves a share of them above the fitted surface: the
// estimate says so, and raising the cells where they lie (hold_quantile) puts most of them under
// it. A recording that holds one force is said to be one.
TEST(RecordingEstimate, PressingSamplesAboveTheSurfaceAreHeldAndWarnedOf) {
  inhap::test::ReliefRecording relief;
  relief.light_share = 0.0;
  const RecordingEstimate deep = estimate_recording(relief.record(), {}, "deep.csv");
  EXPECT_EQ(deep.pressing_samples, 6000u);
  EXPECT_EQ(deep.pressing_above, 0u);
  EXPECT_EQ(deep.surface.cells_raised, 0u);
  EXPECT_EQ(estimate_contact_warning(deep), "");

  relief.light_share = 0.8;
  const Recording light = relief.record();
  EstimateParams no_hold;
  no_hold.hold_quantile = 0;
  const RecordingEstimate fitted = estimate_recording(light, no_hold, "light.csv");
  EXPECT_GT(double(fitted.pressing_above), 0.1 * 6000) << fitted.pressing_above;
  // f_n along the push axis: 0.2 N times the cosine of the relief's tilt (up to 38 degrees).
  EXPECT_GT(fitted.pressing_fn_p5, 0.15);
  EXPECT_LE(fitted.pressing_fn_p5, 0.2);
  const std::string w = estimate_contact_warning(fitted);
  EXPECT_NE(w.find("of the 6000 samples"), std::string::npos) << w;
  EXPECT_NE(w.find("force-controlled"), std::string::npos) << w;

  const RecordingEstimate held = estimate_recording(light, {}, "light.csv");
  EXPECT_GT(held.surface.cells_raised, 0u);
  EXPECT_LT(double(held.pressing_above), 0.5 * double(fitted.pressing_above))
      << held.pressing_above << " against " << fitted.pressing_above;
  // The raise is spread to the neighbours and smoothed (on the real explorations that rendered
  // better than the raw per-cell raise: docs/real-recordings.md), so it overshoots in the
  // valleys: at the light samples' places the surface is off by 0.55 mm (median) where the fit
  // alone was 0.37 mm off, still under the relief's 1 mm.
  std::vector<double> error;
  for (std::size_t i = 0; i < light.size(); ++i)
    if (light.f[i].norm() == relief.light_n) {
      const Vec3& p = light.p[i];
      error.push_back(
          std::abs(held.surface.depth(Vec3(p.x(), p.y(), relief.height(p.x(), p.y())))));
    }
  EXPECT_LT(median(error), 0.75 * relief.amplitude);

  // A flat surface, 97 % of its samples at 0.2 N: none above it, but the force held is said.
  relief.amplitude = 0;
  relief.light_share = 0.97;
  const RecordingEstimate held_force = estimate_recording(relief.record(), {}, "held.csv");
  EXPECT_LT(held_force.pressing_fn_p95 - held_force.pressing_fn_p5,
            RecordingEstimate::kNarrowForceN);
  EXPECT_LT(double(held_force.pressing_above), 0.05 * 6000);
  const std::string narrow = estimate_contact_warning(held_force);
  EXPECT_NE(narrow.find("samples pressing with more than the contact threshold span only"),
            std::string::npos)
      << narrow;
}

}  // namespace test_estimate
}  // namespace inhap::datadriven
