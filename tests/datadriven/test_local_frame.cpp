// Local-frame features (FeatureSet::kLocalFrame): the surface frame is orthonormal and keeps n;
// a model trained in the frame reproduces a law that is linear in the local displacement
// (normal and tangential stiffness differ) on a curved surface exactly, which the world-frame
// features cannot; and rendering is equivariant under rotations that carry the frame along.
#include <gtest/gtest.h>

#include <cmath>

#include "dd_fixtures.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/servo.hpp"

namespace inhap::datadriven {
namespace {

TEST(LocalFrame, SurfaceFrameIsOrthonormalRightHandedAndKeepsTheNormal) {
  for (const Vec3& n0 : {Vec3(0, 0, 1), Vec3(0.3, -0.2, 0.9), Vec3(1, 0, 0), Vec3(0.95, 0.1, 0.2),
                         Vec3(0, -1, 0), Vec3(-0.5, 0.5, -0.7)}) {
    const SurfaceFrame f = surface_frame(n0);
    EXPECT_LT((f.n - n0.normalized()).norm(), 1e-12);
    EXPECT_NEAR(f.t0.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.t1.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.t0.dot(f.n), 0.0, 1e-12);
    EXPECT_NEAR(f.t1.dot(f.n), 0.0, 1e-12);
    EXPECT_NEAR(f.t0.dot(f.t1), 0.0, 1e-12);
    EXPECT_LT((f.t0.cross(f.t1) - f.n).norm(), 1e-12);
    const Vec3 w(0.7, -1.3, 2.1);
    EXPECT_LT((f.to_world(f.to_local(w)) - w).norm(), 1e-12);
  }
  const SurfaceFrame z = surface_frame(Vec3(0, 0, 1));  // +z: the world frame itself
  EXPECT_EQ(z.t0, Vec3::UnitX());
  EXPECT_EQ(z.t1, Vec3::UnitY());
  const SurfaceFrame bad = surface_frame(Vec3(std::nan(""), 0, 1));
  EXPECT_EQ(bad.n, Vec3::UnitZ());
  EXPECT_EQ(surface_frame(Vec3::Zero()).n, Vec3::UnitZ());
}

/// Samples under a sphere of radius 60 mm (a dome top): q on the probe-centre surface, normal
/// n = (q - c)/R, p pressed in by up to 4 mm and displaced tangentially by up to 2 mm; the force
/// is kn * (normal depth) n + kt * (tangential displacement), kn != kt.
struct DomeLaw {
  Vec3 c{0, 0, -40};
  double radius = 60, kn = 1.2, kt = 0.4;
  Vec3 force(const Vec3& p, const Vec3& q) const {
    const Vec3 n = (q - c).normalized(), u = q - p;
    const double un = u.dot(n);
    return kn * un * n + kt * (u - un * n);
  }
  void sample(Rng& rng, double spread, Vec3& p, Vec3& q, Vec3& n) const {
    const double a = rng.uniform(-spread, spread), b = rng.uniform(-spread, spread);
    n = Vec3(std::sin(a), std::sin(b) * std::cos(a), 0).eval();
    n.z() = std::sqrt(std::max(0.0, 1.0 - n.x() * n.x() - n.y() * n.y()));
    q = c + radius * n;
    const SurfaceFrame f = surface_frame(n);
    p = q - f.to_world(Vec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(0.2, 4.0)));
  }
};

TEST(LocalFrame, LearnsALocalLinearLawOnACurvedSurfaceExactly) {
  const DomeLaw law;
  Rng rng(11);
  TrainingSet s;
  for (int i = 0; i < 3000; ++i) {
    Vec3 p, q, n;
    law.sample(rng, 0.6, p, q, n);
    s.p.push_back(p);
    s.q.push_back(q);
    s.n.push_back(n);
    s.v.emplace_back(rng.normal(0, 20), rng.normal(0, 20), rng.normal(0, 10));
    s.f.push_back(law.force(p, q));
  }
  TrainParams prm = test::small_params();
  prm.features = FeatureSet::kLocalFrame;
  const ForceModel local = train_force_model(s, prm);
  prm.features = FeatureSet::kDisplacementProxyVelocity;
  const ForceModel world = train_force_model(s, prm);
  double worst_local = 0, sq_world = 0;
  for (int i = 0; i < 300; ++i) {  // fresh inputs inside the training range
    Vec3 p, q, n;
    law.sample(rng, 0.5, p, q, n);
    const Vec3 v(rng.normal(0, 10), rng.normal(0, 10), rng.normal(0, 5));
    const Vec3 f = law.force(p, q);
    worst_local = std::max(worst_local, (model_force(local, p, v, q, n) - f).norm());
    sq_world += (model_force(world, p, v, q, n) - f).squaredNorm();
  }
  EXPECT_LT(worst_local, 1e-6);
  EXPECT_GT(std::sqrt(sq_world / 300), 1e-3);  // world features: only approximately
}

TEST(LocalFrame, RenderingIsEquivariantUnderRotationsThatCarryTheFrame) {
  // A rotation about world x maps surface_frame(n) onto surface_frame(R n), so p' = q - R(q - p),
  // v' = R v, n' = R n must give f' = R f (q, the location feature, is unchanged).
  const TrainingSet all = test::synthetic_set(2, 6000);
  TrainingSet s = all;
  s.n.assign(s.size(), Vec3::UnitZ());
  TrainParams prm = test::small_params();
  prm.features = FeatureSet::kLocalFrame;
  const ForceModel m = train_force_model(s, prm);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix();
  for (std::size_t i = 0; i < s.size(); i += 97) {
    const Vec3 &p = s.p[i], &q = s.q[i], &v = s.v[i];
    const Vec3 f = model_force(m, p, v, q, Vec3::UnitZ());
    const Vec3 f2 = model_force(m, q - r * (q - p), r * v, q, r * Vec3::UnitZ());
    EXPECT_LT((f2 - r * f).norm(), 1e-9 * (1 + f.norm())) << i;
  }
  // The servo step with the normal gives the same force as model_force after the same history.
  ServoState st;
  for (std::size_t i = 0; i < 50; ++i) servo_step(m, st, s.p[i], s.q[i], s.n[i], true);
  EXPECT_EQ(st.force, model_force(m, s.p[49], st.velocity, s.q[49], s.n[49]));
}

TEST(LocalFrame, TrainingWithoutNormalsIsRejected) {
  TrainingSet s = test::synthetic_set(3, 2000);
  TrainParams prm = test::small_params();
  prm.features = FeatureSet::kLocalFrame;
  EXPECT_THROW(train_force_model(s, prm), Error);
  EXPECT_EQ(feature_set_from_string("local"), FeatureSet::kLocalFrame);
  EXPECT_STREQ(to_string(FeatureSet::kLocalFrame), "local");
}

}  // namespace
}  // namespace inhap::datadriven
