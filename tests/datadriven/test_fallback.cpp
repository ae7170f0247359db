// The force model's fallback outside the training support (fallback.hpp): the monotone
// depth-force law, the distance to the training proxies and, end to end, a model trained on a
// recording of a known law that stiffens with depth renders that law far from its proxies; off
// the training spots the normal force is the one on the proxy's normal line.
// Units: mm, N.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

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

// Off the training spots the normal force is the model's with the probe on the proxy's normal
// line at the same depth; the tangential force stays the model's. Checked against the same
// model with that blend off (friction cone and envelope off, so nothing else moves the force).
TEST(Fallback, OffTheTrainingSpotsTheNormalForceIsTheNormalLines) {
  TrainParams prm = preset_params("best");
  prm.centers = 60;
  prm.friction_cone = prm.sliding_floor = prm.envelope = false;
  ASSERT_GT(prm.fallback_normal_far_mm, prm.fallback_normal_near_mm);
  ASSERT_LT(prm.fallback_normal_far_mm, prm.fallback_near_mm);
  const ForceModel on = train_force_model(known_law_set(), prm);
  ForceModel off = on;
  off.fallback.normal_near_mm = off.fallback.normal_far_mm = 0;
  const Vec3 n = Vec3::UnitZ(), v(1.0, 0.0, 0.0);
  int blended = 0;
  double moved = 0;  // largest |f_n(line) - f_n(probe)| where the blend is on, N
  // Along y = 0 from inside the explored region (x <= -5 mm) to 5 mm beyond its edge; the
  // probe 2.5 mm deep and 3 mm sideways (ten times the data's tangential spread).
  for (double x = -8.0; x <= 0.0; x += 0.5) {
    const Vec3 q(x, 0.0, 0.0), p = q - 2.5 * n + Vec3(3.0, 1.0, 0.0), line = q - 2.5 * n;
    const double dist = on.fallback.support.distance(q);
    const double wn = on.fallback.normal_weight_at(dist);
    ASSERT_EQ(on.fallback.weight_at(dist), 0.0) << x;  // the law stays out of this test
    const Vec3 f_on = model_force(on, p, v, q, n), f_off = model_force(off, p, v, q, n);
    const Vec3 f_line = model_force(off, line, v, q, n);
    EXPECT_NEAR(f_on.x(), f_off.x(), 1e-9) << x;
    EXPECT_NEAR(f_on.y(), f_off.y(), 1e-9) << x;
    EXPECT_NEAR(f_on.z(), f_off.z() + wn * (f_line.z() - f_off.z()), 1e-9) << x;
    if (dist <= prm.fallback_normal_near_mm) {
      EXPECT_EQ(wn, 0.0) << x;
    }
    if (dist >= prm.fallback_normal_far_mm) {
      EXPECT_EQ(wn, 1.0) << x;
    }
    blended += wn == 1.0;
    if (wn > 0) moved = std::max(moved, std::abs(f_line.z() - f_off.z()));
  }
  EXPECT_GE(blended, 2);   // the walk reached the normal line's own region
  EXPECT_GT(moved, 0.01);  // where the blend is on, the sideways probe's normal force differs
  // A file keeps the blend; a file without its fields (written before it) renders without it.
  const std::string text = force_model_to_json(on);
  const ForceModel back = force_model_from_json(text, "test");
  EXPECT_EQ(back.fallback.normal_far_mm, on.fallback.normal_far_mm);
  auto j = nlohmann::json::parse(text);
  j["fallback"].erase("normal_near_mm");
  j["fallback"].erase("normal_far_mm");
  const ForceModel old = force_model_from_json(j.dump(), "old");
  const Vec3 q(0.0, 0.0, 0.0), p = q - 2.5 * n + Vec3(3.0, 0.0, 0.0);
  EXPECT_EQ(model_force(old, p, v, q, n), model_force(off, p, v, q, n));
  EXPECT_EQ(model_force(back, p, v, q, n), model_force(on, p, v, q, n));
  // Distances the other way round are refused, naming the field.
  j["fallback"]["normal_near_mm"] = 4.0;
  j["fallback"]["normal_far_mm"] = 2.0;
  try {
    force_model_from_json(j.dump(), "bad.json");
    ADD_FAILURE() << "accepted normal_near_mm > normal_far_mm";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("normal_near_mm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace inhap::datadriven
