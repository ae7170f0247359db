// The force model's fallback outside the training support (fallback.hpp): the monotone
// depth-force law, the distance to the training proxies and, end to end, a model trained on a
// recording of a known law that stiffens with depth renders that law far from its proxies.
// Units: mm, N.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/fallback.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"

namespace inhap::datadriven {
namespace {

// A law that stiffens with depth (not a power law): f = 0.4 d + 0.15 d^2 + 0.02 d^3, N.
double known_law(double d) {
  return 0.4 * d + 0.15 * d * d + 0.02 * d * d * d;
}

TEST(Fallback, DepthLawFollowsAStiffeningLaw) {
  Rng rng(7);
  std::vector<double> d, f;
  for (int i = 0; i < 20000; ++i) {
    const double x = 4.0 * rng.uniform();
    d.push_back(x);
    f.push_back(known_law(x) + 0.05 * rng.normal());  // 50 mN sensor noise
  }
  const DepthLaw law = fit_depth_law(d, f);
  ASSERT_FALSE(law.empty());
  for (std::size_t k = 1; k < law.force_n.size(); ++k)
    EXPECT_GE(law.force_n[k], law.force_n[k - 1]);
  for (double x : {0.5, 1.0, 2.0, 3.0, 3.9})
    EXPECT_NEAR(law.force(x), known_law(x), 0.02 * known_law(x) + 0.02) << "depth " << x;
  // Beyond the data: the deepest quarter's slope, so 4.5 mm is within the law's curvature.
  EXPECT_NEAR(law.force(4.5), known_law(4.5), 0.05 * known_law(4.5));
  EXPECT_EQ(law.force(0.0), 0.0);
  EXPECT_EQ(law.force(-1.0), 0.0);
}

TEST(Fallback, DepthLawIsMonotoneOnNonMonotoneData) {
  // Forces that dip in the middle (e.g. slipping contacts): the isotonic fit pools them.
  std::vector<double> d, f;
  for (int i = 0; i < 300; ++i) {
    const double x = 0.01 * (i + 1);
    d.push_back(x);
    f.push_back(x < 1.0 ? x : (x < 2.0 ? 0.5 : x - 1.0));
  }
  const DepthLaw law = fit_depth_law(d, f, 30);
  for (std::size_t k = 1; k < law.force_n.size(); ++k)
    EXPECT_GE(law.force_n[k], law.force_n[k - 1]);
  EXPECT_LT(law.force(1.5), 1.0);
  EXPECT_GT(law.force(1.5), 0.5);
  EXPECT_TRUE(fit_depth_law({1.0, 2.0}, {1.0, 2.0}).empty());  // too few samples
  EXPECT_THROW(fit_depth_law({1.0}, {}), Error);
}

TEST(Fallback, SupportDistanceIsTheDistanceToTheNearestProxy) {
  std::vector<Vec3> q;
  for (int i = 0; i <= 200; ++i) q.emplace_back(-20.0 + 0.1 * i, 0.0, 0.0);  // a 20 mm segment
  SupportDistance s = make_support_distance(q, 1.0);
  EXPECT_LE(s.points.size(), 22u);  // one per 1 mm voxel
  s.build(12.0);
  for (double off : {0.0, 2.0, 5.0, 9.0}) {
    // Beside the segment and beyond its end.
    EXPECT_NEAR(s.distance(Vec3(-10.0, off, 0.0)), off, 0.08 * off + 0.75) << off;
    EXPECT_NEAR(s.distance(Vec3(off, 0.0, 0.0)), off, 0.08 * off + 0.75) << off;
  }
  EXPECT_EQ(s.distance(Vec3(100.0, 0.0, 0.0)), 12.0);  // outside the grid: the reach
  Fallback fb;
  fb.law = fit_depth_law(std::vector<double>(30, 1.0), std::vector<double>(30, 1.0));
  fb.support = s;
  EXPECT_EQ(fb.weight(Vec3(-10.0, 0.0, 0.0)), 0.0);
  EXPECT_EQ(fb.weight(Vec3(-10.0, 20.0, 0.0)), 1.0);
}

// Training samples on the plane z = 0 (outward normal +z) in x in [-20, -5], y in [-10, 10]:
// pushes to 0..3.5 mm along the normal with small tangential offsets; the force is the known law
// along the normal plus a tangential spring of 0.3 N/mm.
TrainingSet known_law_set() {
  TrainingSet s;
  Rng rng(3);
  for (int i = 0; i < 6000; ++i) {
    const Vec3 q(-20.0 + 15.0 * rng.uniform(), -10.0 + 20.0 * rng.uniform(), 0.0);
    const double depth = 3.5 * rng.uniform();
    const Vec3 ut(0.3 * rng.normal(), 0.3 * rng.normal(), 0.0);
    const Vec3 p = q - depth * Vec3::UnitZ() + ut;
    s.q.push_back(q);
    s.p.push_back(p);
    s.v.push_back(Vec3(rng.normal(), rng.normal(), rng.normal()));
    s.f.push_back(known_law(depth) * Vec3::UnitZ() - 0.3 * ut);
    s.n.push_back(Vec3::UnitZ());
  }
  return s;
}

TEST(Fallback, FarFromTheTrainingProxiesTheModelRendersTheRecordingsLaw) {
  const TrainingSet set = known_law_set();
  TrainParams prm = preset_params("best");
  prm.centers = 60;
  ASSERT_TRUE(prm.fallback);
  const ForceModel m = train_force_model(set, prm);
  ASSERT_FALSE(m.fallback.empty());
  // 25 mm and more beyond the explored region (farther than far_mm from every proxy), straight
  // pushes: the normal force follows the recording's law within 4 % + 20 mN.
  for (double x : {20.0, 30.0})
    for (double depth : {0.5, 1.5, 2.5, 3.3}) {
      const Vec3 q(x, 0.0, 0.0), p = q - depth * Vec3::UnitZ();
      const Vec3 f = model_force(m, p, Vec3::Zero(), q, Vec3::UnitZ());
      EXPECT_NEAR(f.z(), known_law(depth), 0.04 * known_law(depth) + 0.02)
          << "x " << x << " depth " << depth;
      EXPECT_LT(std::hypot(f.x(), f.y()), 0.05);
    }
  // Inside the region the model renders as trained (the fallback's weight is 0 there).
  EXPECT_EQ(m.fallback.weight(Vec3(-12.0, 0.0, 0.0)), 0.0);
  // Saved and read back, the fallback renders the same force.
  const ForceModel back = force_model_from_json(force_model_to_json(m), "test");
  const Vec3 q(25.0, 0.0, 0.0), p = q - 2.0 * Vec3::UnitZ();
  EXPECT_NEAR((model_force(back, p, Vec3::Zero(), q, Vec3::UnitZ()) -
               model_force(m, p, Vec3::Zero(), q, Vec3::UnitZ()))
                  .norm(),
              0.0, 1e-6);
}

}  // namespace
}  // namespace inhap::datadriven
