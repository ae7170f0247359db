// inhap core types. Units everywhere: millimetres (mm), newtons (N), seconds (s), N/mm.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>

namespace inhap {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;  ///< position in mm, force in N, velocity in mm/s
using Mat3 = Eigen::Matrix3d;

/// Axis-aligned box (mm). Empty when min > max on any axis.
struct Box3 {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Box3& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  Vec3 size() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
};

/// True when every component is finite (no NaN, no inf).
inline bool all_finite(const Vec3& v) {
  return v.allFinite();
}

}  // namespace inhap
