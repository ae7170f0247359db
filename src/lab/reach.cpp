// Reachable surface of an object on a table (see reach.hpp). Units: mm.
#include "inhap/lab/reach.hpp"

#include <algorithm>
#include <cmath>

#include "inhap/core/random.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::lab {

double table_height(const SoftObject& object) {
  const Box3 b = object.shape().bounds();
  return b.empty() ? 0.0 : b.min.z();
}

bool segment_clear(const SoftObject& object, double r, const Vec3& a, const Vec3& b,
                   double clearance_mm) {
  const double len = (b - a).norm();
  const Vec3 u = len > 0 ? Vec3((b - a) / len) : Vec3::UnitZ();
  double s = 0;
  for (int guard = 0; guard < 100000; ++guard) {
    const double d = object.query(a + std::min(s, len) * u).distance - r;
    if (!(d > clearance_mm)) return false;
    if (s >= len) return true;
    s += d;  // nothing of the object lies closer than d: safe step
  }
  return false;
}

bool reachable(const SoftObject& object, double probe_radius, const Vec3& x, const Vec3& approach,
               const ReachOptions& o) {
  const double table = table_height(object);
  if (x.z() < table + o.base_margin_mm) return false;
  const Vec3 a = x + (probe_radius + o.start_mm) * approach;
  const Vec3 e = x + (probe_radius + o.stylus_length_mm) * approach;
  if (std::min(a.z(), e.z()) < table + probe_radius + o.table_clearance_mm) return false;
  if (!segment_clear(object, probe_radius, a, e, o.clearance_mm)) return false;
  const Box3 b = object.shape().bounds();
  const double top = b.max.z() + probe_radius + 10.0;
  return e.z() >= top ||
         segment_clear(object, probe_radius, e, Vec3(e.x(), e.y(), top), o.clearance_mm);
}

namespace {

std::vector<SurfaceSample> sample_mesh(const MeshShape& m, std::size_t count, Rng& rng,
                                       double* area) {
  std::vector<SurfaceSample> out;
  const TriMesh& mesh = *m.mesh;
  std::vector<double> cum(mesh.num_triangles());
  double total = 0;
  for (std::size_t f = 0; f < mesh.num_triangles(); ++f) cum[f] = total += mesh.face_area(f);
  if (area) *area = total;
  if (!(total > 0)) return out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double pick = rng.uniform() * total;
    const std::size_t f = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), pick) - cum.begin()),
        cum.size() - 1);
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Tri& t = mesh.triangles[f];
    const Vec3 p = mesh.positions[static_cast<std::size_t>(t[0])] +
                   u * (mesh.positions[static_cast<std::size_t>(t[1])] -
                        mesh.positions[static_cast<std::size_t>(t[0])]) +
                   v * (mesh.positions[static_cast<std::size_t>(t[2])] -
                        mesh.positions[static_cast<std::size_t>(t[0])]);
    out.push_back({p, mesh.face_normal(f)});
  }
  return out;
}

}  // namespace

std::vector<SurfaceSample> sample_object_surface(const SoftObject& object, std::size_t count,
                                                 std::uint64_t seed, double* area_mm2) {
  Rng rng(seed);
  if (const auto* m = std::get_if<MeshShape>(&object.shape().variant()); m && m->mesh)
    return sample_mesh(*m, count, rng, area_mm2);
  // Uniform points of the box are kept when within h of the surface and projected onto it:
  // the shell's volume is 2 h per unit area, so the projections are uniform by area up to
  // curvature terms of order h / radius.
  constexpr double h = 0.3;
  const Box3 b = object.shape().bounds();
  const Vec3 lo = b.min - Vec3::Constant(2 * h), size = b.size() + Vec3::Constant(4 * h);
  std::vector<SurfaceSample> out;
  out.reserve(count);
  std::size_t tried = 0;
  while (out.size() < count && tried < 2000 * count + 100000) {
    ++tried;
    const Vec3 p =
        lo + Vec3(rng.uniform() * size.x(), rng.uniform() * size.y(), rng.uniform() * size.z());
    const SurfaceQuery s = object.query(p);
    if (std::abs(s.distance) < h) out.push_back({s.closest, s.normal});
  }
  if (area_mm2)
    *area_mm2 =
        tried ? static_cast<double>(out.size()) / static_cast<double>(tried) * size.prod() / (2 * h)
              : 0.0;
  return out;
}

std::vector<SurfaceSample> reachable_samples(const SoftObject& object, double probe_radius,
                                             std::size_t count, std::uint64_t seed,
                                             const ReachOptions& options) {
  std::vector<SurfaceSample> out;
  for (const SurfaceSample& s : sample_object_surface(object, count, seed))
    if (reachable(object, probe_radius, s.point, s.normal, options)) out.push_back(s);
  return out;
}

}  // namespace inhap::lab
