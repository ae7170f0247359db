// Oriented bounding boxes of BVH nodes (principal-axis frames) for MeshIndex distance pruning.
// Units: mm. See docs/spatial-queries.md, "Oriented bounds".
#include "bvh_obb.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace inhap::detail {
namespace {

constexpr double kObbInf = std::numeric_limits<double>::infinity();

// Vertex moments of a subtree: count, sum, sum of outer products.
struct Moments {
  double n = 0;
  Vec3 s = Vec3::Zero();
  Mat3 ss = Mat3::Zero();
  void add(const Vec3& v) {
    n += 1;
    s += v;
    ss += v * v.transpose();
  }
  void add(const Moments& m) {
    n += m.n;
    s += m.s;
    ss += m.ss;
  }
};

// Principal axes of the moments as an int16 quaternion (identity when undefined).
void principal_frame(const Moments& m, std::int16_t (&f)[4]) {
  f[0] = 32767;
  f[1] = f[2] = f[3] = 0;
  if (m.n <= 0) return;
  const Vec3 mean = m.s / m.n;
  const Mat3 cov = m.ss / m.n - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(cov);
  if (es.info() != Eigen::Success || !es.eigenvectors().allFinite()) return;
  Mat3 r = es.eigenvectors();  // columns: axes (smallest variance first, ~ the normal)
  if (r.determinant() < 0) r.col(0) = -r.col(0);
  // Re-orthonormalise (computeDirect's vectors can be slightly off) before the conversion.
  const Eigen::Quaterniond q = Eigen::Quaterniond(r).normalized();
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  double big = 0;
  for (double x : c) big = std::max(big, std::abs(x));
  if (!(big > 0) || !std::isfinite(big)) return;
  for (int k = 0; k < 4; ++k) f[k] = static_cast<std::int16_t>(std::lround(c[k] / big * 32767));
}

// Axes of a frame as matrix rows: fl(M_ij * fl(1 / |q|^2)). Projections with it have the error
// bound of obb_project_error (same derivation).
Mat3 frame_axes(const std::int16_t (&q)[4]) {
  Mat3 a;
  for (int k = 0; k < 3; ++k) a.row(k) = obb_project(q, Vec3::Unit(k)).transpose();
  return a.transpose();  // obb_project(q, e_k) is column k of the axis matrix
}

}  // namespace

std::vector<BvhObb> build_obbs(const BvhBuild& bvh, const std::vector<Vec3>& tri_vertices) {
  const std::size_t n = bvh.nodes.size();
  std::vector<BvhObb> out(n);
  // Slot range and vertex moments per node, bottom-up (children come after their parent).
  std::vector<std::int32_t> begin(n), end(n);
  std::vector<Moments> mom(n);
  for (std::size_t i = n; i-- > 0;) {
    const BvhBuildNode& b = bvh.nodes[i];
    if (b.count > 0) {
      begin[i] = b.first;
      end[i] = b.first + b.count;
      for (std::int32_t s = 3 * begin[i]; s < 3 * end[i]; ++s) mom[i].add(tri_vertices[s]);
    } else {
      const std::size_t l = i + 1, r = static_cast<std::size_t>(b.first);
      begin[i] = begin[l];
      end[i] = end[r];
      mom[i] = mom[l];
      mom[i].add(mom[r]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    BvhObb& o = out[i];
    principal_frame(mom[i], o.q);
    const Mat3 a = frame_axes(o.q);
    Vec3 lo = Vec3::Constant(kObbInf), hi = Vec3::Constant(-kObbInf);
    for (std::int32_t s = 3 * begin[i]; s < 3 * end[i]; ++s) {
      const Vec3& v = tri_vertices[s];
      const Vec3 x = a * v;
      const double e = obb_project_error(v);
      lo = lo.cwiseMin(x - Vec3::Constant(e));
      hi = hi.cwiseMax(x + Vec3::Constant(e));
    }
    for (int k = 0; k < 3; ++k) {
      o.lo[k] = round_down_padded(lo[k]);
      o.hi[k] = round_up_padded(hi[k]);
    }
  }
  return out;
}

}  // namespace inhap::detail
