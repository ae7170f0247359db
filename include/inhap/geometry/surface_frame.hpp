// The one local surface frame of inhap: two tangents t0, t1 and the OUTWARD unit normal n,
// right-handed (t1 = n x t0). Units: whatever the vectors carry (mm, N, mm/s).
//
// Sign convention (one for the whole library): local z is the component along the outward
// normal, to_local(v) = (v.t0, v.t1, v.n). A point below the surface has a negative local z;
// the friction module's yield-surface coordinates use the depth -z instead (see
// friction/yield_surface.hpp, to_gs / from_gs), the data-driven force model uses z as is.
//
// Two rules pick t0 (both kept: models trained with one must be rendered with the same one):
//   surface_frame(n)            t0 = world x projected onto the tangent plane (world y when x is
//                               within ~25 deg of n) -- the data-driven force model's features;
//   surface_frame(n, reference) t0 = `reference` projected (tangent_basis) -- the sliding yield
//                               surfaces' tangential directions (thesis 4.3).
#pragma once

#include "inhap/core/types.hpp"

namespace inhap {

/// Orthonormal tangent basis at the unit normal n: t0 is `reference` projected onto the tangent
/// plane (falls back to the next world axis when reference is nearly parallel to n), t1 = n x t0.
void tangent_basis(const Vec3& n, const Vec3& reference, Vec3& t0, Vec3& t1);

struct SurfaceFrame {
  Vec3 t0 = Vec3::UnitX(), t1 = Vec3::UnitY(), n = Vec3::UnitZ();  ///< n: outward unit normal
  /// (v.t0, v.t1, v.n): local z > 0 outside the surface.
  Vec3 to_local(const Vec3& w) const { return Vec3(t0.dot(w), t1.dot(w), n.dot(w)); }
  Vec3 to_world(const Vec3& l) const { return l.x() * t0 + l.y() * t1 + l.z() * n; }
};

/// Frame with t0 = world x projected onto the tangent plane (world y when x is within ~25 deg of
/// n). A non-finite or zero normal gives the world frame.
inline SurfaceFrame surface_frame(const Vec3& normal) {
  SurfaceFrame f;
  const double len = normal.norm();
  if (!(len > 1e-9) || !normal.allFinite()) return f;
  f.n = normal / len;
  Vec3 t = Vec3::UnitX() - f.n.x() * f.n;
  if (t.norm() < 0.4) t = Vec3::UnitY() - f.n.y() * f.n;
  f.t0 = t.normalized();
  f.t1 = f.n.cross(f.t0);
  return f;
}

/// Frame at the unit normal n with t0 = `reference` projected (tangent_basis).
inline SurfaceFrame surface_frame(const Vec3& unit_normal, const Vec3& reference) {
  SurfaceFrame f;
  f.n = unit_normal;
  tangent_basis(unit_normal, reference, f.t0, f.t1);
  return f;
}

}  // namespace inhap
