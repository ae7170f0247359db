// The servo step never allocates: global operator new is counted while step() runs.
// (This file includes support/alloc_counter.hpp for the whole test_rendering program.)
// Units: mm, N.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>

#include "inhap/rendering/renderer.hpp"
#include "rendering/render_fixtures.hpp"
#include "support/alloc_counter.hpp"

using namespace inhap;
using rendering::Algorithm;

TEST(RendererAlloc, StepNeverAllocates) {
  // Bumpy heightmap with a stiffness map, plus a box corner: every branch of step() runs
  // (free, first contact, contact, release with re-contact sweep, restoration, resets, clamp).
  TriMesh mesh = test::grid_mesh(
      60, 60, 0.5, -15, -15,
      [](double x, double y) { return std::sin(0.4 * x) * std::cos(0.3 * y); },
      [](double x, double) { return x < 0 ? 1.0 : 0.2; });
  rendering::Model m(mesh);
  for (Algorithm a : {Algorithm::kCBA, Algorithm::kTCA}) {
    rendering::State st;
    long ticks = 0, contact = 0, touches = 0, clamped = 0;
    bool was = false;
    const long before = test::heap_allocations();
    for (int i = 0; i < 4000; ++i) {
      const double ph = i * 0.003;
      // Stroke in and out of the surface (depth oscillates around 0), with occasional glitches.
      Vec3 p(12 * std::sin(ph), 10 * std::cos(1.3 * ph),
             std::sin(0.4 * 12 * std::sin(ph)) - 0.8 + std::sin(i * 0.05));
      if (i == 1000) p.x() = std::numeric_limits<double>::quiet_NaN();
      if (i == 2000) p.z() += 100;                                             // jump
      if (i % 1000 >= 500 && i % 1000 < 700) p.z() -= 0.1 * (i % 1000 - 500);  // deep push: clamp
      const Vec3 f = rendering::step(m, st, p, a);
      ++ticks;
      contact += st.collision;
      touches += st.collision && !was;
      clamped += f.norm() > 6.2 - 1e-9;
      was = st.collision;
    }
    EXPECT_EQ(test::heap_allocations() - before, 0) << (a == Algorithm::kTCA ? "TCA" : "CBA");
    EXPECT_EQ(ticks, 4000);
    EXPECT_GT(contact, 500);
    EXPECT_GT(touches, 5);
    EXPECT_GT(clamped, 0);
    EXPECT_GE(st.resets, 2u);
  }
  // The counter itself works (a test that cannot fail is a defect).
  const long probe = test::heap_allocations();
  ::operator delete(::operator new(16));  // (a new-expression could be elided)
  EXPECT_EQ(test::heap_allocations() - probe, 1);
}
