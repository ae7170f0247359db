// Internal to MeshIndex: oriented bounding boxes of BVH nodes for distance pruning. Units: mm.
// Not a public header (lives beside its sources). See docs/spatial-queries.md, "Oriented bounds".
//
// The frame of a box is a rotation stored as an int16 quaternion q. With integer components the
// matrix M(q) = |q|^2 R(q) (R exactly orthogonal) has integer entries below 2^33, computed
// exactly in double whatever the compiler contracts; the axes used are M(q) rows times the
// correctly rounded 1/|q|^2, so they are orthonormal to within 1e-15 and bit-identical in every
// translation unit. The extents along them are rounded outwards to float and padded.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bvh_build.hpp"
#include "inhap/core/types.hpp"

namespace inhap::detail {

/// p in the frame: (a_0 . p, a_1 . p, a_2 . p) for the rows a_k of the rotation. The absolute
/// error of each component is below 1e-15 * |p|_1 (see obb_project_error).
/// q: rotation as an int16 quaternion (w, x, y, z), not normalised.
inline Vec3 obb_project(const std::int16_t q[4], const Vec3& p) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double ww = w * w, xx = x * x, yy = y * y, zz = z * z;
  const double xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
  const double s = 1.0 / (ww + xx + yy + zz);
  // Rows of M = |q|^2 R: every entry is an exact integer in double.
  const double r0 = (ww + xx - yy - zz) * p.x() + 2 * (xy + wz) * p.y() + 2 * (xz - wy) * p.z();
  const double r1 = 2 * (xy - wz) * p.x() + (ww - xx + yy - zz) * p.y() + 2 * (yz + wx) * p.z();
  const double r2 = 2 * (xz + wy) * p.x() + 2 * (yz - wx) * p.y() + (ww - xx - yy + zz) * p.z();
  return {r0 * s, r1 * s, r2 * s};
}

/// Bound on the rounding error of each obb_project component (a generous 3x over gamma(3) +
/// 2 eps, since |R_ij| <= 1).
inline double obb_project_error(const Vec3& p) {
  return 2e-15 * p.cwiseAbs().sum();
}

/// Per build node (same indexing as BvhBuild::nodes): frame and float extents along its axes
/// (same layout as MeshIndex::NodeObb::Child).
struct BvhObb {
  std::int16_t q[4];
  float lo[3], hi[3];
};

/// Lower bound of the squared distance from p to everything inside the oriented box `o`
/// (a BvhObb or a MeshIndex::NodeObb::Child); eq = obb_project_error(p). The exact projection
/// of p lies within eq of the computed one, the box holds the exact projections of its
/// vertices, and the frame is orthogonal, so sum(gap^2) <= |p - x|^2 for every x in the box;
/// the last factor absorbs the rounding of the gaps and squares (relative, ~1e-16 each).
template <class O>
inline double obb_distance2(const O& o, const Vec3& p, double eq) {
  const Vec3 x = obb_project(o.q, p);
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double lo = o.lo[k], hi = o.hi[k];
    // Gap outside [lo, hi] less the projection error, branch-free (lo <= hi).
    const double d = std::max(std::max(lo - x[k], x[k] - hi) - eq, 0.0);
    d2 += d * d;
  }
  return d2 * (1 - 1e-12);
}

/// The rotation rows of obb_project for q, to project many points with one frame: the
/// products M(q) s are rounded once more, so each component of rows * p stays within
/// obb_project_error(p) of the exact projection too.
inline Mat3 obb_rows(const std::int16_t q[4]) {
  Mat3 r;
  for (int k = 0; k < 3; ++k) r.col(k) = obb_project(q, Vec3::Unit(k));
  return r;
}

/// obb_distance2 with the frame given as obb_rows(o.q).
template <class O>
inline double obb_distance2(const O& o, const Mat3& rows, const Vec3& p, double eq) {
  const Vec3 x = rows * p;
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max(std::max(double(o.lo[k]) - x[k], x[k] - double(o.hi[k])) - eq, 0.0);
    d2 += d * d;
  }
  return d2 * (1 - 1e-12);
}

/// Oriented boxes for every node of `bvh`, from the vertices of its triangles (`tri_vertices`:
/// 3 per leaf slot, in `bvh.order` order). Frame: principal axes of the node's vertices.
std::vector<BvhObb> build_obbs(const BvhBuild& bvh, const std::vector<Vec3>& tri_vertices);

}  // namespace inhap::detail
