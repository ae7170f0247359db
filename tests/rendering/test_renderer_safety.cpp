// Renderer safety: bad input, force clamp, huge jumps, fast motion through thin surfaces, and
// finely tessellated meshes. Units: mm, N, N/mm.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "inhap/core/random.hpp"
#include "inhap/rendering/renderer.hpp"
#include "rendering/render_fixtures.hpp"

using namespace inhap;
using rendering::Algorithm;

namespace {

const Algorithm kBoth[] = {Algorithm::kCBA, Algorithm::kTCA};

// Touch a plane z = 0 from above and press to `depth`.
void touch(const rendering::Model& m, rendering::State& st, double x, double y, double depth,
           Algorithm a) {
  rendering::step(m, st, Vec3(x, y, 1), a);
  for (int i = 1; i <= 20; ++i) rendering::step(m, st, Vec3(x, y, 1 - (1 + depth) * i / 20.0), a);
}

}  // namespace

TEST(RendererSafety, NonFiniteOrAbsurdInputGivesZeroForceAndResets) {
  rendering::Model m(test::flat_plane(20, 20, 1, -10, -10));
  const double bad[] = {std::nan(""), std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity(), 1e9};
  for (Algorithm a : kBoth)
    for (double b : bad)
      for (int axis = 0; axis < 3; ++axis) {
        rendering::State st;
        touch(m, st, 1, 2, 1.0, a);
        ASSERT_TRUE(st.collision);
        ASSERT_GT(st.force.z(), 0);
        Vec3 p(1, 2, -1);
        p[axis] = b;
        const Vec3 f = rendering::step(m, st, p, a);
        EXPECT_EQ(f, Vec3::Zero());
        EXPECT_FALSE(st.collision);
        EXPECT_EQ(st.resets, 1u);
        EXPECT_EQ(st.force, Vec3::Zero());
        EXPECT_EQ(st.t, Vec3::Zero());
        // Recovers: the probe is inside, so it is felt again only after leaving and coming back.
        EXPECT_EQ(rendering::step(m, st, Vec3(1, 2, -1), a), Vec3::Zero());
        EXPECT_EQ(rendering::step(m, st, Vec3(1, 2, -0.5), a), Vec3::Zero());
        rendering::step(m, st, Vec3(1, 2, 0.5), a);
        const Vec3 g = rendering::step(m, st, Vec3(1, 2, -0.5), a);
        EXPECT_TRUE(st.collision);
        EXPECT_NEAR((g - Vec3(0, 0, 0.5)).norm(), 0, 1e-9);
      }
}

TEST(RendererSafety, ForceIsClampedToTheDeviceLimit) {
  for (Algorithm a : kBoth) {
    rendering::Model m(test::flat_plane(20, 20, 1, -10, -10, 1.0));
    rendering::State st;
    touch(m, st, 0.5, 0.5, 20.0, a);
    ASSERT_TRUE(st.collision);
    EXPECT_NEAR((st.force - Vec3(0, 0, 6.2)).norm(), 0, 1e-12);
    rendering::Params p3;
    p3.force_limit_n = 3.0;
    rendering::Model m3(test::flat_plane(20, 20, 1, -10, -10, 1.0), p3);
    rendering::State s3;
    touch(m3, s3, 0.5, 0.5, 4.0, a);
    EXPECT_NEAR((s3.force - Vec3(0, 0, 3.0)).norm(), 0, 1e-12);
    // The proxy stays on the surface even though the force saturates.
    EXPECT_NEAR(s3.ihip.point.z(), 0, 1e-12);
  }
}

