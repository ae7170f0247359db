#include <gtest/gtest.h>

#include "inhap/contact/contact_io.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/surface/point_io.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

namespace {
std::vector<Contact> two_contacts() {
  Contact a, b;
  a.tap = 0, a.point = Vec3(1, 2, 3), a.direction = Vec3(0, 0, 1), a.t_contact = 0.5,
  a.t_detect = 0.52, a.peak_force = 2.5, a.estimated = true;
  b.tap = 1, b.point = Vec3(-4, 5, 6), b.direction = Vec3(0, 1, 0), b.t_contact = 1.25,
  b.t_detect = 1.25, b.peak_force = 1.0, b.estimated = false;
  return {a, b};
}
}  // namespace

TEST(ContactIo, PointPlyRoundTripsPositionsDirectionsAndProperties) {
  test::TempDir dir;
  const auto path = dir.path("p.ply");
  write_contact_points(path, two_contacts());
  const TriMesh m = read_mesh(path);
  ASSERT_EQ(m.num_vertices(), 2u);
  EXPECT_EQ(m.num_triangles(), 0u);
  EXPECT_EQ(m.positions[1], Vec3(-4, 5, 6));
  EXPECT_DOUBLE_EQ(m.property("t_contact")[1], 1.25);
  EXPECT_DOUBLE_EQ(m.property("estimated")[0], 1.0);
  EXPECT_DOUBLE_EQ(m.property("peak_force")[0], 2.5);
  const PointSet s = read_points(path);
  ASSERT_EQ(s.directions.size(), 2u);
  EXPECT_EQ(s.directions[1], Vec3(0, 1, 0));
}

TEST(ContactIo, PointsWithoutNormalsHaveNoDirections) {
  test::TempDir dir;
  const auto path = dir.path("p.ply");
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  write_mesh(path, m);
  const PointSet s = read_points(path);
  EXPECT_EQ(s.points.size(), 2u);
  EXPECT_TRUE(s.directions.empty());
}

TEST(ContactIo, EmptyContactListWritesAnEmptyCloud) {
  test::TempDir dir;
  const auto path = dir.path("empty.ply");
  write_contact_points(path, {});
  EXPECT_EQ(read_mesh(path).num_vertices(), 0u);
}

TEST(ContactIo, TableHasOneRowPerTap) {
  test::TempDir dir;
  const auto path = dir.path("t.csv");
  write_contact_table(path, two_contacts());
  const CsvTable t = read_csv(path);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_DOUBLE_EQ(t.column("z")[0], 3.0);
  EXPECT_DOUBLE_EQ(t.column("estimated")[1], 0.0);
}
