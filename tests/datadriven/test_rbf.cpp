// r^3 RBF: matrix entries, exact interpolation of its own centres, linear reproduction.
#include <gtest/gtest.h>

#include <cmath>

#include "inhap/core/random.hpp"
#include "inhap/datadriven/rbf.hpp"

namespace inhap::datadriven {
namespace {

Eigen::MatrixXd random_points(int n, int d, std::uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd x(n, d);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < d; ++k) x(i, k) = rng.uniform(-1, 1);
  return x;
}

TEST(Rbf, MatrixEntriesAreCubedDistances) {
  Eigen::MatrixXd rows(2, 2), centres(3, 2);
  rows << 0, 0, 1, 1;
  centres << 3, 4, 0, 0, 1, 3;
  const Eigen::MatrixXd a = rbf_matrix(rows, centres);
  EXPECT_DOUBLE_EQ(a(0, 0), 125.0);  // |(3,4)| = 5
  EXPECT_DOUBLE_EQ(a(0, 1), 0.0);
  EXPECT_NEAR(a(1, 0), std::pow(std::sqrt(13.0), 3), 1e-12);
  EXPECT_DOUBLE_EQ(a(1, 2), 8.0);  // |(0,2)| = 2
}

TEST(Rbf, InterpolatesItsOwnCentres) {
  const Eigen::MatrixXd c = random_points(60, 4, 5);
  Eigen::VectorXd f(60);
  for (int i = 0; i < 60; ++i) f[i] = std::sin(2 * c(i, 0)) + c(i, 1) * c(i, 2) - std::exp(c(i, 3));
  for (bool tail : {false, true}) {
    const RbfExpansion e = rbf_interpolate(c, f, tail);
    for (int i = 0; i < 60; ++i) {
      const Eigen::VectorXd xi = c.row(i).transpose();
      EXPECT_NEAR(e.eval(xi), f[i], 1e-8) << "tail " << tail << " centre " << i;
    }
  }
}

TEST(Rbf, LinearTailReproducesLinearFunctionsEverywhere) {
  const Eigen::MatrixXd c = random_points(40, 3, 8);
  auto lin = [](const Eigen::VectorXd& x) { return 2.0 + 3.0 * x[0] - x[1] + 0.5 * x[2]; };
  Eigen::VectorXd f(40);
  for (int i = 0; i < 40; ++i) f[i] = lin(c.row(i).transpose());
  const RbfExpansion e = rbf_interpolate(c, f, true);
  EXPECT_LT(e.weights.lpNorm<Eigen::Infinity>(), 1e-8);
  const Eigen::MatrixXd probe = random_points(25, 3, 99) * 1.5;  // also outside the hull
  for (int i = 0; i < 25; ++i) {
    const Eigen::VectorXd x = probe.row(i).transpose();
    EXPECT_NEAR(e.eval(x), lin(x), 1e-8);
  }
}

TEST(Rbf, EvalMatchesMatrixProduct) {
  const Eigen::MatrixXd c = random_points(150, 9, 3);  // more than one evaluation chunk
  const Eigen::MatrixXd x = random_points(10, 9, 4);
  RbfExpansion e;
  e.centres = c;
  e.weights = random_points(150, 1, 6).col(0);
  const Eigen::VectorXd ref = rbf_matrix(x, c) * e.weights;
  for (int i = 0; i < 10; ++i) {
    const Eigen::VectorXd xi = x.row(i).transpose();
    EXPECT_NEAR(e.eval(xi), ref[i], 1e-10 * (1 + std::fabs(ref[i])));
  }
}

}  // namespace
}  // namespace inhap::datadriven
