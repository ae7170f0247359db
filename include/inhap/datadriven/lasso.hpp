// l1-regularised least squares (thesis eq. 4.26) solved to optimality with a certificate:
//   min_w  P(w) = lambda ||w||_1 + 1/2 ||A w - f||_2^2
//
// Method (working-set coordinate descent in the manner of glmnet, Friedman, Hastie and
// Tibshirani, J. Stat. Softw. 33(1), 2010):
//   - the working set W starts with the columns most correlated with f; on W, cyclic coordinate
//     descent with covariance updates on the Gram matrix A_W^T A_W (k x k, k = |W|): a
//     coordinate step costs O(k), never a pass over the N rows; every 10 sweeps a Newton step
//     on the non-zeros with their signs fixed (feature-sign search, Lee et al., NIPS 2006)
//     finishes what coordinate descent does slowly on near-collinear r^3 columns;
//   - then one full pass g = A^T r (the only O(N M) work, split over `threads`) checks the KKT
//     conditions |g_j| <= lambda off W; the worst violators join W (at most
//     max(grow_min, grow_factor * non-zeros) at once, so W stays near the support: its Gram
//     matrix is the main cost) and the loop repeats until none is left and the gap is met;
//   - optionally a geometric lambda path from ||A^T f||_inf down to lambda with strong-rule
//     screening (Tibshirani et al., JRSS B 74(2), 2012; off by default: measured slower on
//     the dense r^3 problems, whose strong sets are large).
// The Gram matrix of the whole problem is never formed (only W's), so N can be large.
//
// Certificate: with r = f - A w and theta = r min(1, lambda / ||A^T r||_inf) (dual feasible),
// the dual value is D = theta^T f - 1/2 ||theta||^2 and P(w) - D >= P(w) - P(w*) >= 0. A fit is
// "converged" when gap <= gap_tolerance * P(w); then P(w) is within that fraction of the optimum.
//
// Units: those of A and f (the force model passes dimensionless r^3 values and forces in N).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "inhap/datadriven/sparsa.hpp"

namespace inhap::datadriven {

/// Which l1 solver the force model uses.
enum class L1Solver {
  kCd,      ///< coordinate descent to the optimum with a duality-gap certificate (default)
  kSparsa,  ///< SpaRSA (the thesis' solver), stops on slow progress
};
const char* to_string(L1Solver s);
/// Parses "cd" or "sparsa"; throws inhap::Error otherwise.
L1Solver l1_solver_from_string(const std::string& s);

struct LassoParams {
  /// > 0: keep the largest max_nonzeros in `support` (and, with a path, stop at the first path
  /// solution with at least this many non-zeros).
  int max_nonzeros = 0;
  double gap_tolerance = 1e-6;  ///< relative duality gap (gap / P) that ends a fit
  int max_sweeps = 100000;      ///< coordinate sweeps over the working set, whole path
  double path_ratio = 0;        ///< lambda_{k+1} = max(lambda, ratio lambda_k); 0 = no path
  int threads = 1;              ///< threads of the full passes A^T r
  /// Columns added to the working set at once: at most max(grow_min, grow_factor non-zeros), the
  /// most violating first.
  int grow_min = 16;
  double grow_factor = 1.0;
};

struct LassoResult {
  Eigen::VectorXd w;         ///< the fit
  std::vector<int> support;  ///< indices of its non-zeros (the largest max_nonzeros), ascending
  double lambda = 0;         ///< lambda of the problem w solves (the target, or a path point)
  int iterations = 0;        ///< coordinate sweeps (all path points)
  int passes = 0;            ///< full passes A^T r
  int nonzeros = 0;          ///< non-zeros of w
  double objective = 0;      ///< P(w) at `lambda`
  double gap = 0;            ///< duality gap P(w) - D(theta) at `lambda` (absolute)
  double kkt = 0;            ///< ||A^T (f - A w)||_inf / lambda (<= 1 at the optimum)
  bool converged = false;    ///< gap <= gap_tolerance * objective
  bool reached_nonzeros = false;  ///< stopped on the path at max_nonzeros
};

/// Primal value, dual value of the scaled residual, their gap and ||A^T r||_inf / lambda,
/// computed explicitly (one product A w and one A^T r).
struct LassoCertificate {
  double primal = 0, dual = 0, gap = 0, kkt = 0;
};
LassoCertificate lasso_certificate(const Eigen::MatrixXd& a, const Eigen::VectorXd& f,
                                   const Eigen::VectorXd& w, double lambda);

/// One problem per column of f (each with its own lambda[c]). Throws inhap::Error on
/// mismatched sizes, lambda <= 0 or non-finite input.
std::vector<LassoResult> lasso_cd_multi(const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                                        const std::vector<double>& lambda,
                                        const LassoParams& params);

/// One problem.
LassoResult lasso_cd(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, double lambda,
                     const LassoParams& params);

/// One l1 fit as the force model uses it, whichever solver produced it.
struct L1Fit {
  Eigen::VectorXd w;
  std::vector<int> support;  ///< non-zeros kept (at most max_nonzeros), ascending
  int iterations = 0;        ///< SpaRSA iterations or coordinate sweeps
  int nonzeros = 0;          ///< non-zeros of w
  double relative_gap = 0;   ///< duality gap / objective at the target lambda
};

/// Solves one problem per column of f with `solver`: kCd uses `lasso` (its max_nonzeros keeps
/// the largest), kSparsa uses `sparsa` (lambda taken from `lambda`). The gap of a SpaRSA fit is
/// computed afterwards (one pass over A).
std::vector<L1Fit> solve_l1(L1Solver solver, const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                            const std::vector<double>& lambda, const SparsaParams& sparsa,
                            const LassoParams& lasso);

}  // namespace inhap::datadriven
