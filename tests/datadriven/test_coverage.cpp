// Training coverage (coverage.hpp): cells visited by the proxy with their force range, the
// support test and the file round trip. Units: mm, N.
#include <gtest/gtest.h>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace {

// Proxies along the x axis from 0 to 30 mm (one every 0.1 mm) with |f| = x / 10 N.
CoverageMap line_map() {
  std::vector<Vec3> q, f;
  for (int i = 0; i <= 300; ++i) {
    q.emplace_back(0.1 * i, 0.5, 0.5);
    f.emplace_back(0, 0, 0.01 * i);
  }
  return CoverageMap(q, f);
}

TEST(Coverage, CellsKeepCountsAndLargestForce) {
  const CoverageMap m = line_map();
  // 3 mm cells: x in [0, 3) ... [30, 33): 11 cells; 30 samples in each full cell.
  ASSERT_EQ(m.cells().size(), 11u);
  EXPECT_EQ(m.cells()[0].samples, 30u);
  EXPECT_NEAR(m.cells()[0].f_max, 0.29, 1e-12);
  EXPECT_NEAR(m.cells()[9].f_max, 2.99, 1e-12);
}

TEST(Coverage, SupportIsNearAVisitedCellAndWithinItsForceRange) {
  const CoverageMap m = line_map();
  EXPECT_FALSE(m.outside(Vec3(15, 0.5, 0.5)));
  EXPECT_FALSE(m.outside(Vec3(15, 3.5, 0.5)));  // next cell over
  EXPECT_TRUE(m.outside(Vec3(15, 7.0, 0.5)));   // two cells away
  EXPECT_TRUE(m.outside(Vec3(-7, 0.5, 0.5)));
  // At x = 15 mm the neighbourhood (x 12..21 mm) reached 2.09 N: 1.2 * 2.09 + 0.5 = 3.008 N.
  EXPECT_NEAR(m.neighbourhood_force(Vec3(15, 0.5, 0.5)), 2.09, 1e-12);
  EXPECT_FALSE(m.outside(Vec3(15, 0.5, 0.5), 3.0));
  EXPECT_TRUE(m.outside(Vec3(15, 0.5, 0.5), 3.1));
}

TEST(Coverage, FileRoundTripAndBadInput) {
  inhap::test::TempDir dir;
  const CoverageMap m = line_map();
  EXPECT_EQ(coverage_path_for(dir.path("model.json")), dir.path("model.coverage.csv"));
  write_coverage(dir.path("c.csv"), m);
  const CoverageMap r = read_coverage(dir.path("c.csv"));
  ASSERT_EQ(r.cells().size(), m.cells().size());
  for (std::size_t i = 0; i < r.cells().size(); ++i) {
    EXPECT_EQ(r.cells()[i].index, m.cells()[i].index);
    EXPECT_EQ(r.cells()[i].samples, m.cells()[i].samples);
    EXPECT_DOUBLE_EQ(r.cells()[i].f_max, m.cells()[i].f_max);
  }
  write_file_atomic(dir.path("bad.csv"), "x,y,z,cell_mm,samples,f_max_n\n0,0,0,-3,1,1\n");
  EXPECT_THROW(read_coverage(dir.path("bad.csv")), ParseError);
}

}  // namespace
}  // namespace inhap::datadriven

namespace inhap::datadriven {
namespace {

TEST(Coverage, GapsAreTheLargestUnvisitedAreasLargestFirst) {
  // Visited: a 30 x 30 mm square (3 mm cells, 10 x 10) except a 4 x 4-cell hole whose cells span
  // x, y in [12, 24) mm, and a single missing cell at x, y in [0, 3) mm.
  std::vector<Vec3> q, f;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      if ((i >= 4 && i < 8 && j >= 4 && j < 8) || (i == 0 && j == 0)) continue;
      q.emplace_back(3.0 * i + 1.5, 3.0 * j + 1.5, 0.0);
      f.emplace_back(0.0, 0.0, 1.0);
    }
  const CoverageMap map(q, f);
  const std::vector<CoverageGap> gaps = coverage_gaps(map);
  ASSERT_EQ(gaps.size(), 2u);
  EXPECT_EQ(gaps[0].cells, 16u);
  EXPECT_NEAR(gaps[0].x_mm, 18.0, 1e-9);
  EXPECT_NEAR(gaps[0].y_mm, 18.0, 1e-9);
  EXPECT_EQ(gaps[1].cells, 1u);
  EXPECT_NEAR(gaps[1].x_mm, 1.5, 1e-9);
  EXPECT_EQ(coverage_gaps(map, 1).size(), 1u);
  EXPECT_TRUE(coverage_gaps(CoverageMap()).empty());
}

}  // namespace
}  // namespace inhap::datadriven
