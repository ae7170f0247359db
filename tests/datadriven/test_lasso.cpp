// Coordinate-descent l1 solver against closed forms, the KKT conditions and SpaRSA.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/l1_problems.hpp"
#include "inhap/datadriven/lasso.hpp"
#include "inhap/datadriven/rbf.hpp"

namespace inhap::datadriven {
namespace {

Eigen::MatrixXd random_matrix(int rows, int cols, Rng& rng) {
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = rng.normal();
  return m;
}

TEST(Lasso, OneCoordinateCertificateByHand) {
  // A = [1], f = [3], lambda = 1: w* = 2, P(w*) = 1/2 + 2 = 5/2. At w = 0: r = 3, A^T r = 3,
  // theta = r / 3 = 1, P = 9/2, D = theta f - theta^2 / 2 = 3 - 1/2 = 5/2 (theta is the dual
  // optimum r* = f - w* = 1 here), gap 2.
  const Eigen::MatrixXd a = Eigen::MatrixXd::Ones(1, 1);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(1, 3.0);
  const LassoCertificate at0 = lasso_certificate(a, f, Eigen::VectorXd::Zero(1), 1.0);
  EXPECT_DOUBLE_EQ(at0.primal, 4.5);
  EXPECT_DOUBLE_EQ(at0.dual, 2.5);
  EXPECT_DOUBLE_EQ(at0.gap, 2.0);
  EXPECT_DOUBLE_EQ(at0.kkt, 3.0);
  const LassoResult r = lasso_cd(a, f, 1.0, {});
  EXPECT_NEAR(r.w[0], 2.0, 1e-12);
  EXPECT_NEAR(r.objective, 2.5, 1e-12);
  EXPECT_LE(r.gap, 1e-12);
  EXPECT_TRUE(r.converged);
}

TEST(Lasso, OrthogonalColumnsGiveScaledSoftThresholds) {
  // A = Q diag(d) with orthonormal Q: the problem separates, w_j = soft(d_j q_j^T f, lambda)/d_j^2.
  Rng rng(7);
  const Eigen::MatrixXd q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(random_matrix(50, 12, rng)).householderQ() *
      Eigen::MatrixXd::Identity(50, 12);
  Eigen::VectorXd d(12), f(50);
  for (int j = 0; j < 12; ++j) d[j] = 0.5 + j;
  for (int i = 0; i < 50; ++i) f[i] = rng.normal();
  const Eigen::MatrixXd a = q * d.asDiagonal();
  const double lambda = 0.4 * (a.transpose() * f).lpNorm<Eigen::Infinity>();
  const LassoResult r = lasso_cd(a, f, lambda, {});
  int expected_nonzeros = 0;
  for (int j = 0; j < 12; ++j) {
    const double u = d[j] * q.col(j).dot(f);
    const double w = (u > lambda ? u - lambda : (u < -lambda ? u + lambda : 0.0)) / (d[j] * d[j]);
    expected_nonzeros += w != 0.0;
    EXPECT_NEAR(r.w[j], w, 1e-10) << j;
  }
  EXPECT_GT(expected_nonzeros, 0);
  EXPECT_LT(expected_nonzeros, 12);
  EXPECT_EQ(r.nonzeros, expected_nonzeros);
  EXPECT_TRUE(r.converged);
}

TEST(Lasso, LargeLambdaGivesZero) {
  Rng rng(3);
  const Eigen::MatrixXd a = random_matrix(30, 8, rng);
  const Eigen::VectorXd f = random_matrix(30, 1, rng).col(0);
  const double lmax = (a.transpose() * f).lpNorm<Eigen::Infinity>();
  const LassoResult r = lasso_cd(a, f, 1.01 * lmax, {});
  EXPECT_EQ(r.nonzeros, 0);
  EXPECT_TRUE(r.w.isZero(0));
  EXPECT_DOUBLE_EQ(r.objective, 0.5 * f.squaredNorm());
  EXPECT_TRUE(r.converged);
}

// Small r^3 problem (near-collinear columns, the hard case for coordinate descent).
L1Problem small_r3(bool normalised) {
  L1Problem p = r3_cube_problem(600, 80, 11);
  if (normalised) normalise_columns(p);
  return p;
}

class LassoR3 : public ::testing::TestWithParam<bool> {};

TEST_P(LassoR3, MeetsTheKktConditionsAndTheGap) {
  const L1Problem p = small_r3(GetParam());
  LassoParams lp;
  lp.gap_tolerance = 1e-9;
  const LassoResult r = lasso_cd(p.a, p.f, p.lambda, lp);
  ASSERT_TRUE(r.converged);
  const LassoCertificate c = lasso_certificate(p.a, p.f, r.w, p.lambda);
  EXPECT_LE(c.gap, 1e-9 * c.primal);
  EXPECT_NEAR(c.primal, r.objective, 1e-9 * c.primal);
  // KKT: a_j^T r = lambda sign(w_j) on the support, |a_j^T r| <= lambda off it.
  const Eigen::VectorXd g = p.a.transpose() * (p.f - p.a * r.w);
  int nz = 0;
  for (Eigen::Index j = 0; j < g.size(); ++j) {
    if (r.w[j] != 0.0) {
      ++nz;
      EXPECT_NEAR(g[j], r.w[j] > 0 ? p.lambda : -p.lambda, 1e-4 * p.lambda) << j;
    } else {
      EXPECT_LE(std::fabs(g[j]), p.lambda * (1 + 1e-4)) << j;
    }
  }
  EXPECT_EQ(nz, r.nonzeros);
  EXPECT_GT(nz, 0);
}

TEST_P(LassoR3, IsNoWorseThanSparsaRunLong) {
  const L1Problem p = small_r3(GetParam());
  SparsaParams sp;
  sp.lambda = p.lambda;
  sp.max_nonzeros = static_cast<int>(p.a.cols());
  sp.stop = SparsaStop::kObjective;
  sp.tolerance = 1e-12;
  sp.max_iterations = 200000;
  const SparsaResult s = sparsa(p.a, p.f, sp);
  const LassoResult r = lasso_cd(p.a, p.f, p.lambda, {});
  EXPECT_LE(r.objective, s.objective * (1 + 1e-6));
  // Both certificates bound the same optimum from above and below.
  const LassoCertificate cs = lasso_certificate(p.a, p.f, s.w, p.lambda);
  EXPECT_GE(r.objective, cs.dual - 1e-9 * r.objective);
}

INSTANTIATE_TEST_SUITE_P(RawAndNormalised, LassoR3, ::testing::Bool());

TEST(Lasso, ThreadsDoNotChangeTheResult) {
  const L1Problem p = small_r3(false);
  LassoParams one, two;
  two.threads = 2;
  const LassoResult a = lasso_cd(p.a, p.f, p.lambda, one);
  const LassoResult b = lasso_cd(p.a, p.f, p.lambda, two);
  EXPECT_EQ(a.w, b.w);
}

TEST(Lasso, PathGivesTheSameOptimum) {
  const L1Problem p = small_r3(true);
  LassoParams direct, path;
  direct.gap_tolerance = path.gap_tolerance = 1e-10;
  path.path_ratio = 0.8;
  const LassoResult a = lasso_cd(p.a, p.f, p.lambda, direct);
  const LassoResult b = lasso_cd(p.a, p.f, p.lambda, path);
  EXPECT_NEAR(a.objective, b.objective, 1e-9 * a.objective);
}

TEST(Lasso, MaxNonzerosKeepsTheLargest) {
  const L1Problem p = small_r3(true);
  const LassoResult full = lasso_cd(p.a, p.f, p.lambda, {});
  ASSERT_GT(full.nonzeros, 5);
  LassoParams lp;
  lp.max_nonzeros = 5;
  const LassoResult r = lasso_cd(p.a, p.f, p.lambda, lp);
  ASSERT_EQ(r.support.size(), 5u);
  double smallest_kept = 1e300, largest_dropped = 0;
  for (Eigen::Index j = 0; j < r.w.size(); ++j) {
    const bool kept = std::find(r.support.begin(), r.support.end(), j) != r.support.end();
    if (kept)
      smallest_kept = std::min(smallest_kept, std::fabs(r.w[j]));
    else
      largest_dropped = std::max(largest_dropped, std::fabs(r.w[j]));
  }
  EXPECT_GE(smallest_kept, largest_dropped);
  EXPECT_TRUE(r.reached_nonzeros);
}

TEST(Lasso, SolveL1ReportsTheGapOfBothSolvers) {
  const L1Problem p = small_r3(true);
  Eigen::MatrixXd f(p.f.size(), 2);
  f.col(0) = p.f;
  f.col(1) = -0.5 * p.f;
  const std::vector<double> lambda{p.lambda, 0.5 * p.lambda};
  SparsaParams sp;
  sp.max_nonzeros = static_cast<int>(p.a.cols());
  sp.stop = SparsaStop::kObjective;
  sp.tolerance = 1e-4;
  const auto cd = solve_l1(L1Solver::kCd, p.a, f, lambda, sp, {});
  const auto sa = solve_l1(L1Solver::kSparsa, p.a, f, lambda, sp, {});
  ASSERT_EQ(cd.size(), 2u);
  ASSERT_EQ(sa.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_LE(cd[c].relative_gap, 1e-6);
    const LassoCertificate cert =
        lasso_certificate(p.a, f.col(static_cast<Eigen::Index>(c)), sa[c].w, lambda[c]);
    EXPECT_NEAR(sa[c].relative_gap, cert.gap / cert.primal, 1e-12);
    EXPECT_EQ(sa[c].nonzeros, static_cast<int>((sa[c].w.array() != 0.0).count()));
  }
}

TEST(Lasso, RejectsBadInput) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Ones(4, 2);
  EXPECT_THROW(lasso_cd(a, Eigen::VectorXd::Ones(3), 1.0, {}), Error);
  EXPECT_THROW(lasso_cd(a, Eigen::VectorXd::Ones(4), 0.0, {}), Error);
  Eigen::VectorXd bad = Eigen::VectorXd::Ones(4);
  bad[1] = std::nan("");
  EXPECT_THROW(lasso_cd(a, bad, 1.0, {}), Error);
  EXPECT_EQ(l1_solver_from_string("cd"), L1Solver::kCd);
  EXPECT_EQ(l1_solver_from_string("sparsa"), L1Solver::kSparsa);
  EXPECT_THROW(l1_solver_from_string("ista"), Error);
}

}  // namespace
}  // namespace inhap::datadriven