TEST(RendererSafety, HugeJumpNeverLeavesTheProxyStuckInside) {
  // An 80 x 80 x 60 mm box: jumps of 50-60 mm land deep inside it, longer ones beyond it.
  rendering::Model m(test::closed_box(Vec3(-40, -40, -60), Vec3(40, 40, 0), 4));
  for (Algorithm a : kBoth)
    for (double jump : {50.0, 60.0, 200.0, 5000.0}) {
      rendering::State st;
      touch(m, st, 1, 1, 1.0, a);
      ASSERT_TRUE(st.collision);
      // Jump (a tracking glitch) from the top face to deep inside the cube or far away.
      const double dz = 0.8 * jump;
      const Vec3 target = jump < 100 ? Vec3(1, 1 + 0.6 * jump, -1 - dz) : Vec3(jump, 0, -10);
      ASSERT_GE((target - Vec3(1, 1, -1)).norm(), 50.0);
      const Vec3 f = rendering::step(m, st, target, a);
      EXPECT_EQ(f, Vec3::Zero()) << jump;
      EXPECT_FALSE(st.collision);
      EXPECT_EQ(st.resets, 1u);
      // No force while inside (no stale proxy on the top face pulling the hand up) ...
      Vec3 p = target;
      if (jump < 100) {
        for (int i = 0; i < 30; ++i) {
          p += Vec3(0.1, 0, -0.3);
          EXPECT_EQ(rendering::step(m, st, p, a), Vec3::Zero());
        }
        // ... leaving through the top face and coming back is detected normally.
        while (p.z() < 2) {
          p.z() += 0.9;
          EXPECT_EQ(rendering::step(m, st, p, a), Vec3::Zero()) << p.z();
        }
      } else {
        p = Vec3(3, 3, 2);
        for (int i = 0; i < 3; ++i) rendering::step(m, st, p + Vec3(0, 0, i * 0.1), a);  // settle
        p = p + Vec3(0, 0, 0.2);
      }
      while (!st.collision && p.z() > -5) rendering::step(m, st, p += Vec3(0, 0, -0.1), a);
      ASSERT_TRUE(st.collision) << jump;
      EXPECT_NEAR(st.ihip.point.z(), 0, 1e-9);
      EXPECT_GT(st.force.z(), 0);
    }
}

TEST(RendererSafety, JumpBelowThresholdFromOutsideIsDetectedAtTheEntryFace) {
  // 15 mm in one tick from above the cube to its inside: the sweep finds the top face.
  rendering::Model m(test::closed_box(Vec3(-20, -20, -40), Vec3(20, 20, 0), 4));
  for (Algorithm a : kBoth) {
    rendering::State st;
    rendering::step(m, st, Vec3(0, 0, 5), a);
    const Vec3 f = rendering::step(m, st, Vec3(0, 0, -10), a);
    EXPECT_TRUE(st.collision);
    EXPECT_NEAR(st.ihip.point.z(), 0, 1e-9);
    EXPECT_NEAR((f - Vec3(0, 0, 6.2)).norm(), 0, 1e-9);  // 10 N at 1 N/mm, clamped
  }
}

