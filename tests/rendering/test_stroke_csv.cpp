// inhap/rendering/stroke_csv.hpp: a stroke written tick by tick reads back, and its summary
// counts what it should.
#include <gtest/gtest.h>

#include "inhap/core/csv.hpp"
#include "inhap/rendering/stroke_csv.hpp"
#include "support/temp_dir.hpp"

namespace inhap::rendering {
namespace {

std::vector<StrokeSample> samples() {
  std::vector<StrokeSample> s(4);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s[i].time = 0.001 * double(i + 1);
    s[i].hip = Vec3(double(i), 2, -1);
    s[i].force = Vec3(0, 0, i < 2 ? 0.0 : 3.0);
    s[i].contact = i >= 2;
    s[i].k = 0.5;
  }
  return s;
}

TEST(StrokeCsv, SummaryCountsContactAndMeanForce) {
  EXPECT_EQ(stroke_summary(samples()),
            "4 ticks (0.004 s), 2 in contact, mean contact force 3.000 N");
  EXPECT_EQ(stroke_summary({}), "0 ticks (0.000 s), 0 in contact, mean contact force 0.000 N");
}

TEST(StrokeCsv, WrittenColumnsReadBack) {
  test::TempDir dir;
  write_stroke_csv(dir.path("s.csv"), samples(), "inhap tca stroke --test");
  static constexpr std::string_view kCols[] = {"t", "px", "fz", "k", "contact"};
  const CsvTable t = read_csv(dir.path("s.csv"), kCols);
  ASSERT_EQ(t.rows(), 4u);
  EXPECT_DOUBLE_EQ(t.column("px")[3], 3.0);
  EXPECT_DOUBLE_EQ(t.column("fz")[2], 3.0);
  EXPECT_DOUBLE_EQ(t.column("contact")[1], 0.0);
  EXPECT_DOUBLE_EQ(t.column("k")[0], 0.5);
}

}  // namespace
}  // namespace inhap::rendering
