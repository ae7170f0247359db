// fit_head (inhap/geometry/volume.hpp): the head scaled into a cube, distances with it.
#include <gtest/gtest.h>

#include "inhap/geometry/volume.hpp"

namespace inhap {
namespace {

HeadModel box_head() {
  HeadModel h;
  h.mesh.positions = {Vec3(10, 20, 30), Vec3(15, 40, 35), Vec3(12, 22, 31)};  // 5 x 20 x 5 mm
  h.mesh.triangles = {{0, 1, 2}};
  h.mesh.set_property("bone_distance", {1.0, 2.0, 4.0});
  return h;
}

TEST(FitHead, LargestSideBecomesFitMmFromTheOrigin) {
  HeadModel h = box_head();
  EXPECT_DOUBLE_EQ(fit_head(h, 100.0), 5.0);  // 100 mm / 20 mm
  const Box3 b = h.mesh.bbox();
  EXPECT_NEAR(b.min.x(), 0.0, 1e-12);
  EXPECT_NEAR(b.max.y(), 100.0, 1e-12);
  EXPECT_EQ(h.mesh.property("bone_distance"), (std::vector<double>{5.0, 10.0, 20.0}));
}

TEST(FitHead, ZeroKeepsTheScannersMillimetres) {
  HeadModel h = box_head();
  EXPECT_DOUBLE_EQ(fit_head(h, 0.0), 1.0);
  EXPECT_EQ(h.mesh.positions[1], Vec3(15, 40, 35));
  EXPECT_EQ(h.mesh.property("bone_distance"), (std::vector<double>{1.0, 2.0, 4.0}));
}

}  // namespace
}  // namespace inhap
