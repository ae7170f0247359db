// The experiments' library functions reached without the program: known answers on the lab's
// exact shapes. Units: mm, s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "inhap/eval/contacts_lab.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {
namespace {

TEST(EvalLab, PositionAtInterpolatesLinearlyAndClampsAtTheEnds) {
  Recording rec;
  rec.t = {0.0, 1.0, 3.0};
  rec.p = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 4, 0)};
  EXPECT_LT((position_at(rec, 0.25) - Vec3(0.5, 0, 0)).norm(), 1e-12);
  EXPECT_LT((position_at(rec, 2.0) - Vec3(2, 2, 0)).norm(), 1e-12);
  EXPECT_LT((position_at(rec, -5.0) - Vec3(0, 0, 0)).norm(), 1e-12);
  EXPECT_LT((position_at(rec, 9.0) - Vec3(2, 4, 0)).norm(), 1e-12);
}

TEST(EvalLab, ShapeHeightFieldOfThePlanarCylinder) {
  // Cylinder of radius 50 mm and height 25 mm on the table: a probe of radius r rests with its
  // centre at 25 + r over the top and at r on the table.
  const lab::Scene scene = lab::builtin_scene("planar");
  const double r = 2.0, half = 70.0;
  const TriMesh m = shape_height_field(scene, r, half);
  ASSERT_GT(m.num_vertices(), 100u);
  std::size_t top = 0, table = 0;
  for (const Vec3& v : m.positions) {
    const double d = std::hypot(v.x() - scene.region.center.x(), v.y() - scene.region.center.y());
    if (d < 45.0) {
      EXPECT_NEAR(v.z(), 25.0 + r, 1e-9);
      ++top;
    } else if (d > 55.0 && std::abs(v.x()) < half && std::abs(v.y()) < half) {
      EXPECT_NEAR(v.z(), r, 1e-9);
      ++table;
    }
  }
  EXPECT_GT(top, 1000u);
  EXPECT_GT(table, 1000u);
}

TEST(EvalLab, ReferenceMeshOfTheFoamBallLiesOnItsSphere) {
  // The foam ball is a sphere of radius 35 mm centred 35 mm above the table.
  const TriMesh m = reference_mesh(lab::builtin_scene("foam-ball").object.shape());
  ASSERT_GT(m.num_vertices(), 100u);
  ASSERT_GT(m.num_triangles(), 100u);
  double top = -1e300, bottom = 1e300;
  for (const Vec3& v : m.positions) {
    EXPECT_NEAR((v - Vec3(0, 0, 35)).norm(), 35.0, 1e-6);
    top = std::max(top, v.z());
    bottom = std::min(bottom, v.z());
  }
  EXPECT_GT(top, 69.0);  // the whole sphere, not a cap
  EXPECT_LT(bottom, 1.0);
}

}  // namespace
}  // namespace inhap::eval
