// Exact signed distances of the lab's analytic shapes against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/random.hpp"
#include "inhap/lab/shape.hpp"

namespace inhap::lab {
namespace {

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_NEAR((a - b).norm(), 0.0, tol) << a.transpose() << " vs " << b.transpose();
}

TEST(Shape, CylinderDistances) {
  const Shape s = CylinderShape{Vec3(0, 0, 0), 50, 25};
  auto q = s.query(Vec3(3, 4, 35));
  EXPECT_DOUBLE_EQ(q.distance, 10);
  expect_vec(q.normal, Vec3::UnitZ(), 1e-12);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, 20)), -5);     // top is the nearest face
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, 3)), -3);      // bottom
  EXPECT_NEAR(s.distance(Vec3(47, 0, 12)), -3, 1e-12);  // side
  EXPECT_NEAR(s.distance(Vec3(60, 0, 10)), 10, 1e-12);
  EXPECT_NEAR(s.distance(Vec3(0, 60, 35)), std::sqrt(200.0), 1e-12);  // rim corner
  expect_vec(s.query(Vec3(0, 60, 35)).normal, Vec3(0, 1, 1).normalized(), 1e-12);
}

TEST(Shape, DomeAndHemisphereDistances) {
  // Cap of base radius 50, height 30: sphere radius (2500 + 900) / 60, centre below the base.
  const double rs = 3400.0 / 60.0;
  const Vec3 c(0, 0, 30 - rs);
  const Shape dome = DomeShape{Vec3::Zero(), 50, 30};
  EXPECT_NEAR(dome.distance(Vec3(0, 0, 40)), 10, 1e-12);
  const Vec3 dir = Vec3(0.3, -0.2, 1).normalized();
  EXPECT_NEAR(dome.distance(c + (rs + 7) * dir), 7, 1e-12);
  expect_vec(dome.query(c + (rs + 7) * dir).normal, dir, 1e-12);
  EXPECT_NEAR(dome.distance(Vec3(10, 0, -4)), 4, 1e-12);  // under the flat base
  EXPECT_NEAR(dome.distance(Vec3(0, 0, 1)), -1, 1e-12);   // just inside the base
  EXPECT_NEAR(dome.distance(Vec3(60, 0, 0)), 10, 1e-12);  // beside the rim
  const Shape hemi = HemisphereShape{Vec3(1, 2, 0), 40};
  EXPECT_NEAR(hemi.distance(Vec3(1, 2, 50)), 10, 1e-12);
  EXPECT_NEAR(hemi.distance(Vec3(1, 2, 10)), -10, 1e-12);  // nearer the base than the dome
  EXPECT_NEAR(hemi.distance(Vec3(1 + 30, 2, 30)), std::hypot(30.0, 30.0) - 40, 1e-12);
}

TEST(Shape, SphereBoxDistances) {
  const Shape sph = SphereShape{Vec3(0, 0, 35), 35};
  EXPECT_NEAR(sph.distance(Vec3(0, 0, 80)), 10, 1e-12);
  EXPECT_NEAR(sph.distance(Vec3(0, 0, 35)), -35, 1e-12);
  const Shape box = BoxShape{Vec3(0, 0, 15), Vec3(40, 30, 15)};
  EXPECT_NEAR(box.distance(Vec3(5, 5, 40)), 10, 1e-12);
  EXPECT_NEAR(box.distance(Vec3(5, 5, 25)), -5, 1e-12);
  EXPECT_NEAR(box.distance(Vec3(43, 34, 30)), 5, 1e-12);  // corner edge: hypot(3, 4)
  expect_vec(box.query(Vec3(5, 5, 25)).normal, Vec3::UnitZ(), 1e-12);
}

TEST(Shape, RidgedSlabDistances) {
  RidgedSlabShape r;  // 100 x 60 x 20, 6 ridges 6 mm high, 14 mm wide, pitch 100/6
  const Shape s = r;
  const double pitch = 100.0 / 6, xc = -50 + 2.5 * pitch;  // centre of the third ridge
  EXPECT_NEAR(s.distance(Vec3(xc, 0, 30)), 4, 1e-12);      // above the peak at z = 26
  // Above a ridge flank: distance to the line from (xc + 7, 20) to (xc, 26).
  const Vec2 a(xc + 7, 20), b(xc, 26), p(xc + 3, 25);
  const Vec2 e = (b - a).normalized();
  const double line = std::abs((p - a).x() * e.y() - (p - a).y() * e.x());
  EXPECT_NEAR(s.distance(Vec3(p.x(), 0, p.y())), line, 1e-12);
  EXPECT_NEAR(s.distance(Vec3(-50 + pitch, 0, 21)), 1, 1e-12);  // flat valley between ridges
  EXPECT_NEAR(s.distance(Vec3(0, 0, 10)), -10, 1e-12);          // inside: bottom and top equal
  EXPECT_NEAR(s.distance(Vec3(0, 35, 10)), 5, 1e-12);           // beyond the end cap
}

TEST(Shape, DistanceIsOneLipschitzAndNormalIsItsGradient) {
  RidgedSlabShape ridged;
  const Shape shapes[] = {CylinderShape{}, DomeShape{}, HemisphereShape{},
                          SphereShape{},   BoxShape{},  ridged};
  Rng rng(5);
  for (const Shape& s : shapes) {
    const Box3 b = s.bounds();
    for (int i = 0; i < 2000; ++i) {
      Vec3 p, q;
      for (int k = 0; k < 3; ++k) {
        p[k] = rng.uniform(b.min[k] - 20, b.max[k] + 20);
        q[k] = p[k] + rng.uniform(-3, 3);
      }
      EXPECT_LE(std::abs(s.distance(p) - s.distance(q)), (p - q).norm() + 1e-9) << s.type_name();
      const SurfaceQuery sq = s.query(p);
      EXPECT_NEAR(sq.normal.norm(), 1.0, 1e-9);
      EXPECT_NEAR((p - sq.closest).norm(), std::abs(sq.distance), 1e-9);
      EXPECT_NEAR(s.distance(sq.closest), 0.0, 1e-9) << s.type_name();
      if (std::abs(sq.distance) > 1e-3) {  // moving along the normal changes d one-for-one
        const double h = std::min(1e-4, 0.5 * std::abs(sq.distance));
        EXPECT_NEAR(s.distance(p + h * sq.normal) - sq.distance, h, 1e-9) << s.type_name();
      }
    }
  }
}

TEST(Shape, DropFindsWhereTheProbeTouches) {
  const Shape cyl = CylinderShape{Vec3::Zero(), 50, 25};
  auto c = cyl.drop(10, -5, 8);
  ASSERT_TRUE(c.has_value());
  expect_vec(*c, Vec3(10, -5, 33), 1e-6);
  const Shape sph = SphereShape{Vec3(0, 0, 35), 35};
  c = sph.drop(12, 9, 8);
  ASSERT_TRUE(c.has_value());
  expect_vec(*c, Vec3(12, 9, 35 + std::sqrt(43.0 * 43.0 - 144 - 81)), 1e-6);
  EXPECT_FALSE(sph.drop(50, 0, 8).has_value());
  // Sharp tip (radius 0) on the ridged slab's valley floor.
  RidgedSlabShape r;
  c = Shape(r).drop(-50 + 100.0 / 6, 0, 0);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->z(), 20, 1e-6);
}

}  // namespace
}  // namespace inhap::lab