TEST(RendererSafety, FastMotionNeverTunnelsThroughASingleSheet) {
  // One-sided sheet z = 0 (normal +z), two triangles; the probe moves 1 mm per tick (1 m/s).
  TriMesh sheet;
  sheet.positions = {{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  rendering::Model m(sheet);
  Rng rng(5);
  for (Algorithm a : kBoth)
    for (int trial = 0; trial < 20; ++trial) {
      rendering::State st;
      Vec3 p(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(0.01, 3));
      const Vec3 dir = Vec3(rng.uniform(-0.7, 0.7), rng.uniform(-0.7, 0.7), -1).normalized();
      rendering::step(m, st, p, a);
      bool touched = false;
      for (int i = 0; i < 25; ++i) {
        p += dir;  // 1 mm per tick
        const Vec3 f = rendering::step(m, st, p, a);
        if (p.z() < 0) {
          touched = true;
          ASSERT_TRUE(st.collision) << trial << " tick " << i;
          EXPECT_NEAR(st.ihip.point.z(), 0, 1e-9);
          EXPECT_GT(f.z(), 0);
          EXPECT_NEAR(f.norm(), std::min(6.2, -p.z()), 1e-9);
        }
      }
      EXPECT_TRUE(touched);
      // From behind, a one-sided sheet is not felt (documented behaviour).
      rendering::State back;
      rendering::step(m, back, Vec3(0, 0, -5), a);
      for (int i = 0; i < 10; ++i)
        EXPECT_EQ(rendering::step(m, back, Vec3(0, 0, -4.5 + i), a), Vec3::Zero());
    }
}

TEST(RendererSafety, FastMotionNeverTunnelsThroughAThinClosedBox) {
  // A 0.5 mm thick plate (closed box): the probe crosses it in one tick.
  rendering::Model m(test::closed_box(Vec3(-30, -30, -0.5), Vec3(30, 30, 0), 6));
  Rng rng(9);
  for (Algorithm a : kBoth)
    for (int trial = 0; trial < 20; ++trial) {
      rendering::State st;
      Vec3 p(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(0.01, 1.0));
      const Vec3 dir = Vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), -1).normalized();
      rendering::step(m, st, p, a);
      for (int i = 0; i < 12; ++i) {
        p += dir;
        const Vec3 f = rendering::step(m, st, p, a);
        if (p.z() < 0) {
          // Pushed up by the top face, never down by the bottom one.
          ASSERT_TRUE(st.collision) << trial << " tick " << i;
          EXPECT_NEAR(st.ihip.point.z(), 0, 1e-9);
          EXPECT_NEAR((f.normalized() - Vec3::UnitZ()).norm(), 0, 1e-9);
        }
      }
    }
}

TEST(RendererSafety, FinelyTessellatedWavySurfaceNeverLosesContactAtOneMetrePerSecond) {
  // z = 0.5 sin(2 pi x / 6) sampled every 0.05 mm (edges 0.05 mm, 64k triangles); the probe
  // strokes 0.5 mm below the surface at 1 mm per tick, i.e. across ~40 triangles per tick.
  const double h = 0.05;
  auto height = [](double x, double) { return 0.5 * std::sin(2 * M_PI * x / 6.0); };
  rendering::Model m(test::grid_mesh(int(40 / h), int(2 / h), h, 0, -1, height,
                                     [](double, double) { return 1.0; }));
  for (Algorithm a : kBoth) {
    rendering::State st;
    Vec3 p(1.0, 0.01, height(1.0, 0) + 1);
    rendering::step(m, st, p, a);
    p.z() = height(1.0, 0) - 0.5;
    rendering::step(m, st, p, a);
    ASSERT_TRUE(st.collision);
    std::uint32_t max_steps = 0;
    for (int i = 0; i < 240; ++i) {
      // Back and forth along x with a little y wobble, always 0.5 mm below the surface.
      const double x = 1.0 + 37.0 * (0.5 - 0.5 * std::cos(i * 2 * M_PI / 80.0));
      const double y = 0.6 * std::sin(i * 0.37);
      const Vec3 next(x, y, height(x, y) - 0.5);
      p = next;
      const Vec3 f = rendering::step(m, st, p, a);
      ASSERT_TRUE(st.collision) << "tick " << i;
      // The proxy keeps up: it is (nearly) the surface point nearest to p. On a polyhedral
      // surface seen from inside, every face whose foot point lies inside it is a local minimum
      // of |q - p| (for the classic god-object too), so it may rest a face or so away from the
      // global one: allow 0.03 mm (< one 0.05 mm edge) and 1 um of extra distance, against
      // the 1 mm the HIP moves per tick.
      const ClosestPoint cp = m.index().closest_point(p);
      const Vec3 q = st.ihip.point - st.t;
      EXPECT_LT((q - cp.point).norm(), 0.03) << "tick " << i;
      EXPECT_LT((q - p).norm() - std::sqrt(cp.distance2), 1e-3) << "tick " << i;
      if (a == Algorithm::kCBA) {
        EXPECT_NEAR(f.norm(), std::sqrt(cp.distance2), 0.02) << "tick " << i;
      }
      max_steps = std::max(max_steps, st.walk_steps);
    }
    EXPECT_GT(max_steps, 20u);  // many tiny triangles crossed in one tick
    EXPECT_EQ(st.fallbacks, 0u);
  }
}

