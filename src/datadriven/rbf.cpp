// r^3 radial basis functions (see include/inhap/datadriven/rbf.hpp).
#include "inhap/datadriven/rbf.hpp"

#include <Eigen/LU>
#include <algorithm>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

Eigen::MatrixXd rbf_matrix(const Eigen::MatrixXd& rows, const Eigen::MatrixXd& centres) {
  const Eigen::Index r = rows.rows(), c = centres.rows(), d = rows.cols();
  Eigen::MatrixXd a(r, c);
  // Row-major copy of the rows keeps the inner loop contiguous.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rr = rows;
  for (Eigen::Index j = 0; j < c; ++j) {
    for (Eigen::Index i = 0; i < r; ++i) {
      double s = 0;
      for (Eigen::Index k = 0; k < d; ++k) {
        const double t = rr(i, k) - centres(j, k);
        s += t * t;
      }
      a(i, j) = s * std::sqrt(s);
    }
  }
  return a;
}

Eigen::MatrixXd tail_matrix(const Eigen::MatrixXd& rows) {
  Eigen::MatrixXd p(rows.rows(), rows.cols() + 1);
  p.col(0).setOnes();
  p.rightCols(rows.cols()) = rows;
  return p;
}

double RbfExpansion::eval(const double* x) const {
  constexpr Eigen::Index kChunk = 64;
  const Eigen::Index k = centres.rows(), d = centres.cols();
  double r2[kChunk];
  double acc = 0;
  for (Eigen::Index j0 = 0; j0 < k; j0 += kChunk) {
    const Eigen::Index nb = std::min(kChunk, k - j0);
    for (Eigen::Index j = 0; j < nb; ++j) r2[j] = 0;
    for (Eigen::Index c = 0; c < d; ++c) {
      const double* col = centres.data() + c * k + j0;
      const double xc = x[c];
      for (Eigen::Index j = 0; j < nb; ++j) {
        const double t = xc - col[j];
        r2[j] += t * t;
      }
    }
    const double* w = weights.data() + j0;
    for (Eigen::Index j = 0; j < nb; ++j) acc += w[j] * (r2[j] * std::sqrt(r2[j]));
  }
  if (tail.size() == d + 1) {
    acc += tail[0];
    for (Eigen::Index c = 0; c < d; ++c) acc += tail[c + 1] * x[c];
  }
  return acc;
}

RbfExpansion rbf_interpolate(const Eigen::MatrixXd& centres, const Eigen::VectorXd& values,
                             bool linear_tail) {
  const Eigen::Index n = centres.rows(), d = centres.cols();
  if (values.size() != n) throw Error("RBF interpolation: expected one value per centre");
  const Eigen::Index t = linear_tail ? d + 1 : 0;
  Eigen::MatrixXd sys = Eigen::MatrixXd::Zero(n + t, n + t);
  sys.topLeftCorner(n, n) = rbf_matrix(centres, centres);
  if (t) {
    const Eigen::MatrixXd p = tail_matrix(centres);
    sys.topRightCorner(n, t) = p;
    sys.bottomLeftCorner(t, n) = p.transpose();
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + t);
  rhs.head(n) = values;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(sys);
  if (!lu.isInvertible())
    throw Error("RBF interpolation: expected distinct centres, got a singular system");
  const Eigen::VectorXd sol = lu.solve(rhs);
  RbfExpansion e;
  e.centres = centres;
  e.weights = sol.head(n);
  if (t) e.tail = sol.tail(t);
  return e;
}

}  // namespace inhap::datadriven
