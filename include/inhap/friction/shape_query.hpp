// The undeformed contact surface as seen by the friction module: closest point and outward
// normal of the surface the probe centre touches (the object's surface offset by the probe
// radius). Units: mm. Implementations are const, allocation-free and exception-free.
#pragma once

#include <limits>

#include "inhap/core/types.hpp"

namespace inhap::friction {

class ShapeQuery {
 public:
  virtual ~ShapeQuery() = default;
  /// Closest point of the probe-centre surface to p and the outward unit normal there; false
  /// when there is none.
  virtual bool closest(const Vec3& p, Vec3& point, Vec3& normal) const noexcept = 0;
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
  bool closest(const Vec3& p, Vec3& point, Vec3& normal) const noexcept override {
    point = p - (p - point_).dot(normal_) * normal_;
    normal = normal_;
    return true;
  }

 private:
  Vec3 point_, normal_;
};

}  // namespace inhap::friction
