// Where a stylus reaches an object resting on a table (lab/reach.hpp), against the geometry.
// Units: mm.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/lab/reach.hpp"

namespace inhap::lab {
namespace {

const ContactLaw kLaw{};

// A hemisphere of radius 40 on the table: every point of the dome at least 2 mm above the
// table is reachable along its normal (the normal points up or out), the flat base and the
// 2 mm band above the table are not. Area: dome 2 pi R^2, base pi R^2, band 2 pi R * 2.
TEST(Reach, HemisphereDomeIsReachableItsBaseIsNot) {
  const SoftObject obj(HemisphereShape{Vec3::Zero(), 40.0}, kLaw);
  double area = 0;
  const auto s = sample_object_surface(obj, 20000, 3, &area);
  ASSERT_EQ(s.size(), 20000u);
  const double pi = std::numbers::pi, dome = 2 * pi * 1600, base = pi * 1600;
  EXPECT_NEAR(area, dome + base, 0.03 * (dome + base));
  std::size_t reach = 0;
  for (const auto& x : s) {
    EXPECT_NEAR(obj.query(x.point).distance, 0.0, 1e-6);
    const bool r = reachable(obj, 0.0, x.point, x.normal);
    if (x.point.z() > 2.05) {
      EXPECT_TRUE(r) << x.point.transpose();
    }
    if (x.point.z() < 1.95) {
      EXPECT_FALSE(r) << x.point.transpose();
    }
    reach += r;
  }
  const double expected = (dome - 2 * pi * 40 * 2) / (dome + base);  // 0.633
  EXPECT_NEAR(double(reach) / double(s.size()), expected, 0.015);
}

// A sphere (radius 35) touching the table: a point at polar angle theta (cos c) is reached
// along its normal when the stylus end 50 mm out stays 1 mm above the table,
// 35 + 35 c + 50 c >= 1, i.e. c >= -0.4; the share of the area is (1 + 0.4) / 2 = 0.7.
TEST(Reach, SphereOnTheTableIsReachedDownToWhereTheStylusMeetsTheTable) {
  const SoftObject obj(SphereShape{Vec3(0, 0, 35), 35.0}, kLaw);
  const auto s = sample_object_surface(obj, 20000, 5);
  std::size_t reach = 0;
  for (const auto& x : s) {
    const double c = x.normal.z();
    const bool r = reachable(obj, 0.0, x.point, x.normal);
    if (c > -0.4 + 1e-3) {
      EXPECT_TRUE(r) << c;
    }
    if (c < -0.4 - 1e-3) {
      EXPECT_FALSE(r) << c;
    }
    reach += r;
  }
  EXPECT_NEAR(double(reach) / double(s.size()), 0.7, 0.015);
  EXPECT_EQ(reachable_samples(obj, 0.0, 20000, 5).size(), reach);
}

// A box 80 x 80 x 20 on the table: segments through it are blocked, its top and sides are
// reached along their normals, the bottom and the 2 mm band above the table are not.
TEST(Reach, BoxTopAndSidesAreReachedButNotItsBase) {
  const SoftObject obj(BoxShape{Vec3(0, 0, 10), Vec3(40, 40, 10)}, kLaw);
  EXPECT_TRUE(segment_clear(obj, 0.0, Vec3(0, 0, 21), Vec3(0, 0, 80)));
  EXPECT_FALSE(segment_clear(obj, 0.0, Vec3(-60, 0, 10), Vec3(60, 0, 10)));
  EXPECT_FALSE(segment_clear(obj, 2.0, Vec3(-60, 0, 21), Vec3(60, 0, 21)));  // probe 2 mm
  EXPECT_TRUE(reachable(obj, 0.0, Vec3(0, 0, 20), Vec3::UnitZ()));
  EXPECT_TRUE(reachable(obj, 0.0, Vec3(40, 0, 10), Vec3::UnitX()));
  EXPECT_FALSE(reachable(obj, 0.0, Vec3(40, 0, 1), Vec3::UnitX()));  // the base band
  EXPECT_FALSE(reachable(obj, 0.0, Vec3(0, 0, 0), -Vec3::UnitZ()));  // the base
}

}  // namespace
}  // namespace inhap::lab
