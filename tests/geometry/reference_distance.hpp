// Independent brute-force references for MeshIndex tests (test_mesh_index*.cpp). Units: mm.
#pragma once

#include <algorithm>

#include "inhap/core/types.hpp"

namespace inhap::test {

/// Closest point to p on the segment [a, b].
inline Vec3 ref_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = b - a;
  const double l2 = e.squaredNorm();
  const double s = l2 > 0 ? std::clamp((p - a).dot(e) / l2, 0.0, 1.0) : 0.0;
  return a + s * e;
}

/// Squared distance from p to triangle (v0, v1, v2): projection onto the plane when it falls
/// inside, else the nearest of the three edges. A (near-)collinear triangle (sin^2 of its angle
/// below 1e-13, width below 3e-7 of its size) is its edges: its plane is not defined well
/// enough to project onto.
inline double ref_distance2(const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
  const Vec3 n = (v1 - v0).cross(v2 - v0);
  const double n2 = n.squaredNorm();
  if (n2 > 1e-13 * (v1 - v0).squaredNorm() * (v2 - v0).squaredNorm()) {
    const Vec3 q = p - n * (n.dot(p - v0) / n2);
    if ((v2 - v1).cross(q - v1).dot(n) >= 0 && (v0 - v2).cross(q - v2).dot(n) >= 0 &&
        (v1 - v0).cross(q - v0).dot(n) >= 0)
      return (p - q).squaredNorm();
  }
  return std::min({(p - ref_on_segment(p, v0, v1)).squaredNorm(),
                   (p - ref_on_segment(p, v1, v2)).squaredNorm(),
                   (p - ref_on_segment(p, v2, v0)).squaredNorm()});
}

}  // namespace inhap::test
