#include "inhap/lab/shape.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/geometry/trimesh.hpp"
#include "shape_mesh.hpp"

namespace inhap::lab {

namespace {

constexpr double kTiny = 1e-12;

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

/// Builds the query from the closest point, the inside flag and the face normal used when the
/// point lies on the surface.
SurfaceQuery finish(const Vec3& p, const Vec3& closest, bool inside, const Vec3& face_normal) {
  SurfaceQuery q;
  q.closest = closest;
  const Vec3 diff = p - closest;
  const double dist = diff.norm();
  q.distance = inside ? -dist : dist;
  if (dist > 1e-9)
    q.normal = inside ? Vec3(-diff / dist) : Vec3(diff / dist);
  else
    q.normal = face_normal;
  return q;
}

/// Radial unit vector of p about a vertical axis through c (x axis when on the axis).
Vec3 radial_dir(const Vec3& p, const Vec3& c, double& rho) {
  const double dx = p.x() - c.x(), dy = p.y() - c.y();
  rho = std::hypot(dx, dy);
  return rho > kTiny ? Vec3(dx / rho, dy / rho, 0) : Vec3(1, 0, 0);
}

SurfaceQuery query_cylinder(const CylinderShape& s, const Vec3& p) {
  double rho;
  const Vec3 er = radial_dir(p, s.base_center, rho);
  const double z = p.z() - s.base_center.z();
  const bool inside = rho < s.radius && z > 0 && z < s.height;
  double cr, cz;
  Vec3 face;
  if (inside) {
    const double d_side = s.radius - rho, d_top = s.height - z, d_bot = z;
    if (d_top <= d_side && d_top <= d_bot) {
      cr = rho, cz = s.height, face = Vec3::UnitZ();
    } else if (d_bot <= d_side) {
      cr = rho, cz = 0, face = -Vec3::UnitZ();
    } else {
      cr = s.radius, cz = z, face = er;
    }
  } else {
    cr = std::min(rho, s.radius);
    cz = std::clamp(z, 0.0, s.height);
    face = cz >= s.height ? Vec3::UnitZ() : cz <= 0 ? Vec3(-Vec3::UnitZ()) : er;
  }
  const Vec3 c = s.base_center + er * cr + Vec3::UnitZ() * cz;
  return finish(p, c, inside, face);
}

/// Sphere of radius rs about c cut by the plane z = c.z + y_cut, keeping the part above it.
SurfaceQuery query_cut_sphere(const Vec3& c, double rs, double y_cut, const Vec3& p) {
  double rho;
  const Vec3 er = radial_dir(p, c, rho);
  const double y = p.z() - c.z();
  const double w = std::sqrt(std::max(0.0, rs * rs - y_cut * y_cut));
  const double len = std::hypot(rho, y);
  const bool inside = len < rs && y > y_cut;
  // candidate on the spherical arc
  double ar = w, ay = y_cut;
  Vec2 arc_n = Vec2(w, y_cut) / rs;
  if (len > kTiny) {
    const double py = y * rs / len;
    if (py >= y_cut) ar = rho * rs / len, ay = py, arc_n = Vec2(rho, y) / len;
  } else if (rs >= y_cut) {
    ar = 0, ay = rs, arc_n = Vec2(0, 1);
  }
  // candidate on the flat base
  const double br = std::min(rho, w), by = y_cut;
  const double da = std::hypot(rho - ar, y - ay), db = std::hypot(rho - br, y - by);
  Vec3 closest, face;
  if (da <= db) {
    closest = c + er * ar + Vec3::UnitZ() * ay;
    face = er * arc_n.x() + Vec3::UnitZ() * arc_n.y();
  } else {
    closest = c + er * br + Vec3::UnitZ() * by;
    face = -Vec3::UnitZ();
  }
  return finish(p, closest, inside, face);
}

SurfaceQuery query_dome(const Vec3& base, double a, double h, const Vec3& p) {
  const double rs = (a * a + h * h) / (2.0 * h);
  const Vec3 c = base + Vec3(0, 0, h - rs);
  return query_cut_sphere(c, rs, rs - h, p);
}

SurfaceQuery query_sphere(const SphereShape& s, const Vec3& p) {
  const Vec3 d = p - s.center;
  const double len = d.norm();
  const Vec3 n = len > kTiny ? Vec3(d / len) : Vec3(Vec3::UnitZ());
  return finish(p, s.center + n * s.radius, len < s.radius, n);
}

SurfaceQuery query_box(const BoxShape& s, const Vec3& p) {
  const Vec3 q = p - s.center;
  const Vec3& h = s.half_size;
  const bool inside = (q.array().abs() < h.array()).all();
  Vec3 c = q, face = Vec3::Zero();
  if (inside) {
    int axis = 0;
    double best = h[0] - std::abs(q[0]);
    for (int k = 1; k < 3; ++k)
      if (h[k] - std::abs(q[k]) < best) best = h[k] - std::abs(q[k]), axis = k;
    const double sgn = q[axis] >= 0 ? 1.0 : -1.0;
    c[axis] = sgn * h[axis];
    face[axis] = sgn;
  } else {
    c = q.cwiseMax(-h).cwiseMin(h);
    int axis = 2;  // face normal when on the surface: the axis at its limit (prefer z)
    for (int k : {2, 0, 1})
      if (std::abs(std::abs(c[k]) - h[k]) < 1e-12) {
        axis = k;
        break;
      }
    face[axis] = c[axis] >= 0 ? 1.0 : -1.0;
  }
  return finish(p, s.center + c, inside, face);
}

/// Closest point on a closed 2-D polygon (CCW), inside flag and outward edge normal.
void polygon_closest(const std::vector<Vec2>& poly, const Vec2& p, Vec2& closest, bool& inside,
                     Vec2& edge_normal) {
  double best = std::numeric_limits<double>::infinity();
  bool odd = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = poly[j];
    const Vec2& b = poly[i];
    const Vec2 e = b - a;
    const double l2 = e.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - a).dot(e) / l2, 0.0, 1.0) : 0.0;
    const Vec2 c = a + t * e;
    const double d2 = (p - c).squaredNorm();
    if (d2 < best) {
      best = d2;
      closest = c;
      edge_normal = l2 > 0 ? Vec2(Vec2(e.y(), -e.x()) / std::sqrt(l2)) : Vec2(0, 1);
    }
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * e.x() / e.y())
      odd = !odd;
  }
  inside = odd;
}

