// The Stanford bunny (confidence -> stiffness) and the CT head (skin-bone distance ->
// stiffness, CGAL-simplified) of thesis fig. 5.3b-c / 5.7b-c, scaled into a 100 mm cube, with
// strokes through the regions the thesis marks. Units: mm, N/mm.
#include "inhap/rendering/real_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <optional>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/volume.hpp"

namespace inhap::rendering {

namespace {

// Uniform scale into [0, cube]^3 (largest extent = cube), min corner at the origin.
double fit_cube(TriMesh& m, double cube) {
  const Box3 b = m.bbox();
  const double ext = (b.max - b.min).maxCoeff();
  if (!(ext > 0)) throw Error("real data: the mesh has no extent");
  const double s = cube / ext;
  m.transform(s, b.min);
  m.normals.clear();
  m.compute_normals();
  return s;
}

void rotate(TriMesh& m, const Mat3& r) {
  for (auto& p : m.positions) p = r * p;
  m.normals.clear();
  m.compute_normals();
}

std::vector<std::vector<std::int32_t>> neighbours(const TriMesh& m) {
  std::vector<std::vector<std::int32_t>> nb(m.num_vertices());
  for (const Tri& t : m.triangles)
    for (int a = 0; a < 3; ++a) {
      nb[std::size_t(t[std::size_t(a)])].push_back(t[std::size_t((a + 1) % 3)]);
      nb[std::size_t(t[std::size_t(a)])].push_back(t[std::size_t((a + 2) % 3)]);
    }
  for (auto& v : nb) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  return nb;
}

std::vector<double> smooth(std::vector<double> v, const std::vector<std::vector<std::int32_t>>& nb,
                           int iterations) {
  std::vector<double> w(v.size());
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      double s = v[i];
      for (auto j : nb[i]) s += v[std::size_t(j)];
      w[i] = s / double(nb[i].size() + 1);
    }
    v.swap(w);
  }
  return v;
}

// Umbrella curvature: (mean of the neighbours - p) . n; > 0 where the surface is concave.
std::vector<double> concavity(const TriMesh& m, const std::vector<std::vector<std::int32_t>>& nb) {
  std::vector<double> h(m.num_vertices(), 0.0);
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (nb[i].empty()) continue;
    Vec3 c = Vec3::Zero();
    for (auto j : nb[i]) c += m.positions[std::size_t(j)];
    h[i] = (c / double(nb[i].size()) - m.positions[i]).dot(m.normals[i]);
  }
  return h;
}

// The top surface under (x, y): first hit of a vertical segment from above.
std::optional<SegmentHit> top_hit(const MeshIndex& index, double x, double y) {
  const Box3 b = index.bounds();
  return index.first_hit(Vec3(x, y, b.max.z() + 1.0), Vec3(x, y, b.min.z() - 1.0));
}

// A stroke the simulated hand can follow: every 0.5 mm the top surface exists, faces up
// (normal z >= min_nz) and does not step by more than 3 mm.
bool strokable(const TriMesh& m, const MeshIndex& index, const Vec2& a, const Vec2& b,
               double min_nz) {
  const double len = (b - a).norm();
  double last = std::numeric_limits<double>::quiet_NaN();
  for (double u = 0; u <= len; u += 0.5) {
    const Vec2 q = a + (b - a) * (u / len);
    const auto hit = top_hit(index, q.x(), q.y());
    if (!hit || m.face_normal(std::size_t(hit->triangle)).z() < min_nz) return false;
    if (std::isfinite(last) && std::abs(hit->point.z() - last) > 3.0) return false;
    last = hit->point.z();
  }
  return true;
}

struct Candidate {
  std::size_t vertex;
  double score;
};

