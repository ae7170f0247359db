// The only translation unit of the friction module that includes CGAL (slow to compile).
#include "inhap/friction/reference_mesh.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/error.hpp"

namespace inhap::friction {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Delaunay = CGAL::Delaunay_triangulation_2<K, Tds>;

double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Vec2 closest_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

}  // namespace

void ReferenceMesh::setup_frame(std::span<const Vec3> points, const Vec3& axis) {
  if (points.empty()) throw Error("reference mesh: expected at least one reference point");
  if (!axis.allFinite() || !(axis.norm() > 0))
    throw Error("reference mesh: expected a non-zero axis");
  points_.assign(points.begin(), points.end());
  axis_ = axis.normalized();
  origin_.setZero();
  for (const Vec3& p : points_) origin_ += p / static_cast<double>(points_.size());
  const Vec3 r = std::abs(axis_.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1_ = (r - r.dot(axis_) * axis_).normalized();
  e2_ = axis_.cross(e1_);
  uv_.resize(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) uv_[i] = project(points_[i]);
  for (std::size_t i = 0; i < uv_.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if ((uv_[i] - uv_[j]).norm() < 1e-6)
        throw Error(
            fmt::format("reference mesh: points {} and {} project onto the same place", j, i));
}

void ReferenceMesh::finish() {
  inv_area2_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Tri& tr = triangles_[t];
    for (int v : tr)
      if (v < 0 || v >= static_cast<int>(points_.size()))
        throw Error(fmt::format("reference mesh: triangle {} has vertex {} out of range", t, v));
    const double a2 = cross2(uv_[tr[1]] - uv_[tr[0]], uv_[tr[2]] - uv_[tr[0]]);
    if (std::abs(a2) < 1e-9)
      throw Error(fmt::format("reference mesh: triangle {} is degenerate", t));
    if (a2 < 0) std::swap(triangles_[t][1], triangles_[t][2]);
    inv_area2_[t] = 1.0 / std::abs(a2);
  }
}

ReferenceMesh ReferenceMesh::build(std::span<const Vec3> points, const Vec3& axis) {
  ReferenceMesh m;
  m.setup_frame(points, axis);
  if (m.uv_.size() >= 3) {
    std::vector<std::pair<K::Point_2, int>> pts;
    for (std::size_t i = 0; i < m.uv_.size(); ++i)
      pts.emplace_back(K::Point_2(m.uv_[i].x(), m.uv_[i].y()), static_cast<int>(i));
    Delaunay dt(pts.begin(), pts.end());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
      m.triangles_.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    // Deterministic order (CGAL's face order depends on insertion internals).
    for (Tri& t : m.triangles_)
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    std::sort(m.triangles_.begin(), m.triangles_.end());
  }
  m.finish();
  return m;
}

ReferenceMesh ReferenceMesh::from_triangles(std::span<const Vec3> points, const Vec3& axis,
                                            std::vector<Tri> triangles) {
  ReferenceMesh m;
  m.setup_frame(points, axis);
  m.triangles_ = std::move(triangles);
  m.finish();
  return m;
}

ReferenceMesh::Location ReferenceMesh::locate(const Vec3& x, int hint) const noexcept {
  Location loc;
  const std::size_t n = points_.size();
  if (n <= 1) return loc;
  const Vec2 p = project(x);
  if (triangles_.empty()) {
    // Two or collinear points: nearest point of the nearest segment between any two of them.
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const Vec2 c = closest_on_segment(p, uv_[i], uv_[j]);
        const double d = (c - p).squaredNorm();
        if (d < best) {
          best = d;
          const double l = (uv_[j] - uv_[i]).norm();
          const double t = (c - uv_[i]).norm() / l;
          loc.vertex = {static_cast<int>(i), static_cast<int>(j), static_cast<int>(j)};
          loc.weight = Vec3(1.0 - t, t, 0.0);
        }
      }
    return loc;
  }
  auto bary = [&](std::size_t t, const Vec2& q) {
    const Tri& tr = triangles_[t];
    const Vec2 &a = uv_[tr[0]], &b = uv_[tr[1]], &c = uv_[tr[2]];
    const double w0 = cross2(b - q, c - q) * inv_area2_[t];
    const double w1 = cross2(c - q, a - q) * inv_area2_[t];
    return Vec3(w0, w1, 1.0 - w0 - w1);
  };
  auto result = [&](std::size_t t, const Vec3& w, bool inside) {
    loc.triangle = static_cast<int>(t);
    loc.vertex = {triangles_[t][0], triangles_[t][1], triangles_[t][2]};
    loc.weight = w;
    loc.inside = inside;
    return loc;
  };
  constexpr double kEps = -1e-12;
  if (hint >= 0 && static_cast<std::size_t>(hint) < triangles_.size()) {
    const Vec3 w = bary(static_cast<std::size_t>(hint), p);
    if (w.minCoeff() >= kEps) return result(static_cast<std::size_t>(hint), w, true);
  }
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3 w = bary(t, p);
    if (w.minCoeff() >= kEps) return result(t, w, true);
  }
  // Outside the covered area: closest point of the nearest triangle.
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_t = 0;
  Vec2 best_c = p;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Tri& tr = triangles_[t];
    for (int e = 0; e < 3; ++e) {
      const Vec2 c = closest_on_segment(p, uv_[tr[e]], uv_[tr[(e + 1) % 3]]);
      const double d = (c - p).squaredNorm();
      if (d < best) {
        best = d;
        best_t = t;
        best_c = c;
      }
    }
  }
  Vec3 w = bary(best_t, best_c).cwiseMax(0.0);
  w /= w.sum();
  return result(best_t, w, false);
}

}  // namespace inhap::friction