SurfaceQuery query_ridged(const RidgedSlabShape& s, const std::vector<Vec2>& poly, const Vec3& p) {
  const Vec3 q = p - s.base_center;
  Vec2 c2 = Vec2::Zero(), n2(0, 1);
  bool in2 = false;
  polygon_closest(poly, Vec2(q.x(), q.z()), c2, in2, n2);
  const double d2 = (Vec2(q.x(), q.z()) - c2).norm();
  const double half = 0.5 * s.size_y;
  const double dy = std::abs(q.y()) - half;
  const double sy = q.y() >= 0 ? 1.0 : -1.0;
  const Vec3 wall(c2.x(), q.y(), c2.y()), wall_n(n2.x(), 0, n2.y());
  const Vec3 cap(q.x(), sy * half, q.z()), cap_n(0, sy, 0);
  Vec3 c, face;
  bool inside = false;
  if (in2 && dy <= 0) {
    inside = true;
    if (d2 <= -dy)
      c = wall, face = wall_n;
    else
      c = cap, face = cap_n;
  } else if (in2) {
    c = cap, face = cap_n;
  } else if (dy <= 0) {
    c = wall, face = wall_n;
  } else {
    c = Vec3(c2.x(), sy * half, c2.y()), face = wall_n;
  }
  return finish(p, s.base_center + c, inside, face);
}

std::vector<Vec2> ridged_profile(const RidgedSlabShape& s) {
  std::vector<Vec2> poly;
  const double hw = 0.5 * s.size_x;
  auto push = [&poly](double x, double z) {
    if (poly.empty() || (poly.back() - Vec2(x, z)).norm() > 1e-12) poly.emplace_back(x, z);
  };
  push(-hw, 0);
  push(hw, 0);
  push(hw, s.thickness);
  if (s.ridges > 0) {
    const double pitch = s.size_x / s.ridges;
    for (int i = s.ridges - 1; i >= 0; --i) {
      const double xc = -hw + (i + 0.5) * pitch;
      push(xc + 0.5 * s.ridge_width, s.thickness);
      push(xc, s.thickness + s.ridge_height);
      push(xc - 0.5 * s.ridge_width, s.thickness);
    }
  }
  push(-hw, s.thickness);
  if ((poly.back() - poly.front()).norm() < 1e-12) poly.pop_back();
  return poly;
}

}  // namespace

Shape::Shape(Variant v) : v_(std::move(v)) {
  if (const auto* r = std::get_if<RidgedSlabShape>(&v_)) profile_ = ridged_profile(*r);
}

std::string_view Shape::type_name() const {
  return std::visit(
      Overloaded{[](const CylinderShape&) { return "cylinder"; },
                 [](const DomeShape&) { return "dome"; },
                 [](const HemisphereShape&) { return "hemisphere"; },
                 [](const SphereShape&) { return "sphere"; }, [](const BoxShape&) { return "box"; },
                 [](const RidgedSlabShape&) { return "ridged-slab"; },
                 [](const MeshShape&) { return "mesh"; }},
      v_);
}

