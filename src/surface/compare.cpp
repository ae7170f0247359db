// Surface comparison: sampling, point-to-plane ICP, cropped Hausdorff/mean/RMS distances.
#include "inhap/surface/compare.hpp"
#include "inhap/core/stats.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/surface/points.hpp"

namespace inhap {

SurfaceSamples sample_surface(const TriMesh& mesh, double density, std::uint64_t seed) {
  SurfaceSamples s;
  s.points = mesh.positions;
  s.weights.assign(mesh.positions.size(), 0.0);
  {
    TriMesh copy;  // the mesh's own normals may be stale or absent
    copy.positions = mesh.positions;
    copy.triangles = mesh.triangles;
    copy.compute_normals();
    s.normals = std::move(copy.normals);
  }
  Rng rng(seed);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const double area = mesh.face_area(f);
    if (!(area > 0)) continue;
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(area * density)));
    const Tri& t = mesh.triangles[f];
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 normal = mesh.face_normal(f);
    for (std::size_t k = 0; k < n; ++k) {
      double u = rng.uniform(), v = rng.uniform();
      if (u + v > 1) u = 1 - u, v = 1 - v;
      s.points.push_back(a + u * (b - a) + v * (c - a));
      s.weights.push_back(area / static_cast<double>(n));
      s.normals.push_back(normal);
    }
  }
  return s;
}

namespace {

Mat3 rotation(const Vec3& w) {
  const double angle = w.norm();
  return angle > 0 ? Mat3(Eigen::AngleAxisd(angle, w / angle)) : Mat3::Identity();
}

}  // namespace

IcpResult icp_point_to_plane(const TriMesh& moving, const TriMesh& fixed, const IcpOptions& o) {
  if (moving.triangles.empty() || fixed.triangles.empty())
    throw Error("ICP: expected two meshes with triangles");
  IcpResult res;
  const MeshIndex index(fixed);
  // Evenly strided samples of the moving surface (vertices and faces).
  const Box3 box = moving.bbox();
  double area = 0;
  for (std::size_t f = 0; f < moving.triangles.size(); ++f) area += moving.face_area(f);
  const SurfaceSamples all =
      sample_surface(moving, 2.0 * static_cast<double>(o.max_samples) / std::max(area, 1e-9), 7);
  std::vector<Vec3> src;
  const std::size_t stride = std::max<std::size_t>(1, all.points.size() / o.max_samples);
  for (std::size_t i = 0; i < all.points.size(); i += stride) src.push_back(all.points[i]);
  const double radius = std::max(1e-9, 0.5 * box.size().norm());

  RigidTransform T;
  std::vector<double> dist(src.size());
  for (std::size_t it = 0; it < o.max_iterations; ++it) {
    std::vector<Vec3> p(src.size()), q(src.size()), n(src.size());
    for (std::size_t i = 0; i < src.size(); ++i) {
      p[i] = T.apply(src[i]);
      const ClosestPoint cp = index.closest_point(p[i]);
      q[i] = cp.point;
      n[i] = cp.valid() ? fixed.face_normal(static_cast<std::size_t>(cp.triangle)) : Vec3::Zero();
      dist[i] = cp.valid() ? std::sqrt(cp.distance2) : std::numeric_limits<double>::infinity();
    }
    const double limit = o.reject_factor * std::max(median(dist, 0.0), 1e-9);
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    double sse = 0;
    std::size_t used = 0;
    for (std::size_t i = 0; i < src.size(); ++i) {
      if (!(dist[i] <= limit) || n[i].squaredNorm() == 0) continue;
      const double r = (p[i] - q[i]).dot(n[i]);
      Eigen::Matrix<double, 6, 1> J;
      J << p[i].cross(n[i]), n[i];
      A.selfadjointView<Eigen::Lower>().rankUpdate(J);
      b -= r * J;
      sse += r * r;
      ++used;
    }
    if (used < 6) break;
    const double rms = std::sqrt(sse / static_cast<double>(used));
    if (it == 0) res.rms_before = rms;
    res.rms_after = rms;
    A = A.selfadjointView<Eigen::Lower>();
    const Eigen::Matrix<double, 6, 1> x = A.ldlt().solve(b);
    if (!x.allFinite()) break;
    const Mat3 dR = rotation(x.head<3>());
    T.R = dR * T.R;
    T.t = dR * T.t + x.tail<3>();
    res.iterations = it + 1;
    if (x.head<3>().norm() * radius + x.tail<3>().norm() < o.tolerance) break;
  }
  res.transform = T;
  return res;
}

