// Internal to MeshIndex: closest point of a triangle to a point (barycentric weights), and the
// prism bound (a cheap lower bound of the distance to a triangle). Units: mm. Not a public
// header (lives beside its sources). See docs/spatial-queries.md, "Closest point".
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/types.hpp"

namespace inhap::detail {

// Closest point on segment p0 p1 to p: parameter in [0, 1].
inline double closest_on_segment(const Vec3& p, const Vec3& p0, const Vec3& p1) {
  const Vec3 e = p1 - p0;
  const double len2 = e.squaredNorm();
  return len2 > 0 ? std::clamp((p - p0).dot(e) / len2, 0.0, 1.0) : 0.0;
}

// Zero-area triangle: closest point over its three edges.
template <class T>
Vec3 closest_bary_degenerate(const Vec3& p, const T& tri) {
  const Vec3* v[3] = {&tri.v0, &tri.v1, &tri.v2};
  Vec3 best(1, 0, 0);
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int e = 0; e < 3; ++e) {
    const int i = e, j = (e + 1) % 3;
    const double s = closest_on_segment(p, *v[i], *v[j]);
    const double d2 = (p - ((1 - s) * *v[i] + s * *v[j])).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.setZero();
      best[i] = 1 - s;
      best[j] = s;
    }
  }
  return best;
}

// Barycentric weights of the point of the triangle closest to p: Voronoi regions of the
// vertices, then of the edges, else the face (Ericson, Real-Time Collision Detection 5.1.5).
template <class T>
Vec3 closest_bary_face(const Vec3& p, const T& tri);

// Slivers (sin^2 of the corner angle below 1e-6) lose the Voronoi-region method to rounding (its
// denominators cancel); there the nearer of its answer and the nearest edge point is taken, and
// below sin^2 = 1e-13 the edges alone (the sliver is then at most 3e-7 of its size wide).
template <class T>
Vec3 closest_bary(const Vec3& p, const T& tri) {
  const Vec3 ab = tri.v1 - tri.v0, ac = tri.v2 - tri.v0;
  const double n2 = ab.cross(ac).squaredNorm(), scale = ab.squaredNorm() * ac.squaredNorm();
  if (n2 >= 1e-6 * scale) return closest_bary_face(p, tri);
  const Vec3 e = closest_bary_degenerate(p, tri);
  if (n2 <= 1e-13 * scale) return e;
  Vec3 f = closest_bary_face(p, tri).cwiseMax(0.0);
  f /= f.sum();
  if (!f.allFinite()) return e;
  auto at = [&](const Vec3& w) { return w[0] * tri.v0 + w[1] * tri.v1 + w[2] * tri.v2; };
  return (p - at(f)).squaredNorm() < (p - at(e)).squaredNorm() ? f : e;
}

template <class T>
Vec3 closest_bary_face(const Vec3& p, const T& tri) {
  const Vec3 ab = tri.v1 - tri.v0, ac = tri.v2 - tri.v0;
  const Vec3 ap = p - tri.v0;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - tri.v1;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double s = d1 / (d1 - d3);
    return {1 - s, s, 0};
  }
  const Vec3 cp = p - tri.v2;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double s = d2 / (d2 - d6);
    return {1 - s, 0, s};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - s, s};
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) return closest_bary_degenerate(p, tri);
  const double v = vb / denom, w = vc / denom;
  return {1 - v - w, v, w};
}

/// x rounded to float, as a double. Through a volatile float: GCC 12 at -O3 was seen to drop the
/// double -> float -> double round trip of neighbouring components it vectorises together
/// (the offsets were then computed for a direction the float record does not hold).
inline double to_float(double x) {
  const volatile float f = static_cast<float>(x);
  return f;
}

