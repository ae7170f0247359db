// Writers of height / stiffness maps and point sets give back, through the readers, exactly
// what was written; what a format cannot hold is an error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/grid_io.hpp"
#include "inhap/surface/point_io.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

TEST(GridIo, CsvRoundTripIsExact) {
  test::TempDir dir;
  Rng rng(7);
  Grid g(9, 7);
  for (double& v : g.values) v = (rng.uniform() - 0.5) * std::pow(10.0, rng.uniform() * 8 - 4);
  g.at(0, 0) = 1.0 / 3.0;
  write_grid(dir.path("h.csv"), g);
  const Grid r = read_grid(dir.path("h.csv"));
  ASSERT_EQ(r.width, 9);
  ASSERT_EQ(r.height, 7);
  EXPECT_EQ(r.values, g.values);
}

TEST(GridIo, PgmHoldsIntegerLevelsOnly) {
  test::TempDir dir;
  Grid g(4, 3);
  for (std::size_t i = 0; i < g.values.size(); ++i) g.values[i] = double(i * 5000 + 7);
  g.values.back() = 65535;
  write_grid(dir.path("k.pgm"), g);
  EXPECT_EQ(read_grid(dir.path("k.pgm")).values, g.values);
  g.at(1, 1) = 2.5;
  try {
    write_grid(dir.path("bad.pgm"), g);
    FAIL() << "a fractional level was written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.pgm"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("x 1, y 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_grid(dir.path("k.txt"), g), Error);
}

TEST(PointsIo, RoundTripWithAndWithoutDirections) {
  test::TempDir dir;
  Rng rng(3);
  PointSet s;
  for (int i = 0; i < 50; ++i) {
    s.points.emplace_back(rng.uniform() * 100, rng.uniform() * 100 - 50, rng.uniform() / 3);
    s.directions.push_back(Vec3(rng.uniform(), rng.uniform(), 1).normalized());
  }
  for (bool ascii : {false, true}) {
    write_points(dir.path("p.ply"), s, ascii);
    const PointSet r = read_points(dir.path("p.ply"));
    EXPECT_EQ(r.points, s.points);
    EXPECT_EQ(r.directions, s.directions);
  }
  PointSet bare{s.points, {}};
  write_points(dir.path("bare.ply"), bare);
  EXPECT_EQ(read_points(dir.path("bare.ply")).points, s.points);
  EXPECT_TRUE(read_points(dir.path("bare.ply")).directions.empty());
  s.directions.pop_back();
  EXPECT_THROW(write_points(dir.path("bad.ply"), s), Error);
}

}  // namespace
}  // namespace inhap
