// Sliding yield surface f_s (force space) and elastic displacement limit surface g_s
// (displacement space), thesis eq. 4.6-4.11 and fig. 4.8. Units: force space N, displacement
// space mm, angles rad.
//
// Both are the same shape around the surface normal of the reference point, stored in local
// coordinates (x along t_0, y along t_1, z = "level" along -n_c):
//   f_s: level = f_N (normal load), radius = f_T limit  -> local(f_l), f_l = load on the object
//   g_s: level = depth -u.n_c,      radius = |u_t| limit -> local(u),   u = p - p_c
// The measured vertices are the limits of K tangential directions (angles theta_k) at L levels
// (one per f_N). Between them the surface is linear: for direction k the radius is piecewise
// linear in the level through the apex (0, 0) and the vertices (level_jk, radius_jk), and it
// grows proportionally to the level beyond the last vertex (a cone through the apex, exact for
// Coulomb friction); between two directions the radius is linear in the angle (so an isotropic
// limit is an exact circle). A point is inside when its tangential distance from the axis is at
// most the radius at its level and angle; levels <= 0 have radius 0.
//
// Fixed-capacity storage: surfaces are copied, blended and queried inside the servo step
// without allocating.
#pragma once

#include <array>
#include <optional>
#include <span>

#include "inhap/core/types.hpp"
#include "inhap/geometry/surface_frame.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::friction {

class YieldSurface {
 public:
  static constexpr int kMaxDirections = 16;
  static constexpr int kMaxLevels = 8;

  YieldSurface() = default;
  /// `angles`: K strictly increasing angles in [0, 2 pi). `level` and `radius`: L x K values,
  /// row-major (level j, direction k); levels strictly increasing in j and > 0, radii >= 0 and
  /// finite. Throws inhap::Error naming the offending value.
  static YieldSurface make(std::span<const double> angles, int levels,
                           std::span<const double> level, std::span<const double> radius);

  int directions() const { return k_; }
  int levels() const { return l_; }
  bool empty() const { return k_ == 0; }
  double angle(int k) const { return angle_[k]; }
  double level(int j, int k) const { return level_[j][k]; }
  double radius(int j, int k) const { return radius_[j][k]; }

  /// Limit radius at `level` in direction `theta` (rad, any value).
  double radius_at(double level, double theta) const noexcept;
  /// |xy| - radius_at(z, atan2(y, x)): > 0 outside, <= 0 inside.
  double excess(const Vec3& local) const noexcept;
  bool inside(const Vec3& local) const noexcept { return excess(local) <= 0.0; }
  /// Return mapping: the point of the surface at the same level along the ray from the axis
  /// through `local` (the radial direction in the tangent plane). Unchanged when on the axis.
  Vec3 radial_return(const Vec3& local) const noexcept;
  /// First crossing of the ray origin + s dir, s in (0, max_s], with the surface (sampled in 256
  /// steps, then bisected to 1e-12 of max_s); nullopt when none.
  std::optional<double> intersect_ray(const Vec3& origin, const Vec3& dir,
                                      double max_s) const noexcept;

  /// This surface := sum_i weights[i] * surfaces[i], vertex by vertex (same K, L and angles;
  /// weights >= 0 summing to 1). Used for barycentric interpolation between reference points.
  void blend(std::span<const YieldSurface* const> surfaces,
             std::span<const double> weights) noexcept;
  bool same_layout(const YieldSurface& other) const noexcept;

  /// Closed triangle mesh in local coordinates for export and figures: apex at the origin, the
  /// measured rings (with `subdivisions` interpolated vertices per angular sector), and a flat
  /// cap at the mean last level. Vertices: 1 + L*K*subdivisions + 1.
  TriMesh to_mesh(int subdivisions = 1) const;

 private:
  double direction_radius(int k, double level) const noexcept;
  int k_ = 0, l_ = 0;
  std::array<double, kMaxDirections> angle_{};
  std::array<std::array<double, kMaxDirections>, kMaxLevels> level_{}, radius_{};
};

/// Yield-surface coordinates of a world vector v in the surface frame f: (v.t0, v.t1, depth) with
/// depth = -v.n, positive into the object (SurfaceFrame's own z runs along the outward normal).
inline Vec3 to_gs(const SurfaceFrame& f, const Vec3& v) {
  Vec3 l = f.to_local(v);
  l.z() = -l.z();
  return l;
}
/// Inverse of to_gs.
inline Vec3 from_gs(const SurfaceFrame& f, const Vec3& l) {
  return f.to_world(Vec3(l.x(), l.y(), -l.z()));
}

}  // namespace inhap::friction
