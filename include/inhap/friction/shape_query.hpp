// The undeformed contact surface as seen by the friction module: closest point and outward
// normal of the surface the probe centre touches (the object's surface offset by the probe
// radius). Units: mm. Implementations are const, allocation-free and exception-free.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "inhap/core/types.hpp"

namespace inhap::friction {

class ShapeQuery {
 public:
  virtual ~ShapeQuery() = default;
  /// Closest point of the probe-centre surface to p and the outward unit normal there; false
  /// when there is none within max_distance (mm; a bound lets a spatial index prune early).
  virtual bool closest(const Vec3& p, Vec3& point, Vec3& normal,
                       double max_distance) const noexcept = 0;
  bool closest(const Vec3& p, Vec3& point, Vec3& normal) const noexcept {
    return closest(p, point, normal, std::numeric_limits<double>::infinity());
  }
  /// closest() warm-started for a servo loop: `hint` holds what this shape left in it on the
  /// previous call (start with -1; any value is safe). It may make the search cheaper and never
  /// changes the answer. The default ignores it.
  virtual bool closest(const Vec3& p, Vec3& point, Vec3& normal, double max_distance,
                       std::int32_t& hint) const noexcept {
    (void)hint;
    return closest(p, point, normal, max_distance);
  }
  /// Depth of p below the surface along the normal at its closest point (> 0 inside), mm;
  /// NaN when there is no closest point.
  double depth(const Vec3& p) const noexcept {
    Vec3 c, n;
    if (!closest(p, c, n)) return std::numeric_limits<double>::quiet_NaN();
    return (c - p).dot(n);
  }
};

/// An infinite plane (tests, flat objects).
class PlaneShape final : public ShapeQuery {
 public:
  PlaneShape(const Vec3& point, const Vec3& normal) : point_(point), normal_(normal.normalized()) {}
  using ShapeQuery::closest;
  bool closest(const Vec3& p, Vec3& point, Vec3& normal,
               double max_distance) const noexcept override {
    const double d = (p - point_).dot(normal_);
    if (std::abs(d) > max_distance) return false;
    point = p - d * normal_;
    normal = normal_;
    return true;
  }

 private:
  Vec3 point_, normal_;
};

}  // namespace inhap::friction
