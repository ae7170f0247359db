// Params::spatial_order renumbers the model's mesh for cache locality; what the hand feels must
// not change: the same path gives the same forces and points tick for tick with it on and off.
// Units: mm, N, N/mm, s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "inhap/rendering/renderer.hpp"
#include "rendering/render_fixtures.hpp"

using namespace inhap;
using rendering::Algorithm;

namespace {

double height(double x, double y) {
  return 2.0 * std::exp(-(x * x + (y - 3) * (y - 3)) / 18.0);
}

TriMesh bumpy() {
  return test::grid_mesh(80, 80, 0.4, -16, -16, height, [](double x, double y) {
    return 0.3 + 0.6 * (0.5 + 0.5 * std::sin(0.3 * x + 0.2 * y));
  });
}

}  // namespace

TEST(RendererOrder, SpatialOrderChangesNumberingNotForces) {
  rendering::Params sorted, plain;
  plain.spatial_order = false;
  const rendering::Model a(bumpy(), sorted), b(bumpy(), plain);
  // The numbering did change (else the test would compare a model with itself).
  bool renumbered = false;
  for (std::size_t f = 0; f < a.mesh().num_triangles() && !renumbered; ++f)
    renumbered = a.mesh().triangles[f] != b.mesh().triangles[f];
  ASSERT_TRUE(renumbered);
  for (Algorithm alg : {Algorithm::kCBA, Algorithm::kTCA}) {
    rendering::State sa, sb;
    int contact = 0;
    for (int i = 0; i < 6000; ++i) {
      const double t = i * 1e-3;  // a fast circle over the bump, pressing 0.5-2 mm deep
      const double x = 10 * std::sin(4 * t), y = 10 * std::sin(5.5 * t + 0.5);
      // From 2 mm above (contact needs an entering crossing), then 0.5-2 mm deep.
      const double depth = std::min(-2.0 + 10.0 * t, 1.25 + 0.75 * std::sin(3 * t));
      const Vec3 p(x, y, height(x, y) - depth);
      const Vec3 fa = rendering::step(a, sa, p, alg), fb = rendering::step(b, sb, p, alg);
      ASSERT_NEAR((fa - fb).norm(), 0.0, 1e-9) << "tick " << i;
      ASSERT_NEAR((sa.ihip.point - sb.ihip.point).norm(), 0.0, 1e-9) << "tick " << i;
      ASSERT_EQ(sa.collision, sb.collision);
      contact += sa.collision;
    }
    EXPECT_GT(contact, 3000);  // the path is mostly in contact, across many triangles
  }
}

// rendering::prefetch reads ahead for the next tick. It must change nothing: the same path with
// and without it gives identical forces and states. With an exact prediction it walks the very
// triangles the next step walks.
TEST(RendererPrefetch, ChangesNothingAndWalksWhereTheNextStepWalks) {
  const rendering::Model m(bumpy());
  const Vec3 nan = Vec3::Constant(std::nan(""));
  for (Algorithm alg : {Algorithm::kCBA, Algorithm::kTCA}) {
    rendering::State plain, warmed;
    long compared = 0, walked = 0, differ = 0;
    for (int i = 0; i < 6000; ++i) {
      const double t = i * 1e-3;
      const double x = 10 * std::sin(4 * t), y = 10 * std::sin(5.5 * t + 0.5);
      const double depth = std::min(-2.0 + 10.0 * t, 1.25 + 0.75 * std::sin(3 * t));
      const Vec3 p(x, y, height(x, y) - depth);
      const bool was = warmed.collision;
      const std::uint32_t ahead = rendering::prefetch(m, warmed, p);  // an exact prediction
      EXPECT_EQ(rendering::prefetch(m, warmed, nan), 0u);
      EXPECT_EQ(rendering::prefetch(m, warmed, p + Vec3(0, 0, 1e3)), 0u);  // a glitch-sized jump
      const Vec3 fa = rendering::step(m, plain, p, alg), fb = rendering::step(m, warmed, p, alg);
      ASSERT_EQ(fa, fb) << "tick " << i;
      ASSERT_EQ(plain.ihip.point, warmed.ihip.point) << "tick " << i;
      ASSERT_EQ(plain.ihip.triangle, warmed.ihip.triangle) << "tick " << i;
      ASSERT_EQ(plain.s, warmed.s) << "tick " << i;
      ASSERT_EQ(plain.t, warmed.t) << "tick " << i;
      if (was && warmed.collision) {
        ++compared;
        walked += ahead > 0;
        differ += ahead != warmed.walk_steps;
      }
    }
    EXPECT_GT(compared, 3000);
    EXPECT_GT(walked, 500) << "the path crosses triangles on many ticks";
    EXPECT_EQ(differ, 0);
  }
}
