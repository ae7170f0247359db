// Elastic border of one (reference point, f_N, direction) sweep (thesis 4.3.2, fig. 4.7,
// Table 4.1). Units: mm, N.
//
// Each f_T step is loaded twice, with a short (100 ms) and a long (600 ms) plateau. The 2-D
// feature of a step is (||u^p_100||, Delta u^p_plateau = ||u^p_600|| - ||u^p_100||) (tangential
// norms). A weighted 2-means separates elastic from sliding steps; the border is the split of
// the f_T-ordered steps that disagrees least with the cluster labels, moved down past any
// earlier step whose plateau growth is above the noise floor (a step just past the limit creeps
// only a little), and the limit f_T is refined between the last elastic and the first sliding
// step by extrapolating the plateau growth of the first sliding steps to zero (viscous creep
// past the limit grows linearly with the excess load). See
// docs/sliding-yield-surface.md for the weights and why.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::friction {

/// One f_T step of a sweep.
struct BorderStep {
  double f_tangential = 0;  ///< N
  double u_short = 0;       ///< ||u^p|| after the short plateau (tangential), mm
  double u_long = 0;        ///< ||u^p|| after the long plateau (tangential), mm
  double depth = 0;         ///< -u_meas . n_c at t_measurement (short plateau), mm
  double radius = 0;        ///< |tangential part of u_meas| at t_measurement, mm
  bool capped = false;      ///< a cycle was unloaded early (max_slip): the growth is a lower bound
  double f_normal = 0;      ///< commanded f_N, N (0: unknown)
  /// Measured |f_t| / f_n of the reaction force at t_measurement, decomposed at the normal of
  /// the surface under the displaced probe (NaN: unknown).
  double ratio = std::numeric_limits<double>::quiet_NaN();
  /// The same ratio decomposed at the two candidate normals (ForceFrame in sys_model.hpp):
  /// n_c, the normal where the stuck contact began, and the normal of the surface under the
  /// displaced probe. `ratio` is one of them (NaN: unknown).
  double ratio_anchor = std::numeric_limits<double>::quiet_NaN();
  double ratio_probe = std::numeric_limits<double>::quiet_NaN();
  double growth() const { return u_long - u_short; }  ///< Delta u^p_plateau, mm
};

struct BorderOptions {
  // Features a = log(1 + ||u^p_100|| / floor_up), b = log(1 + max(0, Delta) / floor_growth),
  // each divided by its largest value over the sweep (at least log 2, so a sweep of pure noise
  // is not blown up), then weighted.
  double weight_up = 0.5;      ///< weight of ||u^p_100||
  double weight_growth = 1.0;  ///< weight of Delta u^p_plateau
  double floor_up = 0.2;       ///< mm
  double floor_growth = 0.1;   ///< mm
  /// Noise floor of the plateau growth, mm: the sliding cluster must grow at least this much,
  /// and a step growing this much is sliding.
  double min_sliding_growth = 0.03;
  int max_iterations = 100;
  bool refine = true;     ///< extrapolate the growth of the first sliding steps
  int refine_points = 3;  ///< sliding steps used by the extrapolation
};

struct BorderResult {
  std::vector<int> labels;  ///< k-means label per step: 0 elastic, 1 sliding
  std::size_t split = 0;    ///< index of the first sliding step (steps.size(): none)
  /// f_elastic_limit: tangential force at the border in the contact frame under the probe,
  /// ratio_limit * f_N when the measured ratios are known, else f_limit_load, N.
  double f_limit = 0;
  double f_limit_load = 0;  ///< border of the commanded tangential load (frame of n_c), N
  double ratio_limit = std::numeric_limits<double>::quiet_NaN();  ///< measured f_t/f_n there
  double depth = 0;          ///< normal part of u_elastic_limit (depth, positive inward), mm
  double radius = 0;         ///< tangential part of u_elastic_limit, mm
  bool no_sliding = false;   ///< no step slid: f_limit is the last step (a lower bound)
  bool all_sliding = false;  ///< even the first step slid: f_limit is extrapolated below it
  /// Slope of the plateau growth over f_T past the border, mm/N, from the line through the
  /// first sliding steps (0: fewer than two sliding steps; then a known slope may be used).
  double growth_slope = 0;
  /// f_limit extrapolated from a lower f_N level (the border lay beyond the force range).
  bool extrapolated = false;
};

/// Weighted Lloyd k-means in 2-D: distance sum_d feature_weight[d] (x_d - c_d)^2, centroids
/// weighted by sample_weight (empty: all 1). `centers` holds the k initial centres on input
/// and the final ones on output. Returns the label of every point. Deterministic.
std::vector<int> weighted_kmeans(std::span<const Vec2> points,
                                 std::span<const double> sample_weight, const Vec2& feature_weight,
                                 std::vector<Vec2>& centers, int max_iterations = 100);

/// Finds the elastic border of a sweep; `steps` must be ordered by increasing f_T (throws
/// inhap::Error otherwise or when empty). `known_slope` (mm/N, 0: none) is the growth slope to
/// extrapolate with when fewer than two steps slid (e.g. the median over the other sweeps of
/// the same reference point: the creep viscosity is a property of the material).
BorderResult find_elastic_border(std::span<const BorderStep> steps,
                                 const BorderOptions& options = {}, double known_slope = 0.0);

}  // namespace inhap::friction
