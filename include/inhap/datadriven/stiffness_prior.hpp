// Local stiffness prior of the data-driven force model: f_n ~ k(q) d^alpha.
//
// Units: q in mm, depth d (the normal part of the elastic displacement, n . (q - p)) in mm,
// force in N, k in N/mm^alpha.
//
// The RBF expansions of a bin interpolate f(q - p, q, pdot); where the training run pressed a
// spot only shallowly, a deep push there borrows the deep response of the nearest spots that
// were pressed deep, even when those are stiffer or softer. The prior carries what the shallow
// data say about the local stiffness down to any depth: log f_n = log k(q) + alpha log d, with
// log k(q) a smooth map over the proxy's location and one exponent alpha for the object, fitted
// by backfitting (alternating least squares) on the in-contact training samples:
//   * given alpha, log k on a regular 3-D grid over q (cell `cell`) = Gaussian-weighted (sigma)
//     mean of log f_n,i - alpha log d_i of the samples near the node (splatted trilinearly, then
//     blurred separably), shrunk with the weight of `prior_weight` samples towards a
//     Gaussian-weighted local-linear fit at 2.5 sigma (moments splatted and blurred the same
//     way; the slope lightly ridge-regularised), itself shrunk towards the local-linear fit at
//     6 sigma and that towards the global mean. So a gap in the data is filled from the data
//     around it, following their trend: at the rim of the explored region the stiffness keeps
//     falling or rising as it did, instead of taking the mean of the data behind it. Then the
//     residuals are smoothed (sigma) and added ("twicing");
//   * given the map, alpha = the least-squares slope (through the origin) of
//     log f_n,i - log k(q_i) against log d_i, clamped to [0.5, 3].
// Samples with d < min_depth or f_n < min_force are left out of the fit (log of noise).
// The same fit serves the shear prior (TrainParams::shear_prior): |f_t| = k_t(q) |u_t|^beta, with
// the tangential displacement |u_t| in the place of d.
// Rendering: k(q) by trilinear interpolation (q clamped into the grid), d^alpha for d > 0, 0
// otherwise: a handful of flops, no allocation.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

struct StiffnessPriorParams {
  double cell = 1.0;          ///< grid spacing, mm
  double sigma = 1.5;         ///< Gaussian smoothing radius over q, mm
  double min_depth = 0.5;     ///< samples shallower than this are not fitted, mm
  double min_force = 0.2;     ///< samples with a smaller normal force are not fitted, N
  double prior_weight = 1.0;  ///< shrinkage towards the coarser level, in samples
  int iterations = 6;         ///< backfitting rounds
  void validate() const;      ///< throws inhap::Error on out-of-range values
};

struct StiffnessPrior {
  double exponent = 0;               ///< alpha (0: empty map, normal_force() = 0)
  Vec3 origin = Vec3::Zero();        ///< position of node (0, 0, 0), mm
  double cell = 1.0;                 ///< grid spacing, mm
  std::array<int, 3> dims{0, 0, 0};  ///< nodes per axis
  std::vector<double> log_k;         ///< ln k per node (x fastest), k in N/mm^alpha
  std::size_t fitted_samples = 0;    ///< samples used by the fit (diagnostic)

  bool empty() const { return log_k.empty() || !(exponent > 0); }

  /// ln k at q (trilinear; q clamped into the grid). Servo-safe.
  double log_stiffness(const Vec3& q) const {
    double t[3];
    int i0[3];
    for (int a = 0; a < 3; ++a) {
      const int n = dims[static_cast<std::size_t>(a)];
      double g = (q[a] - origin[a]) / cell;
      g = std::fmin(std::fmax(g, 0.0), static_cast<double>(n - 1));
      int i = static_cast<int>(g);
      if (i > n - 2) i = n > 1 ? n - 2 : 0;
      i0[a] = i;
      t[a] = n > 1 ? g - i : 0.0;
    }
    const std::size_t nx = static_cast<std::size_t>(dims[0]);
    const std::size_t nxy = nx * static_cast<std::size_t>(dims[1]);
    const std::size_t sx = dims[0] > 1 ? 1 : 0, sy = dims[1] > 1 ? nx : 0,
                      sz = dims[2] > 1 ? nxy : 0;
    const std::size_t b = static_cast<std::size_t>(i0[0]) + nx * static_cast<std::size_t>(i0[1]) +
                          nxy * static_cast<std::size_t>(i0[2]);
    auto lerp = [](double u, double v, double s) { return u + s * (v - u); };
    const double c00 = lerp(log_k[b], log_k[b + sx], t[0]);
    const double c10 = lerp(log_k[b + sy], log_k[b + sy + sx], t[0]);
    const double c01 = lerp(log_k[b + sz], log_k[b + sz + sx], t[0]);
    const double c11 = lerp(log_k[b + sz + sy], log_k[b + sz + sy + sx], t[0]);
    return lerp(lerp(c00, c10, t[1]), lerp(c01, c11, t[1]), t[2]);
  }

  /// Prior force magnitude k(q) x^alpha for a displacement x (mm): the normal force at depth x
  /// for the stiffness prior, the tangential force at a tangential displacement x for the shear
  /// prior; N. 0 for x <= 0, an empty map or a non-finite input. Servo-safe.
  double force(const Vec3& q, double x) const {
    if (empty() || !(x > 0) || !q.allFinite()) return 0.0;
    return std::exp(log_stiffness(q) + exponent * std::log(x));
  }
  /// The same, named for the stiffness prior: normal force at depth d (mm), N.
  double normal_force(const Vec3& q, double depth) const { return force(q, depth); }
};

/// Fits the map to in-contact samples: proxy q (mm), depth d = n . (q - p) (mm) and normal force
/// f_n = n . f (N). Returns an empty map when fewer than 10 samples pass the depth and force
/// thresholds. Throws inhap::Error on unequal lengths or bad parameters.
StiffnessPrior fit_stiffness_prior(const std::vector<Vec3>& q, const std::vector<double>& depth,
                                   const std::vector<double>& normal_force,
                                   const StiffnessPriorParams& params = {});

/// Checks sizes and finiteness; throws inhap::Error naming what is wrong, prefixed by `where`.
void validate_stiffness_prior(const StiffnessPrior& m, const std::string& where);

}  // namespace inhap::datadriven
