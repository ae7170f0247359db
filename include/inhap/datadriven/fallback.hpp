// Graceful fallback of the force model outside its training support (issue 18 item 3).
//
// Units: mm, N.
//
// Far from every training proxy the RBF expansions extrapolate (their inputs are clamped to the
// training box, so a push where the recording never went borrows whatever the nearest centres
// say). The fallback is a physically sane model fitted to the recording's own depth-force law:
//   * DepthLaw: the normal force against the depth d = n . (q - p) (positive inside) of the
//     in-contact training samples, as a monotone non-decreasing function through (0, 0):
//     isotonic regression (pool adjacent violators) of f_n on d over depth bins, linear between
//     the knots and, beyond the deepest knot, a straight line with the slope of the deepest
//     quarter of the knots. No shape is assumed (a law that stiffens with depth is followed as
//     measured, not forced into k d^alpha);
//   * SupportDistance: the distance from q to the nearest training proxy, on a grid (the proxies
//     are voxelised at `cell_mm`; the grid holds the chamfer distance to those voxels' proxies).
// With the stiffness prior (preset best) the law is fitted to f_n / k(q), k(q) the prior's local
// stiffness, and rendered times k(q) (force_model_priors.hpp): the data's own depth dependence
// at the prior's local level.
// Rendering blends: f = (1 - w) f_model + w (k(q) law(d) n + shear prior), with
// w = smoothstep((dist - near_mm) / (far_mm - near_mm)): the model as trained within near_mm of
// the data, the law beyond far_mm. A few flops and one trilinear lookup: servo-safe.
//
// Closer in, between normal_near_mm and normal_far_mm (2 and 4 mm by default, before the law
// takes over), the model's normal force comes from the probe moved onto the proxy's normal line
// at the same depth (p' = q - d n, no tangential displacement), with weight
// w_n = smoothstep((dist - normal_near_mm) / (normal_far_mm - normal_near_mm)); its tangential
// force stays the model's. Between training spots the RBFs otherwise extrapolate their
// dependence on the tangential displacement u_t: a probe stuck 5 mm sideways at a depth the data
// showed only at other spots was rendered with half the normal force the data show there (the
// lab's MuJoCo dome, whose training data, spot by spot, show f_n independent of |u_t|). Costs one
// more RBF evaluation where w_n > 0. normal_near_mm = normal_far_mm = 0 turns it off (files written
// before it: off, so they render as before).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

/// Monotone depth-force law f_n(d): knots (depth mm, force N), increasing depth, non-decreasing
/// force, then a straight line of `slope_n_per_mm` beyond the last knot.
struct DepthLaw {
  std::vector<double> depth_mm, force_n;
  double slope_n_per_mm = 0;
  bool empty() const { return depth_mm.size() < 2; }
  /// Normal force at depth d (mm), N; 0 for d <= 0, an empty law or a non-finite d. Servo-safe.
  double force(double d) const;
};

/// Fits the law to depths d (mm) and normal forces f_n (N) of in-contact samples (samples with
/// d <= 0 or non-finite values are left out). Empty when fewer than 20 samples remain. At most
/// `knots` depth bins of equal width.
DepthLaw fit_depth_law(const std::vector<double>& depth_mm, const std::vector<double>& normal_n,
                       int knots = 100);

/// Distance to the nearest training proxy, mm, on a grid.
struct SupportDistance {
  double cell_mm = 1.0;      ///< voxel size of the proxies kept and of the grid
  std::vector<Vec3> points;  ///< one training proxy per voxel floor(q / cell_mm) (its first), mm
  /// Derived by build() (not saved): the grid of distances (x fastest), origin and dims.
  Vec3 origin = Vec3::Zero();
  std::array<int, 3> dims{0, 0, 0};
  std::vector<float> distance_mm;
  double reach_mm = 0;  ///< beyond the grid (and the grid's initial value): at least this far

  bool empty() const { return points.empty(); }
  /// Builds the distance grid out to `reach_mm` around the points.
  void build(double reach_mm);
  /// Distance from q to the nearest training proxy, mm (trilinear on the grid; reach_mm outside
  /// it or for a non-finite q). Servo-safe.
  double distance(const Vec3& q) const;
};

/// Voxelises proxies q (mm) at cell_mm, keeping the first proxy of each voxel.
SupportDistance make_support_distance(const std::vector<Vec3>& q, double cell_mm = 1.0);

struct Fallback {
  DepthLaw law;
  SupportDistance support;
  double near_mm = 6.0;  ///< within this distance of a training proxy: the model as trained
  double far_mm = 12.0;  ///< beyond it: the law alone
  /// The normal force from the normal line (see above) blends in from normal_near_mm to
  /// normal_far_mm; 0 and 0: never.
  double normal_near_mm = 0.0, normal_far_mm = 0.0;
  bool empty() const { return law.empty() || support.empty(); }
  /// Blend weight of the law at proxy q: 0 near the data, 1 far from it. Servo-safe.
  double weight(const Vec3& q) const { return weight_at(support.distance(q)); }
  /// The same for a distance to the support (mm) already looked up.
  double weight_at(double dist_mm) const;
  /// Weight of the normal line's normal force at that distance: 0 near the data (and when off),
  /// 1 from normal_far_mm on. Servo-safe.
  double normal_weight_at(double dist_mm) const;
  /// How far the distance grid must reach: the larger of far_mm and normal_far_mm.
  double reach_mm() const { return far_mm > normal_far_mm ? far_mm : normal_far_mm; }
};

/// Checks sizes, ordering and finiteness; throws inhap::Error naming what is wrong, prefixed by
/// `where`.
void validate_fallback(const Fallback& f, const std::string& where);
/// The normal line's distances are 0 and 0 (off), or 0 <= near < far, finite (mm).
bool valid_normal_blend(double near_mm, double far_mm);
/// Throws inhap::Error, prefixed by `where`, unless valid_normal_blend.
void validate_normal_blend(double near_mm, double far_mm, const std::string& where);

}  // namespace inhap::datadriven
