// l1-regularised least squares for the RBF weights (thesis eq. 4.26):
//   min_w  lambda ||w||_1 + 1/2 ||A w - f||_2^2
// solved by SpaRSA (Wright, Nowak and Figueiredo, IEEE TSP 57(7), 2009): iterative shrinkage
// w+ = soft(w - grad/alpha, lambda/alpha) with a Barzilai-Borwein choice of alpha, the
// safeguarded (non-monotone) acceptance test
//   phi(w+) <= max_{i=k-m..k} phi(w_i) - sigma/2 alpha ||w+ - w||^2   (else alpha *= eta),
// and continuation on lambda (a geometric sequence from near ||A^T f||_inf down to lambda).
// It stops at the first continuation stage whose solution has the wanted number of non-zeros
// (keeping the largest if there are more), or when it converges at the final lambda. The weights
// are then debiased: least squares restricted to the support, solved by conjugate gradients on the
// normal equations (CGLS form), relative tolerance 1e-9.
//
// Units: those of A and f (the force model passes dimensionless r^3 values and forces in N).
// Several right-hand sides sharing one A are solved in lock step so that the dominant product
// A^T R reads A once per iteration for all of them; each column is still its own problem.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace inhap::datadriven {

/// What ends a continuation stage.
enum class SparsaStop {
  kStep,       ///< ||w+ - w|| <= tolerance ||w+||
  kObjective,  ///< |phi(w) - phi(w+)| <= tolerance phi(w+)
};

struct SparsaParams {
  double lambda = 0;       ///< target lambda (absolute, > 0)
  int max_nonzeros = 300;  ///< stop at the first stage solution with this many non-zeros
  SparsaStop stop = SparsaStop::kStep;
  double tolerance = 1e-6;     ///< of the stop criterion
  int max_iterations = 20000;  ///< over all continuation stages
  bool continuation = true;
  double continuation_start = 0.5;  ///< first lambda = max(lambda, start * ||A^T f||_inf)
  double continuation_ratio = 0.2;  ///< lambda_{s+1} = max(lambda, ratio * lambda_s)
  int memory = 5;                   ///< non-monotone memory m (0 = monotone)
  double sigma = 1e-2;              ///< sufficient-decrease constant
  double eta = 2.0;                 ///< alpha growth factor on rejection
  double alpha_min = 1e-30, alpha_max = 1e30;
};

struct SparsaResult {
  Eigen::VectorXd w;         ///< final iterate
  std::vector<int> support;  ///< indices of its non-zeros (the largest max_nonzeros), ascending
  int iterations = 0;        ///< accepted iterations
  int rejections = 0;        ///< rejected trial steps (alpha increases)
  int stages = 0;            ///< continuation stages entered
  bool reached_nonzeros = false;  ///< stopped because max_nonzeros was reached
  bool converged = false;         ///< converged at the target lambda
  double objective = 0;           ///< lambda ||w||_1 + 1/2 ||A w - f||^2 at the target lambda
};

/// lambda ||w||_1 + 1/2 ||A w - f||_2^2
double lasso_objective(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, const Eigen::VectorXd& w,
                       double lambda);

/// One problem. Throws inhap::Error on mismatched sizes or lambda <= 0.
SparsaResult sparsa(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, const SparsaParams& params);

/// One problem per column of f (each with its own lambda[c]), solved in lock step.
std::vector<SparsaResult> sparsa_multi(const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                                       const std::vector<double>& lambda,
                                       const SparsaParams& params);

struct CgResult {
  Eigen::VectorXd x;
  int iterations = 0;
  double relative_residual = 0;  ///< ||B^T f - G x|| / ||B^T f||, G the (ridged) B^T B
  bool converged = false;
};

/// Least squares min ||B x - f|| by CG on the normal equations B^T B x = B^T f (B^T B formed
/// once, Jacobi preconditioner), starting from x0 (empty = zero), until ||B^T (f - B x)|| <=
/// tolerance ||B^T f||.
/// With ridge > 0 the normal equations become (B^T B + ridge diag(B^T B)) x = B^T f (a
/// relative Tikhonov term for numerically singular supports; 0 = plain least squares).
CgResult cg_least_squares(const Eigen::MatrixXd& b, const Eigen::VectorXd& f,
                          const Eigen::VectorXd& x0, double tolerance = 1e-9,
                          int max_iterations = 0 /* 0 = 50 * columns + 100 */, double ridge = 0);

}  // namespace inhap::datadriven