TEST(RendererSafety, FinelyTessellatedSphereKeepsContactAtOneMetrePerSecond) {
  // Icosphere of radius 3 mm with ~0.05 mm edges (82k triangles); the probe circles it 0.3 mm
  // inside at 1 mm per tick.
  const double R = 3.0, depth = 0.3;
  rendering::Model m(test::icosphere(R, 6));
  for (Algorithm a : kBoth) {
    rendering::State st;
    rendering::step(m, st, Vec3(R + 1, 0, 0), a);
    rendering::step(m, st, Vec3(R - depth, 0, 0), a);
    ASSERT_TRUE(st.collision);
    for (int i = 1; i <= 60; ++i) {
      const double phi = i * 1.0 / (R - depth);  // 1 mm of arc per tick
      const Vec3 p = (R - depth) * Vec3(std::cos(phi), std::sin(phi) * std::cos(0.3 * phi),
                                        std::sin(phi) * std::sin(0.3 * phi))
                                       .normalized();
      const Vec3 f = rendering::step(m, st, p, a);
      ASSERT_TRUE(st.collision) << i;
      EXPECT_NEAR((st.ihip.point - st.t).norm(), R, 0.01) << i;
      EXPECT_GT(f.normalized().dot(p.normalized()), 0.99) << i;
      EXPECT_NEAR(f.norm(), depth, 0.02) << i;
    }
  }
}

TEST(RendererSafety, GlobalFallbackHelpsAWalkOutOfBudgetButNeverCrossesAThinWall) {
  // Budget of 1 triangle move per tick: on a plane the global closest point takes over.
  rendering::Params tight;
  tight.max_walk_steps = 1;
  rendering::Model plane(test::flat_plane(100, 100, 0.1, -5, -5), tight);
  for (Algorithm a : kBoth) {
    rendering::State st;
    touch(plane, st, -4, -4, 0.5, a);
    ASSERT_TRUE(st.collision);
    for (int i = 1; i <= 8; ++i) {
      const Vec3 p(-4 + i, -4 + 0.7 * i, -0.5);  // ~12 cells per tick
      const Vec3 f = rendering::step(plane, st, p, a);
      ASSERT_TRUE(st.collision);
      EXPECT_NEAR((st.ihip.point - Vec3(p.x(), p.y(), 0)).norm(), 0, 1e-9) << i;
      EXPECT_NEAR((f - Vec3(0, 0, 0.5)).norm(), 0, 1e-9);
    }
    EXPECT_GT(st.fallbacks, 0u);
  }
  // A 0.5 mm plate pressed 2 mm deep (the HIP is below the bottom face, i.e. outside the plate
  // as seen from the bottom): the global closest point is on the bottom face and disagrees on
  // inside/outside, so it is refused and the push stays upward.
  rendering::Params none;
  none.max_walk_steps = 0;
  rendering::Model plate(test::closed_box(Vec3(-30, -30, -0.5), Vec3(30, 30, 0), 6), none);
  for (Algorithm a : kBoth) {
    rendering::State st;
    rendering::step(plate, st, Vec3(1, 1, 1), a);
    rendering::step(plate, st, Vec3(1, 1, -2), a);
    ASSERT_TRUE(st.collision);
    for (int i = 1; i <= 20; ++i) {
      const Vec3 f = rendering::step(plate, st, Vec3(1 + i, 1 + 0.5 * i, -2), a);
      ASSERT_TRUE(st.collision) << i;
      EXPECT_NEAR(st.ihip.point.z(), 0, 1e-12) << i;
      EXPECT_GT(f.z(), 0) << i;
    }
    EXPECT_GT(st.fallbacks, 0u);
  }
}
