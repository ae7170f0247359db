// SpaRSA and CG debiasing against problems with known answers: exact support recovery, a
// brute-force lasso optimum (enumeration of supports and signs), and least-squares optima.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/rbf.hpp"
#include "inhap/datadriven/sparsa.hpp"

namespace inhap::datadriven {
namespace {

Eigen::MatrixXd gaussian(int m, int n, std::uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd a(m, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) a(i, j) = rng.normal() / std::sqrt(m);
  return a;
}

struct Sparse {
  Eigen::MatrixXd a;
  Eigen::VectorXd x, f;
  std::vector<int> support;
};

Sparse sparse_problem(std::uint64_t seed) {
  Sparse s;
  s.a = gaussian(100, 200, seed);
  s.x = Eigen::VectorXd::Zero(200);
  s.support = {7, 31, 64, 102, 150, 188};
  Rng rng(seed + 100);
  for (int j : s.support) s.x[j] = (rng.uniform() < 0.5 ? -1 : 1) * rng.uniform(1.0, 2.0);
  s.f = s.a * s.x;
  return s;
}

TEST(Sparsa, RecoversExactSupportAndDebiasesToTheTruth) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Sparse s = sparse_problem(seed);
    SparsaParams p;
    p.lambda = 1e-3 * (s.a.transpose() * s.f).lpNorm<Eigen::Infinity>();
    p.max_nonzeros = 100;
    p.tolerance = 1e-10;
    const SparsaResult r = sparsa(s.a, s.f, p);
    EXPECT_TRUE(r.converged) << seed;
    ASSERT_EQ(r.support, s.support) << seed;
    Eigen::MatrixXd as(100, 6);
    for (int k = 0; k < 6; ++k) as.col(k) = s.a.col(r.support[static_cast<std::size_t>(k)]);
    Eigen::VectorXd x0(6);
    for (int k = 0; k < 6; ++k) x0[k] = r.w[r.support[static_cast<std::size_t>(k)]];
    const CgResult cg = cg_least_squares(as, s.f, x0, 1e-9);
    ASSERT_TRUE(cg.converged);
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(cg.x[k], s.x[s.support[static_cast<std::size_t>(k)]], 1e-7);
  }
}

TEST(Sparsa, StopsAtTheWantedNumberOfNonZeros) {
  const Sparse s = sparse_problem(4);
  SparsaParams p;
  p.lambda = 1e-8 * (s.a.transpose() * s.f).lpNorm<Eigen::Infinity>();
  p.max_nonzeros = 6;
  const SparsaResult r = sparsa(s.a, s.f, p);
  EXPECT_TRUE(r.reached_nonzeros);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.support, s.support);  // continuation brings the true atoms in first
}

// Exact lasso optimum by enumerating every support S and sign pattern s: the KKT conditions
// A_S^T (f - A_S w) = lambda s, sign(w) = s, |A_j^T (f - A_S w)| <= lambda off S.
double brute_force_lasso(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, double lambda,
                         Eigen::VectorXd& best_w) {
  const int n = static_cast<int>(a.cols()), m = static_cast<int>(a.rows());
  double best = 0.5 * f.squaredNorm();  // w = 0
  best_w = Eigen::VectorXd::Zero(n);
  for (int mask = 1; mask < (1 << n); ++mask) {
    std::vector<int> sup;
    for (int j = 0; j < n; ++j)
      if (mask & (1 << j)) sup.push_back(j);
    const int k = static_cast<int>(sup.size());
    if (k > m) continue;
    Eigen::MatrixXd as(m, k);
    for (int i = 0; i < k; ++i) as.col(i) = a.col(sup[static_cast<std::size_t>(i)]);
    const Eigen::MatrixXd g = as.transpose() * as;
    const Eigen::VectorXd b = as.transpose() * f;
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(g);
    if (qr.rank() < k) continue;
    for (int signs = 0; signs < (1 << k); ++signs) {
      Eigen::VectorXd sg(k);
      for (int i = 0; i < k; ++i) sg[i] = (signs & (1 << i)) ? 1.0 : -1.0;
      const Eigen::VectorXd ws = qr.solve(b - lambda * sg);
      if (((ws.array() * sg.array()) <= 0).any()) continue;
      Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < k; ++i) w[sup[static_cast<std::size_t>(i)]] = ws[i];
      const Eigen::VectorXd corr = a.transpose() * (f - a * w);
      if (corr.lpNorm<Eigen::Infinity>() > lambda * (1 + 1e-9)) continue;
      const double obj = lasso_objective(a, f, w, lambda);
      if (obj < best) {
        best = obj;
        best_w = w;
      }
    }
  }
  return best;
}

