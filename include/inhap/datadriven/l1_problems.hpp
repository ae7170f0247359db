// Seeded l1 test problems for the solver benchmark (`inhap model bench-solver`, bench_solver):
//   - "r3_cube": N points uniform in the unit cube, M centres (the first M of another uniform
//     draw), A(i, j) = ||x_i - c_j||^3, f = a smooth function of x plus Gaussian noise,
//     lambda = 0.001 ||A^T f||_inf (issue 19's problem);
//   - "r3_cube_normalised": the same with unit-norm columns (how the force model solves it);
//   - "force_model": one bin of the force model as it is trained by default: the in-contact
//     samples of a synthetic recording (datadriven::synthetic_recording), features (q - p, q, pdot)
//     standardised with weights 1, 3, 0.5, k-means rows as centres (regression design),
//     unit-norm columns, target = f_z minus its linear-tail fit, lambda = 0.001 ||A^T f||_inf.
// Units: dimensionless (unit cube, standardised features); the force model's target is in N.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace inhap::datadriven {

struct L1Problem {
  std::string name;
  Eigen::MatrixXd a;  ///< N x M
  Eigen::VectorXd f;  ///< N
  double lambda = 0;  ///< absolute
};

/// Issue 19's r^3 problem (n points, m centres, noise standard deviation `noise`).
L1Problem r3_cube_problem(int n = 20000, int m = 1000, std::uint64_t seed = 1, double noise = 0.05);

/// Scales every column of a to unit norm (zero columns are left alone) and recomputes lambda as
/// `ratio` ||A^T f||_inf; appends "_normalised" to the name.
void normalise_columns(L1Problem& p, double ratio = 0.001);

/// One force-model bin from `samples` synthetic 1 kHz samples with m k-means centres.
L1Problem force_model_problem(int samples = 65000, int m = 300, std::uint64_t seed = 1);

}  // namespace inhap::datadriven