namespace {

struct Side {
  OneSided stats;
  std::vector<double> vertex_error;
};

/// The open rim of a mesh: per face, which of its edges (bit e: from vertex e to e+1) and
/// vertices (bit 3 + v) lie on the boundary; and points along the boundary edges.
struct Rim {
  std::vector<std::uint8_t> flags;
  std::vector<Vec3> samples;  ///< every margin/4 along the boundary edges (margin > 0)
};

Rim make_rim(const TriMesh& m, double margin) {
  Rim rim;
  const MeshAdjacency adj = build_adjacency(m);
  std::vector<char> bvert(m.positions.size(), 0);
  rim.flags.assign(m.triangles.size(), 0);
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (std::size_t e = 0; e < 3; ++e) {
      if (adj.face_neighbors[f][e] >= 0) continue;
      rim.flags[f] |= static_cast<std::uint8_t>(1u << e);
      const Vec3& a = m.positions[static_cast<std::size_t>(m.triangles[f][e])];
      const Vec3& b = m.positions[static_cast<std::size_t>(m.triangles[f][(e + 1) % 3])];
      bvert[static_cast<std::size_t>(m.triangles[f][e])] = 1;
      bvert[static_cast<std::size_t>(m.triangles[f][(e + 1) % 3])] = 1;
      if (margin > 0) {
        const auto steps = static_cast<int>(std::ceil((b - a).norm() / (0.25 * margin)));
        for (int k = 0; k <= steps; ++k)
          rim.samples.push_back(a + (b - a) * k / std::max(1, steps));
      }
    }
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (std::size_t v = 0; v < 3; ++v)
      if (bvert[static_cast<std::size_t>(m.triangles[f][v])])
        rim.flags[f] |= static_cast<std::uint8_t>(1u << (3 + v));
  return rim;
}

/// True when the closest point lies on the boundary of its mesh (up to rounding of the
/// barycentric weights).
bool on_rim(const ClosestPoint& cp, const Rim& rim) {
  if (!cp.valid()) return false;
  constexpr double eps = 1e-5;
  const std::uint8_t f = rim.flags[static_cast<std::size_t>(cp.triangle)];
  for (int e = 0; e < 3; ++e)  // on edge e when the opposite vertex has no weight
    if ((f & (1u << e)) && cp.bary[(e + 2) % 3] <= eps) return true;
  for (int v = 0; v < 3; ++v)
    if ((f & (1u << (3 + v))) && cp.bary[v] >= 1.0 - eps) return true;
  return false;
}

/// Half-length of the normal lines of the overlap test: longer than any distance between the
/// two meshes.
double line_length(const TriMesh& a, const TriMesh& b) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const TriMesh* m : {&a, &b})
    for (const Vec3& p : m->positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return 2.0 * (hi - lo).norm() + 1.0;
}

