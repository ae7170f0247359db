// `tca stroke`'s simulated hand: it finishes at every force the help allows, on soft and on very
// stiff maps, and holds the force it is asked for (issue 20).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/rendering/stroke.hpp"
#include "support/meshes.hpp"

namespace inhap {
namespace {

/// A flat 60 x 60 mm map, stiffness from k0 (x = 0) to k1 (x = 60) N/mm.
rendering::Model flat_map(double k0, double k1) {
  TriMesh m = test::make_grid_mesh(31, 31, 2.0);
  std::vector<double> k;
  for (const Vec3& p : m.positions) k.push_back(k0 + (k1 - k0) * p.x() / 60.0);
  m.set_property("stiffness", k);
  return rendering::Model(std::move(m));
}

/// Mean and largest |error| of the force in the stroke phase's middle half.
struct Held {
  double mean = 0, worst = 0;
};
Held held_force(const std::vector<rendering::StrokeSample>& s, double target) {
  // The stroke is the contact span; take its middle half (settled, before the lift-off).
  std::size_t first = s.size(), last = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i].contact) first = std::min(first, i), last = i;
  Held h;
  if (first >= last) return h;
  const std::size_t a = first + (last - first) / 4, b = last - (last - first) / 4;
  for (std::size_t i = a; i < b; ++i) {
    h.mean += s[i].force.norm() / double(b - a);
    h.worst = std::max(h.worst, std::abs(s[i].force.norm() - target));
  }
  return h;
}

rendering::StrokeOptions stroke(double force) {
  rendering::StrokeOptions o;
  o.from = Vec2(10, 30);
  o.to = Vec2(50, 30);
  o.force_n = force;
  o.timeout_s = 60;
  return o;
}

TEST(StrokeHand, FinishesOnSoftMapsAtHighForces) {
  for (auto alg : {rendering::Algorithm::kTCA, rendering::Algorithm::kCBA}) {
    const rendering::Model soft = flat_map(0.2, 1.0);
    for (double f : {4.5, 6.0, kDeviceForceLimitN}) {
      const auto s = rendering::simulate_stroke(soft, alg, stroke(f));
      ASSERT_FALSE(s.empty());
      EXPECT_FALSE(s.back().contact) << f << " N: the hand did not lift off";
      EXPECT_NEAR(held_force(s, f).mean, f, 0.05 * f) << f << " N";
    }
    const rendering::Model softer = flat_map(0.1, 0.1);
    const auto s = rendering::simulate_stroke(softer, alg, stroke(1.5));
    EXPECT_NEAR(held_force(s, 1.5).mean, 1.5, 0.05 * 1.5);
  }
}

// The stiffest map a model accepts (100 N/mm; stiffer is refused, RendererModel.*).
TEST(StrokeHand, StableOnAVeryStiffMap) {
  for (auto alg : {rendering::Algorithm::kTCA, rendering::Algorithm::kCBA}) {
    const rendering::Model stiff = flat_map(100, 100);
    const auto s = rendering::simulate_stroke(stiff, alg, stroke(2.0));
    const Held h = held_force(s, 2.0);
    EXPECT_NEAR(h.mean, 2.0, 0.1) << "mean force while stroking";
    EXPECT_LT(h.worst, 1.0) << "the force loop oscillates";
  }
}

}  // namespace
}  // namespace inhap