// The first candidate (in order) with a strokable line of half length `half` through it along x
// or y; its stroke with mark `label` at the middle.
DataStroke stroke_through(const TriMesh& m, const MeshIndex& index,
                          const std::vector<Candidate>& order, double half, const MarkedPoint& mark,
                          const std::string& name, bool prefer_y) {
  for (const Candidate& c : order) {
    const Vec3& p = m.positions[c.vertex];
    const Vec2 centre(p.x(), p.y());
    const Vec2 dirs[2] = {prefer_y ? Vec2::UnitY() : Vec2::UnitX(),
                          prefer_y ? Vec2::UnitX() : Vec2::UnitY()};
    for (const Vec2& d : dirs) {
      const Vec2 a = centre - half * d, b = centre + half * d;
      if (!strokable(m, index, a, b, 0.3)) continue;
      DataStroke s{name, a, b, {mark}};
      s.marks.front().along_mm = half;
      return s;
    }
  }
  throw Error(fmt::format("real data: no strokable line for '{}'", name));
}

// Vertices seen from above (the top hit at their (x, y) is the vertex's own neighbourhood).
std::vector<char> visible_from_above(const TriMesh& m, const MeshIndex& index, double min_nz) {
  std::vector<char> vis(m.num_vertices(), 0);
  for (std::size_t i = 0; i < vis.size(); ++i) {
    if (m.normals[i].z() < min_nz) continue;
    const Vec3& p = m.positions[i];
    const auto hit = top_hit(index, p.x(), p.y());
    vis[i] = hit && std::abs(hit->point.z() - p.z()) < 0.5;
  }
  return vis;
}

}  // namespace

