// simulate_stroke: the force-tracking hand reproduces the force-constancy prediction on a plane
// of two stiffness halves. Units: mm, N, N/mm, s.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/rendering/stroke.hpp"
#include "rendering/render_fixtures.hpp"

using namespace inhap;
using rendering::Algorithm;

namespace {

TriMesh halves(double k1, double k2) {
  return test::grid_mesh(
      120, 20, 0.5, -30, -5, [](double, double) { return 0.0; },
      [=](double x, double) { return x < -1e-9 ? k1 : k2; });
}

double mean_hip_z(const std::vector<rendering::StrokeSample>& s, double lo, double hi) {
  double sum = 0;
  int n = 0;
  for (const auto& e : s)
    if (e.contact && e.hip.x() >= lo && e.hip.x() <= hi && e.hip.y() == 0) {
      sum += e.hip.z();
      ++n;
    }
  return n ? sum / n : NAN;
}

}  // namespace

TEST(RendererStroke, HandHoldsForceAndShowsTheCbaDipButNotTheTcaOne) {
  const double k1 = 1.0, k2 = 0.25, F = 1.5;
  rendering::Model m(halves(k1, k2));
  rendering::StrokeOptions o;
  o.from = {-20, 0};
  o.to = {20, 0};
  o.force_n = F;
  o.speed_mm_s = 20;
  const auto cba = rendering::simulate_stroke(m, Algorithm::kCBA, o);
  const auto tca = rendering::simulate_stroke(m, Algorithm::kTCA, o);
  // Descends, strokes 40 mm at 20 mm/s (2 s) and lifts off.
  ASSERT_GT(cba.size(), 2000u);
  EXPECT_FALSE(cba.back().contact);
  EXPECT_NEAR(cba.back().hip.x(), 20, 1e-9);
  // Force held within 2 % away from the border.
  for (const auto& e : cba) {
    if (e.contact && std::abs(e.hip.x()) > 3 && e.hip.y() == 0 && e.hip.x() > -19.9 &&
        e.hip.x() < 19.9) {
      ASSERT_NEAR(e.force.norm(), F, 0.02 * F) << e.time;
    }
  }
  const double predicted = -F * (1 / k2 - 1 / k1);
  const double cba_step = mean_hip_z(cba, 5, 15) - mean_hip_z(cba, -15, -5);
  EXPECT_NEAR(cba_step, predicted, 0.05 * std::abs(predicted));
  // TCA: from before the border to 0.5 mm after it (the restoration adds a_s * travel later).
  const double tca_step = mean_hip_z(tca, 0.5, 1.0) - mean_hip_z(tca, -5, -1);
  EXPECT_LE(std::abs(tca_step), 0.1);
  std::printf("stroke: CBA step %.3f mm (predicted %.3f), TCA step %.3f mm\n", cba_step, predicted,
              tca_step);
}

TEST(RendererStroke, TremorIsSeededAndOptionsAreChecked) {
  rendering::Model m(halves(1.0, 1.0));
  rendering::StrokeOptions o;
  o.from = {-5, 0};
  o.to = {5, 0};
  o.tremor_n = 0.1;
  o.seed = 3;
  const auto a = rendering::simulate_stroke(m, Algorithm::kTCA, o);
  const auto b = rendering::simulate_stroke(m, Algorithm::kTCA, o);
  o.seed = 4;
  const auto c = rendering::simulate_stroke(m, Algorithm::kTCA, o);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].hip, b[i].hip);
  bool differs = a.size() != c.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) differs = a[i].hip != c[i].hip;
  EXPECT_TRUE(differs);

  rendering::StrokeOptions bad;
  bad.force_n = 10;  // above the 6.2 N limit
  EXPECT_THROW(rendering::simulate_stroke(m, Algorithm::kCBA, bad), Error);
  bad = {};
  bad.speed_mm_s = 0;
  EXPECT_THROW(rendering::simulate_stroke(m, Algorithm::kCBA, bad), Error);
  bad = {};
  bad.from = {100, 100};  // no surface below
  try {
    rendering::simulate_stroke(m, Algorithm::kCBA, bad);
    ADD_FAILURE() << "expected Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no surface below"), std::string::npos) << e.what();
  }
}
