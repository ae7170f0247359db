// Shape reconstruction on the virtual lab (see shape_lab.hpp). Units: mm, N, s, N/mm.
#include "inhap/eval/shape_lab.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "inhap/contact/tapping.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/reach.hpp"
#include "inhap/surface/points.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::eval {
namespace {

// --- reference surfaces of the lab shapes ("the optical scan") -------------------------------

/// Closed mesh of a spherical cap on the plane z = base.z: sphere part + base disc.
TriMesh dome_mesh(const Vec3& base, double a, double h) {
  const double rs = (a * a + h * h) / (2 * h);
  const Vec3 c = base + Vec3(0, 0, h - rs);
  const double theta_max = std::atan2(a, rs - h);  // polar angle of the rim
  const int rings = 120, sectors = 360;
  TriMesh m;
  m.positions.push_back(c + Vec3(0, 0, rs));
  for (int i = 1; i <= rings; ++i) {
    const double th = theta_max * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double ph = 2 * std::numbers::pi * j / sectors;
      m.positions.push_back(
          c + rs * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  auto v = [&](int i, int j) { return 1 + (i - 1) * sectors + (j % sectors); };
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({0, v(1, j), v(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  const int centre = static_cast<int>(m.positions.size());
  m.positions.push_back(base);
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({centre, v(rings, j + 1), v(rings, j)});
  return m;
}

/// A sphere: the cap of height 2r over a vanishing base circle.
TriMesh sphere_mesh(const Vec3& c, double r) {
  return dome_mesh(c - Vec3(0, 0, r), 1e-6 * r, 2 * r);
}

/// Prism over y in [-hy, hy] whose (x, z) section is bounded below by z = zb and above by the
/// x-monotone chain `top` (x increasing, z > zb); the caps are triangulated in vertical strips.
TriMesh prism_mesh(const std::vector<Vec2>& top, double zb, const Vec3& origin, double hy) {
  TriMesh m;
  const int n = static_cast<int>(top.size());
  // Per side: top chain (0..n-1), then the bottom points below it (n..2n-1).
  for (double y : {-hy, hy}) {
    for (const Vec2& p : top) m.positions.push_back(origin + Vec3(p.x(), y, p.y()));
    for (const Vec2& p : top) m.positions.push_back(origin + Vec3(p.x(), y, zb));
  }
  auto v = [&](int side, int bottom, int i) { return side * 2 * n + bottom * n + i; };
  auto quad = [&](int a, int b, int c, int d) {  // a-b-c-d clockwise seen from outside
    m.triangles.push_back({a, c, b});
    m.triangles.push_back({a, d, c});
  };
  for (int i = 0; i + 1 < n; ++i) {
    quad(v(0, 0, i), v(1, 0, i), v(1, 0, i + 1), v(0, 0, i + 1));  // top
    quad(v(0, 1, i), v(0, 1, i + 1), v(1, 1, i + 1), v(1, 1, i));  // bottom
    quad(v(0, 1, i), v(0, 0, i), v(0, 0, i + 1), v(0, 1, i + 1));  // cap y = -hy
    quad(v(1, 1, i), v(1, 1, i + 1), v(1, 0, i + 1), v(1, 0, i));  // cap y = +hy
  }
  quad(v(0, 1, 0), v(1, 1, 0), v(1, 0, 0), v(0, 0, 0));                  // wall x = x_first
  quad(v(0, 1, n - 1), v(0, 0, n - 1), v(1, 0, n - 1), v(1, 1, n - 1));  // wall x = x_last
  return m;
}

}  // namespace

MatchedContacts match_contacts(const lab::LabRecording& lab, const ContactOptions& o,
                               std::size_t limit) {
  MatchedContacts m;
  const TappingResult res = contacts_from_recording(lab.rec, o, ForceSource::kAuto);
  long last_tap = -1;
  for (const Contact& c : res.contacts) {
    const long tap = lab.truth.tap[c.detect_index];
    if (tap < 0 || tap == last_tap) {  // noise, or a second detection within one true contact
      ++m.false_detections;
      continue;
    }
    last_tap = tap;
    if (m.contacts.size() == limit) break;
    m.contacts.push_back(c);
    m.truth.push_back(lab.truth.c[c.detect_index]);
    m.error.push_back((c.point - lab.truth.c[c.detect_index]).norm());
    m.stiffness.push_back(lab.truth.k[c.detect_index]);
  }
  return m;
}

EntrySideCounts count_far_side_contacts(const lab::LabRecording& lab, const lab::SoftObject& object,
                                        double probe_radius_mm, double approach_mm,
                                        double reversal_n) {
  EntrySideCounts out;
  const lab::TruthTable& tr = lab.truth;
  const std::size_t n = std::min(tr.size(), lab.rec.size());
  Vec3 dir = Vec3::Zero(), last_normal = Vec3::Zero(), exit_normal = Vec3::Zero();
  bool reversed = false, went_away = true;
  for (std::size_t i = 0; i < n; ++i) {
    const bool starts = tr.contact[i] && (i == 0 || !tr.contact[i - 1]);
    if (starts) {
      if (reversed) ++out.force_reversals;
      reversed = false;
      ++out.episodes;
      dir = tr.force[i].norm() > 1e-12 ? Vec3(tr.force[i].normalized()) : Vec3::Zero();
      if (all_finite(tr.c[i])) {
        const Vec3 normal = object.query(tr.c[i]).normal;
        if (!went_away && normal.dot(last_normal) < -0.5 && exit_normal.dot(last_normal) < -0.5)
          ++out.far_side_first_contacts;
        last_normal = normal;
      }
      went_away = false;
    } else if (tr.contact[i] && tr.force[i].dot(dir) < -reversal_n) {
      reversed = true;
    }
    if (i > 0 && !tr.contact[i] && tr.contact[i - 1])
      exit_normal = object.query(lab.rec.p[i]).normal;  // the side the last contact ended on
    if (!tr.contact[i] && !went_away &&
        object.query(lab.rec.p[i]).distance - probe_radius_mm >= approach_mm)
      went_away = true;
  }
  if (reversed) ++out.force_reversals;
  return out;
}

lab::LabRecording record_taps(const lab::Scene& scene, std::size_t taps, std::uint64_t seed,
                              const Progress& progress, lab::Physics physics,
                              const lab::TapOptions& tap) {
  lab::RecordSpec spec;
  spec.physics = physics;
  spec.operator_name = "tap";
  spec.probe = lab::ProbeSpec::tip();
  spec.seed = seed;
  spec.tap = tap;
  // About 0.7 taps per second in region mode, 1.1 going round the object.
  spec.seconds = 10.0 + (tap.whole_object ? 0.95 : 1.7) * static_cast<double>(taps);
  for (int attempt = 0; attempt < 4; ++attempt) {
    lab::LabRecording rec =
        lab::record_scene(scene, spec, [&](const std::string&, double f, double) {
          if (progress) progress("tapping", f, 0.0);
        });
    long n = 0;
    for (long t : rec.truth.tap) n = std::max(n, t + 1);
    if (static_cast<std::size_t>(n) >= taps) return rec;
    spec.seconds *= 1.6;
  }
  throw Error(
      fmt::format("eval: the tapping operator gave fewer than {} taps on {}", taps, scene.name));
}

TriMesh reachable_part(const TriMesh& reference, const lab::SoftObject& object,
                       const lab::ReachOptions& reach) {
  // Faces are split until their edges are at most 2 mm (a prism's side wall is two triangles
  // from the table to the top) and kept when their centroid is reachable.
  constexpr double kMaxEdge = 2.0;
  TriMesh out;
  std::vector<std::array<Vec3, 3>> stack;
  for (std::size_t f = 0; f < reference.num_triangles(); ++f) {
    const Tri& t = reference.triangles[f];
    const Vec3 n = reference.face_normal(f);
    stack.push_back({reference.positions[static_cast<std::size_t>(t[0])],
                     reference.positions[static_cast<std::size_t>(t[1])],
                     reference.positions[static_cast<std::size_t>(t[2])]});
    while (!stack.empty()) {
      const auto [a, b, c] = stack.back();
      stack.pop_back();
      if (std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) > kMaxEdge) {
        const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
        stack.push_back({a, ab, ca});
        stack.push_back({ab, b, bc});
        stack.push_back({ca, bc, c});
        stack.push_back({ab, bc, ca});
        continue;
      }
      if (!lab::reachable(object, 0.0, (a + b + c) / 3.0, n, reach)) continue;
      const auto i = static_cast<std::int32_t>(out.positions.size());
      out.positions.insert(out.positions.end(), {a, b, c});
      out.triangles.push_back({i, i + 1, i + 2});
    }
  }
  out.compute_normals();
  return out;
}

double taps_per_minute(const lab::LabRecording& rec) {
  long n = 0;
  for (long t : rec.truth.tap) n = std::max(n, t + 1);
  const double seconds = rec.rec.size() > 1 ? rec.rec.t.back() - rec.rec.t.front() : 0.0;
  return seconds > 0 ? 60.0 * static_cast<double>(n) / seconds : 0.0;
}

double tap_coverage(const lab::SoftObject& object, const std::vector<Vec3>& taps, double radius_mm,
                    std::size_t samples, const lab::ReachOptions& reach) {
  const std::vector<lab::SurfaceSample> s = lab::reachable_samples(object, 0.0, samples, 99, reach);
  if (s.empty() || taps.empty()) return 0.0;
  std::vector<Vec3> pts;
  for (const auto& x : s) pts.push_back(x.point);
  const std::vector<double> d = nearest_distances(taps, pts);
  std::size_t near = 0;
  for (double v : d) near += v <= radius_mm;
  return static_cast<double>(near) / static_cast<double>(d.size());
}

lab::Scene bunny_scene(const std::string& ply_path, double size_mm) {
  TriMesh m = read_mesh(ply_path);
  for (Vec3& p : m.positions) p = Vec3(p.x(), -p.z(), p.y());  // y up -> z up
  Box3 b;
  for (const Vec3& p : m.positions) b.extend(p);
  const double scale = size_mm / std::max(b.size().maxCoeff(), 1e-12);
  const Vec3 base(b.center().x(), b.center().y(), b.min.z());
  for (Vec3& p : m.positions) p = scale * (p - base);
  lab::Scene scene;
  scene.name = "bunny";
  scene.description =
      fmt::format("Stanford bunny scaled to {:g} mm, standing on z = 0, Ecoflex 00-30", size_mm);
  scene.object = lab::SoftObject(lab::make_mesh_shape(std::move(m), ply_path),
                                 lab::builtin_scene("planar").object.material());
  scene.region = lab::default_region(scene.object.shape());
  scene.source = ply_path;
  return scene;
}

TriMesh reference_mesh(const lab::Shape& shape) {
  TriMesh m;
  if (const auto* mesh = std::get_if<lab::MeshShape>(&shape.variant())) {
    if (!mesh->mesh) throw Error("eval shape: the mesh shape has no mesh");
    m = *mesh->mesh;
    m.compute_normals();
    return m;
  }
  if (const auto* s = std::get_if<lab::SphereShape>(&shape.variant())) {
    m = sphere_mesh(s->center, s->radius);
  } else if (const auto* h = std::get_if<lab::HemisphereShape>(&shape.variant())) {
    m = dome_mesh(h->base_center, h->radius, h->radius);
  } else if (const auto* d = std::get_if<lab::DomeShape>(&shape.variant())) {
    m = dome_mesh(d->base_center, d->base_radius, d->height);
  } else if (const auto* b = std::get_if<lab::BoxShape>(&shape.variant())) {
    const Vec3 hs = b->half_size;
    m = prism_mesh({{-hs.x(), hs.z()}, {hs.x(), hs.z()}}, -hs.z(), b->center, hs.y());
  } else if (const auto* r = std::get_if<lab::RidgedSlabShape>(&shape.variant())) {
    // The lab's profile: flat top of the slab with triangular ridges (x increasing).
    const double hw = 0.5 * r->size_x, pitch = r->size_x / r->ridges;
    std::vector<Vec2> top{{-hw, r->thickness}};
    for (int i = 0; i < r->ridges; ++i) {
      const double xc = -hw + (i + 0.5) * pitch;
      for (const Vec2& p :
           {Vec2(xc - 0.5 * r->ridge_width, r->thickness), Vec2(xc, r->thickness + r->ridge_height),
            Vec2(xc + 0.5 * r->ridge_width, r->thickness)})
        if ((top.back() - p).norm() > 1e-9) top.push_back(p);
    }
    if ((top.back() - Vec2(hw, r->thickness)).norm() > 1e-9) top.emplace_back(hw, r->thickness);
    m = prism_mesh(top, 0.0, r->base_center, 0.5 * r->size_y);
  } else {
    throw Error(fmt::format("eval shape: no reference mesh for a {} shape", shape.type_name()));
  }
  m.compute_normals();
  // The distances are only as good as this mesh: it must be closed and outward.
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  double volume = 0;
  for (const Tri& t : m.triangles)
    volume += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  if (!topo.watertight() || !topo.oriented() || !(volume > 0))
    throw Error(
        fmt::format("eval shape: internal error: the reference mesh of the {} shape is "
                    "not closed and outward",
                    shape.type_name()));
  return m;
}

ShapeVariant reconstruct_and_compare(const lab::LabRecording& rec, ContactMethod method,
                                     std::size_t taps, const TriMesh& reference,
                                     const ShapeCompareOptions& options) {
  ContactOptions o;
  o.method = method;
  ShapeVariant v;
  v.matched = match_contacts(rec, o, taps);
  const MatchedContacts& m = v.matched;
  std::vector<Vec3> pts, dirs;
  for (const Contact& c : m.contacts) pts.push_back(c.point), dirs.push_back(c.direction);
  ReconstructReport rep;
  v.mesh = reconstruct_surface(pts, dirs, options.reconstruct, &rep);
  // Common region: the reference near the true contact points of the taps the model was built
  // from (an outlier tap, e.g. a tip that slipped down a wall, is not part of the model).
  std::vector<Vec3> region;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (rep.used[i]) region.push_back(m.truth[i]);
  CompareOptions co;
  co.icp = options.icp;
  co.crop_sides = options.uncropped_reconstruction ? CropSides::kB : CropSides::kBoth;
  co.region = region;
  co.region_radius = options.region_mm;
  co.exclude_boundary = true;
  co.rim_margin = options.rim_margin_mm;
  co.normal_overlap = options.normal_overlap;
  v.points = pts.size();
  v.vertices = v.mesh.num_vertices();
  v.faces = v.mesh.num_triangles();
  v.cmp = compare_surfaces(v.mesh, reference, co);
  if (options.reachable_reference) {
    // Reference side: only its reachable part (within the region of the taps) is scored.
    const CompareResult r = compare_surfaces(v.mesh, *options.reachable_reference, co);
    v.cmp.b_to_a = r.b_to_a;
    v.cmp.b_vertex_error.clear();
    v.cmp.hausdorff = std::max(v.cmp.a_to_b.max, v.cmp.b_to_a.max);
    v.cmp.mean = 0.5 * (v.cmp.a_to_b.mean + v.cmp.b_to_a.mean);
    v.cmp.rms = std::sqrt(
        0.5 * (v.cmp.a_to_b.rms * v.cmp.a_to_b.rms + v.cmp.b_to_a.rms * v.cmp.b_to_a.rms));
  }
  v.region = std::move(region);
  for (Vec3& p : v.mesh.positions) p = v.cmp.transform.apply(p);
  return v;
}

}  // namespace inhap::eval
