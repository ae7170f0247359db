// True contact time by a two-segment ("knee") fit of the force magnitude (thesis sec. 3.2.2).
// Units: time s, force N (any consistent units work: the fit is affine-invariant in both).
//
// Model (eq. 3.1): over samples (t_i, f_i), i = 0..n-1 (the window [t_{d-N}, t_d]), g(t) is
// the continuous piecewise-linear function through (t_0, g0), (t_c, gc), (t_{n-1}, gd), i.e.
//   g(t) = g0 * a(t) + gc * b(t) + gd * c(t)
// with the "hat" basis a = (t_c - t)/(t_c - t_0), b = (t - t_0)/(t_c - t_0) on [t_0, t_c] and
// b = (t_{n-1} - t)/(t_{n-1} - t_c), c = (t - t_c)/(t_{n-1} - t_c) on [t_c, t_{n-1}].
// For a fixed t_c the SSE E = sum (f_i - g(t_i))^2 is a linear least-squares problem in
// G = (g0, gc, gd): A G = B with A symmetric tridiagonal (the thesis' eq. 3.6-3.7 have typos;
// see docs/shape-modeling.md). The fit minimises E over t_c exactly on every sample time with
// running sums (O(n) total), then optionally refines t_c continuously between the neighbouring
// samples (golden-section search on the exact E(t_c) of each interval).
//
// fit_knee() allocates nothing and throws nothing: usable inside a servo step.
#pragma once

#include <cstddef>
#include <span>

#include "inhap/core/types.hpp"

namespace inhap {

struct KneeOptions {
  /// Refine t_c continuously in the two sample intervals next to the best sample.
  bool refine = true;
};

struct KneeFit {
  bool valid = false;     ///< false: fewer than 4 samples, non-increasing or non-finite input
  double tc = 0;          ///< knee time (s), in (t_0, t_{n-1})
  std::size_t index = 0;  ///< sample index with t[index] <= tc < t[index + 1]
  double g0 = 0, gc = 0, gd = 0;  ///< fitted values at t_0, t_c, t_{n-1} (N)
  double sse = 0;                 ///< sum of squared residuals at the optimum (N^2)
};

/// Fits two connected segments to (t[i], f[i]); t strictly increasing, n >= 4.
KneeFit fit_knee(std::span<const double> t, std::span<const double> f,
                 const KneeOptions& options = {});

/// SSE of the best two-segment fit with the knee forced at `tc` (t_0 < tc < t_{n-1}), by the
/// same closed form as fit_knee(); optionally returns G = (g0, gc, gd). Infinity if degenerate.
double knee_sse_at(std::span<const double> t, std::span<const double> f, double tc,
                   Vec3* g = nullptr);

}  // namespace inhap