Side one_sided(const TriMesh& from, const MeshIndex& to, const Rim& to_rim, CompareOptions o,
               std::uint64_t seed, double line, bool crop) {
  if (!crop) {  // every sample of this side counts
    o.region.clear();
    o.crop_distance = 0;
    o.exclude_boundary = false;
    o.normal_overlap = false;
  }
  Side side;
  const SurfaceSamples s = sample_surface(from, o.density, seed);
  std::vector<double> d(s.points.size());
  std::vector<char> rim(s.points.size(), 0);
  std::vector<Vec3> foot(o.exclude_boundary ? s.points.size() : 0);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const ClosestPoint cp = to.closest_point(s.points[i]);
    d[i] = std::sqrt(cp.distance2);
    if (o.exclude_boundary) {
      rim[i] = on_rim(cp, to_rim);
      foot[i] = cp.point;
    }
  }
  if (o.exclude_boundary && o.rim_margin > 0 && !to_rim.samples.empty()) {
    const std::vector<double> dr = nearest_distances(to_rim.samples, foot);
    for (std::size_t i = 0; i < dr.size(); ++i) rim[i] = rim[i] || dr[i] <= o.rim_margin;
  }
  side.vertex_error.assign(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(from.num_vertices()));
  std::vector<double> region_d;
  if (!o.region.empty()) region_d = nearest_distances(o.region, s.points);
  double wsum = 0, wmean = 0, wsq = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!region_d.empty() && region_d[i] > o.region_radius) continue;
    if (o.crop_distance > 0 && d[i] > o.crop_distance) continue;
    if (rim[i]) continue;
    if (o.normal_overlap) {
      const Vec3 n = line * s.normals[i];
      if (!(n.squaredNorm() > 0) || !to.any_hit(s.points[i] - n, s.points[i] + n)) continue;
    }
    ++side.stats.samples;
    if (d[i] >= side.stats.max) side.stats.max = d[i], side.stats.max_at = s.points[i];
    wsum += s.weights[i];
    wmean += s.weights[i] * d[i];
    wsq += s.weights[i] * d[i] * d[i];
  }
  if (wsum > 0) {
    side.stats.mean = wmean / wsum;
    side.stats.rms = std::sqrt(wsq / wsum);
  }
  return side;
}

}  // namespace

std::string_view to_string(CropSides sides) {
  switch (sides) {
    case CropSides::kA:
      return "a";
    case CropSides::kB:
      return "b";
    case CropSides::kBoth:
      break;
  }
  return "both";
}

CropSides crop_sides_from_string(std::string_view text) {
  if (text == "both") return CropSides::kBoth;
  if (text == "a") return CropSides::kA;
  if (text == "b") return CropSides::kB;
  throw Error("crop sides: expected both, a or b, got '" + std::string(text) + "'");
}

CompareResult compare_surfaces(const TriMesh& a_in, const TriMesh& b, const CompareOptions& o) {
  if (a_in.triangles.empty() || b.triangles.empty())
    throw Error("compare: expected two meshes with triangles");
  CompareResult res;
  TriMesh a = a_in;
  if (o.icp) {
    res.transform = icp_point_to_plane(a, b, o.icp_options).transform;
    for (Vec3& p : a.positions) p = res.transform.apply(p);
    a.compute_normals();
  }
  const MeshIndex index_a(a), index_b(b);
  Rim rim_a, rim_b;
  if (o.exclude_boundary) rim_a = make_rim(a, o.rim_margin), rim_b = make_rim(b, o.rim_margin);
  const double line = o.normal_overlap ? line_length(a, b) : 0.0;
  Side ab = one_sided(a, index_b, rim_b, o, o.seed, line, o.crop_sides != CropSides::kB);
  Side ba = one_sided(b, index_a, rim_a, o, o.seed + 1, line, o.crop_sides != CropSides::kA);
  if (ab.stats.samples == 0 || ba.stats.samples == 0)
    throw Error("compare: no surface sample left in the common region (check the crop options)");
  res.a_to_b = ab.stats;
  res.b_to_a = ba.stats;
  res.a_vertex_error = std::move(ab.vertex_error);
  res.b_vertex_error = std::move(ba.vertex_error);
  res.hausdorff = std::max(res.a_to_b.max, res.b_to_a.max);
  res.mean = 0.5 * (res.a_to_b.mean + res.b_to_a.mean);
  res.rms = std::sqrt(0.5 * (res.a_to_b.rms * res.a_to_b.rms + res.b_to_a.rms * res.b_to_a.rms));
  return res;
}

CropSides auto_crop_sides(const TriMesh& a, const TriMesh& b) {
  auto closed = [](const TriMesh& m) {
    return analyze_topology(m, build_adjacency(m)).watertight();
  };
  const bool ca = closed(a), cb = closed(b);
  if (ca == cb) return CropSides::kBoth;
  return cb ? CropSides::kB : CropSides::kA;
}

CroppedSides cropped_sides(const CompareOptions& o) {
  const bool any =
      !o.region.empty() || o.crop_distance > 0 || o.exclude_boundary || o.normal_overlap;
  return {any && o.crop_sides != CropSides::kB, any && o.crop_sides != CropSides::kA};
}

}  // namespace inhap