RealDataset load_bunny(const std::string& ply_path, const RealDataOptions& o) {
  TriMesh m = read_mesh(ply_path);
  if (!m.has_property("confidence"))
    throw Error(fmt::format("{}: expected a vertex property 'confidence'", ply_path));
  Mat3 r;
  r << 1, 0, 0, 0, 0, -1, 0, 1, 0;  // y-up -> z-up
  rotate(m, r);
  RealDataset ds;
  ds.name = "bunny";
  ds.file = ply_path;
  ds.scale = fit_cube(m, o.cube_mm);
  const std::vector<double>& conf = m.property("confidence");
  const double cmax = *std::max_element(conf.begin(), conf.end());
  if (!(cmax > 0)) throw Error(fmt::format("{}: every confidence is 0", ply_path));
  std::vector<double> k(conf.size());
  std::size_t floored = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    k[i] = o.k_max * conf[i] / cmax;
    if (k[i] < o.k_floor) {
      k[i] = o.k_floor;
      ++floored;
    }
  }
  m.set_property("stiffness", k);
  ds.stiffness_from = fmt::format(
      "scan confidence: k = {} N/mm x confidence / {:.3f} (its maximum), floored at {} N/mm "
      "({:.1f}% of the vertices)",
      o.k_max, cmax, o.k_floor, 100.0 * double(floored) / double(k.size()));
  // Stroke: through the softest concave region seen from above (thesis point C).
  const auto nb = neighbours(m);
  const std::vector<double> ks = smooth(k, nb, 10), hs = smooth(concavity(m, nb), nb, 10);
  const MeshIndex index(m, MeshIndexOptions{.seed_shell = 0});
  const std::vector<char> vis = visible_from_above(m, index, 0.7);
  std::vector<Candidate> order;
  for (std::size_t i = 0; i < k.size(); ++i)
    if (vis[i] && hs[i] > 0) order.push_back({i, ks[i]});
  std::sort(order.begin(), order.end(),
            [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  ds.strokes.push_back(stroke_through(m, index, order, 12.0,
                                      {"C", 0, "concave, low-confidence (soft) region"},
                                      "bunny concave soft region", false));
  ds.mesh = std::move(m);
  return ds;
}

RealDataset load_head(const std::string& nhdr_path, const RealDataOptions& o) {
  HeadModelOptions ho;
  ho.k_min = o.head_k_min;
  ho.k_max = o.k_max;
  const HeadModel hm = head_from_volume(read_nrrd(nhdr_path), ho);
  TriMesh m = simplify_mesh(hm.mesh, o.head_triangles);
  Mat3 r;
  r << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // the face (-y in the volume) up (+z)
  rotate(m, r);
  RealDataset ds;
  ds.name = "ct-head";
  ds.file = nhdr_path;
  ds.scale = fit_cube(m, o.cube_mm);
  // Stiffness inversely proportional to the skin-bone distance d (thesis: 0.4-1.0 N/mm):
  // k = clamp(k_max d_ref / d, k_min, k_max), d_ref = (k_min / k_max) d_far, d_far the 98th
  // percentile of d over the skin facing up (the face). Over the whole skin d_far would be set by
  // the caps closing the clipped volume at its first and last slice (far from any bone: 43 mm
  // against the face's 23 mm), and the whole face would be 1.0 N/mm.
  const std::vector<double>& dist = m.property("bone_distance");
  std::vector<double> face;
  for (std::size_t i = 0; i < dist.size(); ++i)
    if (m.normals[i].z() > 0.5) face.push_back(dist[i]);
  if (face.empty()) throw Error(fmt::format("{}: no skin faces up", nhdr_path));
  const auto q = static_cast<std::size_t>(0.98 * double(face.size() - 1));
  std::nth_element(face.begin(), face.begin() + std::ptrdiff_t(q), face.end());
  const double k_min = std::max(o.k_floor, o.head_k_min), d_far = face[q];
  const double d_ref = k_min / o.k_max * d_far;
  std::vector<double> k(dist.size());
  for (std::size_t i = 0; i < k.size(); ++i)
    k[i] = std::clamp(o.k_max * d_ref / std::max(dist[i], 1e-9), k_min, o.k_max);
  m.set_property("stiffness", k);
  ds.stiffness_from = fmt::format(
      "skin-to-bone distance d (CT mm): k = {} N/mm x {:.1f} mm / d, clamped to [{}, {}] N/mm "
      "({} N/mm from d = {:.1f} mm, the 98th percentile over the face, on)",
      o.k_max, d_ref, k_min, o.k_max, k_min, d_far);
  // Stroke over the eye (thesis point D): the softest up-facing skin 8-25 mm beside and
  // 10-32 mm towards the crown (-y: the first slices are the top of the head) from the nose tip,
  // the highest point of the face-up head.
  const auto nb = neighbours(m);
  const std::vector<double> ks = smooth(k, nb, 5);
  const MeshIndex index(m, MeshIndexOptions{.seed_shell = 0});
  const std::vector<char> vis = visible_from_above(m, index, 0.5);
  const auto nose =
      std::size_t(std::max_element(m.positions.begin(), m.positions.end(),
                                   [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); }) -
                  m.positions.begin());
  const Vec3 tip = m.positions[nose];
  std::vector<Candidate> order;
  for (std::size_t i = 0; i < k.size(); ++i) {
    const Vec3 d = m.positions[i] - tip;
    if (vis[i] && std::abs(d.x()) > 8 && std::abs(d.x()) < 25 && d.y() > -32 && d.y() < -10)
      order.push_back({i, ks[i]});
  }
  std::sort(order.begin(), order.end(),
            [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  ds.strokes.push_back(stroke_through(
      m, index, order, 9.0, {"D", 0, "eye: protruding, softer skin"}, "head over the eye", true));
  ds.mesh = std::move(m);
  return ds;
}

std::vector<RealDataset> load_real_datasets(const std::string& dir, const RealDataOptions& o) {
  namespace fs = std::filesystem;
  const fs::path root(dir);
  const fs::path afm = root / "afm-topography" / "sample_0.top",
                 bunny = root / "bunny" / "bun_zipper.ply", head = root / "headsq" / "quarter.nhdr";
  for (const auto& f : {afm, bunny, head})
    if (!fs::exists(f))
      throw Error(fmt::format("{}: missing (expected the real data sets)", f.string()));
  std::vector<RealDataset> out;
  out.push_back(load_afm(afm.string(), o));
  out.push_back(load_bunny(bunny.string(), o));
  out.push_back(load_head(head.string(), o));
  return out;
}

}  // namespace inhap::rendering