/// Fills a prism bound (fields n[3], o, m[3][4], all float) for the triangle (a, b, c): the
/// plane's unit normal and the midpoint of the vertices' projections (its slack: half their
/// spread plus the rounding of the projections and of the float offset); per edge the outward
/// unit normal in the plane and the largest projection of the three vertices plus its rounding
/// bound, rounded up to float. Returns false, leaving b all zero (bound 0), for zero-area triangles
/// and slivers, and whenever the float frame is not orthonormal to within 0.9e-6 or the plane
/// slack exceeds 1e-6 of the offsets. slack: the plane's;
/// scale: the largest |offset| (for prism_error).
template <class B>
bool make_prism_bound(const Vec3& a, const Vec3& b, const Vec3& c, B& out, double& slack,
                      double& scale) {
  out = B{};
  const Vec3 v[3] = {a, b, c};
  const Vec3 nn = (b - a).cross(c - a);
  const double len = nn.norm();
  // Slivers (sin of the corner angle below 1e-5) have no reliable normal.
  if (!(len > 1e-5 * (b - a).norm() * (c - a).norm()) || !std::isfinite(len)) return false;
  const Vec3 nh = nn / len;
  B r{};
  const Vec3 nf(to_float(nh[0]), to_float(nh[1]), to_float(nh[2]));
  for (int k = 0; k < 3; ++k) r.n[k] = static_cast<float>(nf[k]);  // exact
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, err = 0;
  for (const Vec3& x : v) {
    const double d = nf.dot(x);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
    err = std::max(err, 1e-15 * nf.cwiseAbs().dot(x.cwiseAbs()));
  }
  r.o = static_cast<float>(to_float(0.5 * (lo + hi)));
  double lambda = nf.squaredNorm();  // bound on the largest eigenvalue of the frame's Gram matrix
  double sc = std::abs(double(r.o));
  for (int j = 0; j < 3; ++j) {
    Vec3 mm = (v[(j + 1) % 3] - v[j]).cross(nh);
    if (mm.dot(v[(j + 2) % 3] - v[j]) > 0) mm = -mm;  // outward
    const double ml = mm.norm();
    if (!(ml > 0) || !std::isfinite(ml)) return false;
    mm /= ml;
    const Vec3 mf(to_float(mm[0]), to_float(mm[1]), to_float(mm[2]));
    for (int k = 0; k < 3; ++k) r.m[j][k] = static_cast<float>(mf[k]);  // exact
    double off = -std::numeric_limits<double>::infinity(), e = 0;
    for (const Vec3& x : v) {
      off = std::max(off, mf.dot(x));
      e = std::max(e, 1e-15 * mf.cwiseAbs().dot(x.cwiseAbs()));
    }
    const double top = off + e, t = to_float(top);  // rounded up to float:
    r.m[j][3] = t < top
                    ? std::nextafter(static_cast<float>(t), std::numeric_limits<float>::infinity())
                    : static_cast<float>(t);
    const float f = r.m[j][3];
    lambda = std::max(lambda, std::max(nf.squaredNorm(), mf.squaredNorm()) + std::abs(nf.dot(mf)));
    sc = std::max(sc, std::abs(double(f)));
  }
  const double sl = std::max(hi - double(r.o), double(r.o) - lo) + err;
  // The plane slack is shared by the whole mesh: a triangle needing more than float rounding
  // keeps the zero record instead.
  if (!(lambda <= 1 + 0.9e-6) || !std::isfinite(sc) || !(sl <= 1e-6 * (1 + sc))) return false;
  out = r;
  slack = sl;
  scale = sc;
  return true;
}

/// Rounding bound of prism_bound's dot products for the point p; scale: the largest |offset|.
inline double prism_error(const Vec3& p, double scale) {
  return 1e-15 * (p.cwiseAbs().sum() + scale);
}

/// Lower bound of the squared distance from p to the triangle of a prism bound b ("prism
/// bound", docs/spatial-queries.md): the distance to its plane and, outside an edge's
/// half-plane, the distance to that half-plane, combined as orthogonal components (the float
/// directions are unit and orthogonal to within 0.9e-6, hence the last factor). eq:
/// prism_error(p, scale); slack: the largest plane slack of make_prism_bound.
template <class B>
inline double prism_bound(const B& b, const Vec3& p, double eq, double slack) {
  const double h = std::max(
      std::abs(double(b.n[0]) * p.x() + double(b.n[1]) * p.y() + double(b.n[2]) * p.z() - b.o) -
          slack - eq,
      0.0);
  double e = 0;
  for (int j = 0; j < 3; ++j)
    e = std::max(e, double(b.m[j][0]) * p.x() + double(b.m[j][1]) * p.y() +
                        double(b.m[j][2]) * p.z() - b.m[j][3] - eq);
  return (h * h + e * e) * (1 - 1e-6);
}

}  // namespace inhap::detail
