// Triangulation of the reference points of the sliding yield surfaces over the object's surface
// and barycentric location of a contact point in it (thesis 4.3.2, last paragraph). Units: mm.
//
// The reference points are projected onto the plane through their centroid perpendicular to
// `axis` (the mean surface normal) and triangulated there (2-D Delaunay, CGAL). A contact point
// is located by projecting it the same way: inside a triangle its barycentric weights
// interpolate any per-reference-point quantity linearly; outside the covered area it takes the
// weights of the closest point of the nearest triangle (a documented, continuous extension:
// constant along the outward direction from the border). This requires the reference points to
// form a height field over that plane (planar patches, domes): say so when choosing them.
//
// locate() is const, allocation-free and exception-free (servo-ready).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::friction {

class ReferenceMesh {
 public:
  /// Weights of (up to) three reference points; unused slots have weight 0.
  struct Location {
    std::array<int, 3> vertex{0, 0, 0};
    Vec3 weight{1, 0, 0};
    int triangle = -1;    ///< triangle used (-1: fewer than 3 points or collinear points)
    bool inside = false;  ///< the projection lies in a triangle (not the nearest-triangle fallback)
  };

  ReferenceMesh() = default;
  /// Delaunay triangulation of the projected points. Throws inhap::Error when `points` is empty
  /// or two points project onto the same place.
  static ReferenceMesh build(std::span<const Vec3> points, const Vec3& axis);
  /// Uses the given triangles (checked: indices in range, non-degenerate in projection).
  static ReferenceMesh from_triangles(std::span<const Vec3> points, const Vec3& axis,
                                      std::vector<Tri> triangles);

  /// Location of x; `hint` is a triangle to try first (e.g. the previous one).
  Location locate(const Vec3& x, int hint = -1) const noexcept;

  std::size_t size() const { return points_.size(); }
  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<Tri>& triangles() const { return triangles_; }
  const Vec3& axis() const { return axis_; }
  /// Projected 2-D coordinates of a point.
  Vec2 project(const Vec3& x) const { return Vec2((x - origin_).dot(e1_), (x - origin_).dot(e2_)); }

 private:
  void setup_frame(std::span<const Vec3> points, const Vec3& axis);
  void finish();
  std::vector<Vec3> points_;
  std::vector<Vec2> uv_;
  std::vector<Tri> triangles_;
  std::vector<double> inv_area2_;  // 1 / (2 * signed area) per triangle
  Vec3 axis_ = Vec3::UnitZ(), origin_ = Vec3::Zero(), e1_ = Vec3::UnitX(), e2_ = Vec3::UnitY();
};

}  // namespace inhap::friction
