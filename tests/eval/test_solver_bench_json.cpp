// inhap/eval/solver_bench.hpp: the JSON and the line of `model bench-solver` carry the result.
#include <gtest/gtest.h>

#include "inhap/eval/solver_bench.hpp"

namespace inhap::eval {
namespace {

TEST(SolverBenchJson, FieldsAreTheResults) {
  SolverBenchResult r;
  r.name = "r3_cube";
  r.rows = 600;
  r.columns = 60;
  r.optimum = 2.0;
  r.cd.objective = 2.5;
  r.cd.gap = 0.5;  // relative gap 0.2
  r.cd.nonzeros = 17;
  r.sparsa.time_s = 3.0;
  r.speedup = 1.5;
  const nlohmann::ordered_json j = solver_bench_json(r);
  EXPECT_EQ(j["name"], "r3_cube");
  EXPECT_EQ(j["rows"], 600);
  EXPECT_DOUBLE_EQ(j["relative_gap"].get<double>(), 0.2);
  EXPECT_EQ(j["nonzeros"], 17);
  EXPECT_DOUBLE_EQ(j["baseline"]["time_s"].get<double>(), 3.0);
  const std::string s = solver_bench_line(r);
  EXPECT_EQ(s.rfind("r3_cube (600 x 60): optimum 2; cd 2.5 (", 0), 0u) << s;
  EXPECT_NE(s.find("; 1.5x"), std::string::npos) << s;
}

}  // namespace
}  // namespace inhap::eval