SurfaceQuery Shape::query(const Vec3& p) const {
  return std::visit(
      Overloaded{
          [&](const CylinderShape& s) { return query_cylinder(s, p); },
          [&](const DomeShape& s) { return query_dome(s.base_center, s.base_radius, s.height, p); },
          [&](const HemisphereShape& s) {
            return query_dome(s.base_center, s.radius, s.radius, p);
          },
          [&](const SphereShape& s) { return query_sphere(s, p); },
          [&](const BoxShape& s) { return query_box(s, p); },
          [&](const RidgedSlabShape& s) { return query_ridged(s, profile_, p); },
          [&](const MeshShape& s) { return query_mesh(s, p); }},
      v_);
}

Box3 Shape::bounds() const {
  Box3 b;
  std::visit(Overloaded{[&](const CylinderShape& s) {
                          b.extend(s.base_center - Vec3(s.radius, s.radius, 0));
                          b.extend(s.base_center + Vec3(s.radius, s.radius, s.height));
                        },
                        [&](const DomeShape& s) {
                          const double rs = (s.base_radius * s.base_radius + s.height * s.height) /
                                            (2 * s.height);
                          const double r = s.height > rs ? rs : s.base_radius;
                          b.extend(s.base_center - Vec3(r, r, 0));
                          b.extend(s.base_center + Vec3(r, r, s.height));
                        },
                        [&](const HemisphereShape& s) {
                          b.extend(s.base_center - Vec3(s.radius, s.radius, 0));
                          b.extend(s.base_center + Vec3(s.radius, s.radius, s.radius));
                        },
                        [&](const SphereShape& s) {
                          b.extend(s.center - Vec3::Constant(s.radius));
                          b.extend(s.center + Vec3::Constant(s.radius));
                        },
                        [&](const BoxShape& s) {
                          b.extend(s.center - s.half_size);
                          b.extend(s.center + s.half_size);
                        },
                        [&](const RidgedSlabShape& s) {
                          b.extend(s.base_center - Vec3(s.size_x / 2, s.size_y / 2, 0));
                          b.extend(s.base_center +
                                   Vec3(s.size_x / 2, s.size_y / 2, s.thickness + s.ridge_height));
                        },
                        [&](const MeshShape& s) { b = mesh_bounds(s); }},
             v_);
  return b;
}

std::optional<Vec3> Shape::drop(double x, double y, double probe_radius) const {
  const Box3 b = bounds();
  if (b.empty()) return std::nullopt;
  const double bottom = b.min.z() - probe_radius - 1.0;
  Vec3 p(x, y, b.max.z() + probe_radius + 1.0);
  for (int it = 0; it < 400; ++it) {
    const double gap = distance(p) - probe_radius;
    if (!std::isfinite(gap)) return std::nullopt;
    if (gap < 1e-7) return gap > -1e-6 ? std::optional<Vec3>(p) : std::nullopt;
    p.z() -= gap;
    if (p.z() < bottom) return std::nullopt;
  }
  return std::nullopt;
}

std::string validate_shape(const Shape& shape) {
  auto pos = [](double v) { return std::isfinite(v) && v > 0; };
  return std::visit(
      Overloaded{
          [&](const CylinderShape& s) -> std::string {
            return pos(s.radius) && pos(s.height) && all_finite(s.base_center)
                       ? ""
                       : "cylinder: expected finite base_center and positive radius, height";
          },
          [&](const DomeShape& s) -> std::string {
            return pos(s.base_radius) && pos(s.height) && all_finite(s.base_center)
                       ? ""
                       : "dome: expected finite base_center and positive base_radius, height";
          },
          [&](const HemisphereShape& s) -> std::string {
            return pos(s.radius) && all_finite(s.base_center)
                       ? ""
                       : "hemisphere: expected finite base_center and a positive radius";
          },
          [&](const SphereShape& s) -> std::string {
            return pos(s.radius) && all_finite(s.center)
                       ? ""
                       : "sphere: expected a finite center and a positive radius";
          },
          [&](const BoxShape& s) -> std::string {
            return all_finite(s.center) && pos(s.half_size.minCoeff()) && all_finite(s.half_size)
                       ? ""
                       : "box: expected a finite center and positive size";
          },
          [&](const RidgedSlabShape& s) -> std::string {
            if (!(pos(s.size_x) && pos(s.size_y) && pos(s.thickness) && all_finite(s.base_center)))
              return "ridged-slab: expected positive size_x, size_y, thickness";
            if (s.ridges < 0 || s.ridges > 1000) return "ridged-slab: expected 0..1000 ridges";
            if (s.ridges > 0 && !(pos(s.ridge_height) && pos(s.ridge_width) &&
                                  s.ridge_width <= s.size_x / s.ridges + 1e-9))
              return fmt::format(
                  "ridged-slab: expected positive ridge_height and 0 < ridge_width <= size_x / "
                  "ridges ({:g} mm)",
                  s.size_x / s.ridges);
            return "";
          },
          [&](const MeshShape& s) -> std::string {
            return s.index && s.mesh && s.mesh->normals.size() == s.mesh->positions.size()
                       ? ""
                       : "mesh: not loaded";
          }},
      shape.variant());
}

}  // namespace inhap::lab