TEST(Sparsa, MatchesBruteForceLassoOptimum) {
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    const Eigen::MatrixXd a = gaussian(6, 10, seed);  // under-determined, like A~
    const Eigen::VectorXd f = gaussian(6, 1, seed + 50).col(0) * 3.0;
    for (double ratio : {0.3, 0.05}) {
      const double lambda = ratio * (a.transpose() * f).lpNorm<Eigen::Infinity>();
      Eigen::VectorXd wb;
      const double best = brute_force_lasso(a, f, lambda, wb);
      SparsaParams p;
      p.lambda = lambda;
      p.max_nonzeros = 10;
      p.tolerance = 1e-12;
      p.max_iterations = 200000;
      const SparsaResult r = sparsa(a, f, p);
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " ratio " << ratio);
      EXPECT_TRUE(r.converged);
      EXPECT_NEAR(r.objective, best, 1e-9 * (1 + best));
      EXPECT_NEAR((r.w - wb).lpNorm<Eigen::Infinity>(), 0.0, 1e-5);
      EXPECT_NEAR(lasso_objective(a, f, r.w, lambda), r.objective, 1e-12 * (1 + best));
    }
  }
}

TEST(Sparsa, LockStepColumnsMatchSingleProblems) {
  const Sparse s = sparse_problem(9);
  Eigen::MatrixXd f(100, 2);
  f.col(0) = s.f;
  f.col(1) = gaussian(100, 1, 77).col(0);
  SparsaParams p;
  p.max_nonzeros = 40;
  p.tolerance = 1e-13;
  const std::vector<double> lam{0.01, 0.02};
  const auto multi = sparsa_multi(s.a, f, lam, p);
  for (int c = 0; c < 2; ++c) {
    p.lambda = lam[static_cast<std::size_t>(c)];
    const SparsaResult single = sparsa(s.a, f.col(c), p);
    EXPECT_NEAR((multi[static_cast<std::size_t>(c)].w - single.w).norm(), 0.0, 1e-9);
    EXPECT_EQ(multi[static_cast<std::size_t>(c)].support, single.support);
  }
}

TEST(Sparsa, RejectsBadInput) {
  SparsaParams p;
  p.lambda = 0;
  EXPECT_THROW(sparsa(Eigen::MatrixXd::Ones(3, 4), Eigen::VectorXd::Ones(3), p), Error);
  p.lambda = 1;
  EXPECT_THROW(sparsa(Eigen::MatrixXd::Ones(3, 4), Eigen::VectorXd::Ones(2), p), Error);
}

TEST(CgDebias, ReachesTheLeastSquaresOptimum) {
  const Eigen::MatrixXd b = gaussian(50, 12, 31);
  const Eigen::VectorXd f = gaussian(50, 1, 32).col(0);
  const Eigen::VectorXd ref = b.colPivHouseholderQr().solve(f);
  const CgResult r = cg_least_squares(b, f, Eigen::VectorXd(), 1e-9);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.relative_residual, 1e-9);
  EXPECT_NEAR((r.x - ref).norm() / ref.norm(), 0.0, 1e-8);
  EXPECT_LT((b.transpose() * (f - b * r.x)).norm(), 1e-8);  // normal equations hold
}

TEST(CgDebias, ReachesTheOptimumOnAnRbfSupport) {
  // A realistic, ill-conditioned case: 80 r^3 rows, 40 of the columns as support.
  Rng rng(5);
  Eigen::MatrixXd pts(200, 4);
  for (int i = 0; i < 200; ++i)
    for (int d = 0; d < 4; ++d) pts(i, d) = rng.uniform(-1, 1);
  const Eigen::MatrixXd a = rbf_matrix(pts.topRows(80), pts);
  Eigen::MatrixXd b(80, 40);
  for (int k = 0; k < 40; ++k) b.col(k) = a.col(5 * k);
  Eigen::VectorXd f(80);
  for (int i = 0; i < 80; ++i) f[i] = std::sin(3 * pts(i, 0)) + pts(i, 1);
  const Eigen::VectorXd ref = b.colPivHouseholderQr().solve(f);
  const CgResult r = cg_least_squares(b, f, Eigen::VectorXd(), 1e-9, 100000);
  EXPECT_TRUE(r.converged);
  // Same fitted values as the direct solution (the optimum), even if the weights are ill-posed.
  EXPECT_NEAR((b * r.x - b * ref).norm() / f.norm(), 0.0, 1e-6);
}

}  // namespace
}  // namespace inhap::datadriven
