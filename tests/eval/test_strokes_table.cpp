// The table `eval strokes` prints (inhap/eval/strokes.hpp).
#include <gtest/gtest.h>

#include "inhap/eval/strokes.hpp"

namespace inhap::eval {
namespace {

TEST(StrokesTable, RowLinesUpUnderTheHeader) {
  DatasetResult r;
  r.name = "bunny";
  r.triangles = 69451;
  r.strokes = 1;
  r.distortion_tca = 0.2024;
  r.distortion_cba = 0.73;
  r.jump_tca = 0.587;
  r.jump_cba = 1.593;
  r.step_p50_us = 0.1;
  r.step_p99_us = 0.4;
  const std::string h = strokes_table_header(), row = strokes_table_row(r);
  EXPECT_EQ(row,
            "bunny        69451       1     0.202 / 0.730        0.587 / 1.593        0.1 / 0.4   "
            "\n");
  EXPECT_EQ(h.size(), row.size());  // same column widths
}

}  // namespace
}  // namespace inhap::eval
