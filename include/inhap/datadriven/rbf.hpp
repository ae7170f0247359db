// Polyharmonic radial basis functions psi(r) = r^3 (thesis eq. 4.25), optionally with a linear
// polynomial tail a_0 + a^T x (an r^3 interpolant is only conditionally positive definite; the
// thesis omits the tail, so it is off by default in the force model).
//
// Units: the inputs are whatever the caller passes (the force model uses normalised,
// dimensionless features); the output is in the units of the weights (N in the force model).
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace inhap::datadriven {

inline double psi(double r) {
  return r * r * r;
}

/// A(i, j) = psi(||rows_i - centres_j||): rows R x D, centres C x D, result R x C.
Eigen::MatrixXd rbf_matrix(const Eigen::MatrixXd& rows, const Eigen::MatrixXd& centres);

/// Linear tail basis [1, x^T] of every row: R x (D+1).
Eigen::MatrixXd tail_matrix(const Eigen::MatrixXd& rows);

/// A sum of r^3 kernels: s(x) = sum_j w_j psi(||x - c_j||) [+ tail_0 + tail_{1..D}^T x].
/// Centres are stored K x D column-major so that evaluation vectorises over centres.
struct RbfExpansion {
  Eigen::MatrixXd centres;  ///< K x D
  Eigen::VectorXd weights;  ///< K
  Eigen::VectorXd tail;     ///< empty, or D+1 coefficients (constant first)

  int dim() const { return static_cast<int>(centres.cols()); }
  int size() const { return static_cast<int>(centres.rows()); }
  /// Evaluates at x (dim() values). No allocation.
  double eval(const double* x) const;
  double eval(const Eigen::VectorXd& x) const { return eval(x.data()); }
};

/// Exact interpolation through (centres_i, values_i): solves A w = f, or with `linear_tail` the
/// saddle system [A P; P^T 0][w; a] = [f; 0]. Throws inhap::Error when the system is singular.
RbfExpansion rbf_interpolate(const Eigen::MatrixXd& centres, const Eigen::VectorXd& values,
                             bool linear_tail);

}  // namespace inhap::datadriven
