// eval/solver_bench reached without the program: on a small seeded r^3 problem the certified
// solver lands within its gap tolerance of the optimum and neither solver beats the optimum.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/eval/solver_bench.hpp"

namespace inhap::eval {
namespace {

TEST(SolverBench, CdIsWithinItsGapOfTheOptimumAndSparsaNotBelowIt) {
  SolverBenchOptions o;
  o.points = 600;
  o.centres = 60;
  o.threads = 1;
  const SolverBenchResult r = bench_l1_solver("r3_cube", o);
  EXPECT_EQ(r.rows, 600);
  EXPECT_EQ(r.columns, 60);
  EXPECT_GT(r.optimum, 0);
  EXPECT_LE(r.optimum_gap, 1e-12 * r.optimum * 1.0001);
  // The certificate: P(w) - P(w*) <= gap <= 1e-6 P(w).
  EXPECT_LE(r.cd.gap, o.gap_tolerance * r.cd.objective);
  EXPECT_LE(r.cd.excess, o.gap_tolerance * 1.01);
  EXPECT_GE(r.cd.excess, -1e-10);
  EXPECT_GE(r.sparsa.excess, -1e-10);
  EXPECT_LE(r.cd.kkt, 1.0 + 1e-3);  // ||A^T r||_inf <= lambda at the optimum
  EXPECT_GT(r.cd.nonzeros, 0);
  EXPECT_LE(r.cd.nonzeros, r.columns);
}

TEST(SolverBench, NormalisedProblemHasTheSameShapeAndUnknownNamesAreRejected) {
  SolverBenchOptions o;
  o.points = 300;
  o.centres = 30;
  const datadriven::L1Problem p = make_l1_problem("r3_cube_normalised", o);
  EXPECT_EQ(p.a.rows(), 300);
  EXPECT_EQ(p.a.cols(), 30);
  EXPECT_THROW(make_l1_problem("r4_sphere", o), Error);
}

}  // namespace
}  // namespace inhap::eval
