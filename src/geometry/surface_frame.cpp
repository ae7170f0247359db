// The library's one local surface frame (see surface_frame.hpp).
#include "inhap/geometry/surface_frame.hpp"

#include <cmath>

namespace inhap {

void tangent_basis(const Vec3& n, const Vec3& reference, Vec3& t0, Vec3& t1) {
  Vec3 r = reference;
  if (!(r.norm() > 0) || std::abs(r.normalized().dot(n)) > 0.95) {
    // Next world axis that is not nearly parallel to n.
    r = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    if (std::abs(reference.normalized().dot(Vec3::UnitX())) > 0.9) r = Vec3::UnitY();
    if (std::abs(r.dot(n)) > 0.95) r = Vec3::UnitZ();
  }
  t0 = (r - r.dot(n) * n).normalized();
  t1 = n.cross(t0);
}

}  // namespace inhap
