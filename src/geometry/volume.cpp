// Isosurfaces of scalar volumes by marching tetrahedra, distances between surfaces and the
// CT-head stiffness map. Units: mm, N/mm.
//
// Why marching tetrahedra written here: CGAL 5.5 (the installed version) has no grid
// isosurfacing (Isosurfacing_3 arrived in CGAL 6.0) and VTK would add a very large dependency
// for one filter. Marching tetrahedra needs no case tables: every cube is split into the six
// tetrahedra of the Kuhn triangulation (all sharing the main diagonal), which is conforming
// between neighbouring cubes, so welding vertices per grid edge gives a watertight surface.
// See docs/tca-experiment.md.
#include "inhap/geometry/volume.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <span>
#include <unordered_map>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_index.hpp"

namespace inhap {

namespace {

// Volume with an optional one-voxel border of "outside" samples.
struct PaddedView {
  const Volume& v;
  int pad;
  float outside;
  int nx() const { return v.nx + 2 * pad; }
  int ny() const { return v.ny + 2 * pad; }
  int nz() const { return v.nz + 2 * pad; }
  float at(int i, int j, int k) const {
    i -= pad;
    j -= pad;
    k -= pad;
    if (i < 0 || j < 0 || k < 0 || i >= v.nx || j >= v.ny || k >= v.nz) return outside;
    return v.at(i, j, k);
  }
  Vec3 position(int i, int j, int k) const { return v.position(i - pad, j - pad, k - pad); }
};

class TetMarcher {
 public:
  TetMarcher(const PaddedView& view, double iso) : view_(view), iso_(iso) {}

  TriMesh run() {
    const int nx = view_.nx(), ny = view_.ny(), nz = view_.nz();
    std::array<float, 8> val;
    std::array<std::uint64_t, 8> gid;
    for (int k = 0; k + 1 < nz; ++k)
      for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
          int inside = 0;
          for (int c = 0; c < 8; ++c) {
            const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
            val[c] = view_.at(i + di, j + dj, k + dk);
            gid[c] = (std::uint64_t(k + dk) * ny + (j + dj)) * nx + (i + di);
            inside += val[c] >= iso_;
          }
          if (inside == 0 || inside == 8) continue;
          // Kuhn triangulation: paths 0 -> e_a -> e_a + e_b -> 7 for each axis order (a, b).
          static constexpr int kAxisOrders[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
          for (const auto& ab : kAxisOrders) {
            const int c1 = 1 << ab[0], c2 = c1 | (1 << ab[1]);
            tetrahedron({0, c1, c2, 7}, i, j, k, val, gid);
          }
        }
    // Gradient normals; angle-weighted face normals where the gradient vanishes.
    std::vector<Vec3> gradient_normals = std::move(mesh_.normals);
    mesh_.compute_normals();
    for (std::size_t v = 0; v < gradient_normals.size(); ++v) {
      const double len = gradient_normals[v].norm();
      if (len > 1e-12 && std::isfinite(len)) mesh_.normals[v] = gradient_normals[v] / len;
    }
    return std::move(mesh_);
  }

 private:
  Vec3 corner_position(int i, int j, int k, int c) const {
    return view_.position(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
  }

  // Central-difference gradient of the samples at a grid point (one-sided at the border), per mm.
  Vec3 gradient(const Eigen::Vector3i& g) const {
    const int n[3] = {view_.nx(), view_.ny(), view_.nz()};
    Vec3 grad;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3i lo = g, hi = g;
      if (g[a] > 0) --lo[a];
      if (g[a] + 1 < n[a]) ++hi[a];
      const double h = (hi[a] - lo[a]) * view_.v.spacing[a];
      grad[a] =
          h > 0 ? (double(view_.at(hi.x(), hi.y(), hi.z())) - view_.at(lo.x(), lo.y(), lo.z())) / h
                : 0.0;
    }
    return grad;
  }

  // One vertex per crossed grid edge, computed from the lower grid id so it is the same for
  // every tetrahedron sharing the edge. Its normal is minus the interpolated sample gradient
  // (smooth and exact for the field, unlike face normals of marching-tetrahedra slivers).
  std::int32_t edge_vertex(std::uint64_t ga, std::uint64_t gb, Eigen::Vector3i a, Eigen::Vector3i b,
                           float va, float vb) {
    if (ga > gb) {
      std::swap(ga, gb);
      std::swap(a, b);
      std::swap(va, vb);
    }
    const std::uint64_t key = (ga << 32) | gb;  // grid ids < 2^32 (checked by the caller)
    auto [it, fresh] = edges_.try_emplace(key, static_cast<std::int32_t>(mesh_.positions.size()));
    if (fresh) {
      // Keep vertices off the grid points (2 % of the edge) so no triangle degenerates when a
      // sample equals the iso value exactly.
      const double t = std::clamp((iso_ - double(va)) / (double(vb) - double(va)), 0.02, 0.98);
      const Vec3 pa = view_.position(a.x(), a.y(), a.z()), pb = view_.position(b.x(), b.y(), b.z());
      mesh_.positions.push_back(pa + t * (pb - pa));
      mesh_.normals.push_back(-((1 - t) * gradient(a) + t * gradient(b)));
    }
    return it->second;
  }

  void emit(std::span<const std::int32_t> cycle, const Vec3& outward) {
    Vec3 area = Vec3::Zero();
    for (std::size_t a = 0; a < cycle.size(); ++a)
      area += mesh_.positions[cycle[a]].cross(mesh_.positions[cycle[(a + 1) % cycle.size()]]);
    const bool flip = area.dot(outward) < 0;
    for (std::size_t a = 1; a + 1 < cycle.size(); ++a) {
      Tri t{cycle[0], cycle[a], cycle[a + 1]};
      if (flip) std::swap(t[1], t[2]);
      mesh_.triangles.push_back(t);
    }
  }

  void tetrahedron(std::array<int, 4> c, int i, int j, int k, const std::array<float, 8>& val,
                   const std::array<std::uint64_t, 8>& gid) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (int a = 0; a < 4; ++a) (val[c[a]] >= iso_ ? in[n_in++] : out[n_out++]) = c[a];
    if (n_in == 0 || n_out == 0) return;
    std::array<Vec3, 8> pos;
    std::array<Eigen::Vector3i, 8> grid;
    for (int a : c) {
      pos[a] = corner_position(i, j, k, a);
      grid[a] = Eigen::Vector3i(i + (a & 1), j + ((a >> 1) & 1), k + ((a >> 2) & 1));
    }
    Vec3 cin = Vec3::Zero(), cout = Vec3::Zero();
    for (int a = 0; a < n_in; ++a) cin += pos[in[a]] / n_in;
    for (int a = 0; a < n_out; ++a) cout += pos[out[a]] / n_out;
    auto vert = [&](int a, int b) {
      return edge_vertex(gid[a], gid[b], grid[a], grid[b], val[a], val[b]);
    };
    if (n_in == 1 || n_out == 1) {
      const int apex = n_in == 1 ? in[0] : out[0];
      const auto& others = n_in == 1 ? out : in;
      const std::array<std::int32_t, 3> tri{vert(apex, others[0]), vert(apex, others[1]),
                                            vert(apex, others[2])};
      emit(tri, cout - cin);
    } else {  // 2 + 2: a quad through the four crossed edges, in cyclic order
      const std::array<std::int32_t, 4> quad{vert(in[0], out[0]), vert(in[0], out[1]),
                                             vert(in[1], out[1]), vert(in[1], out[0])};
      emit(quad, cout - cin);
    }
  }

  const PaddedView& view_;
  double iso_;
  TriMesh mesh_;
  std::unordered_map<std::uint64_t, std::int32_t> edges_;
};

}  // namespace

TriMesh extract_isosurface(const Volume& volume, double iso, const IsosurfaceOptions& options) {
  if (volume.nx < 1 || volume.ny < 1 || volume.nz < 1 ||
      volume.values.size() != std::size_t(volume.nx) * volume.ny * volume.nz)
    throw Error(fmt::format("volume {}x{}x{} has {} samples", volume.nx, volume.ny, volume.nz,
                            volume.values.size()));
  if (!std::isfinite(iso)) throw Error("iso value must be finite");
  if ((double(volume.nx) + 2) * (double(volume.ny) + 2) * (double(volume.nz) + 2) >= 4294967296.0)
    throw Error(fmt::format("volume {}x{}x{} is too large for isosurfacing (max 2^32 samples)",
                            volume.nx, volume.ny, volume.nz));
  const float lowest =
      volume.values.empty() ? 0.0f : *std::min_element(volume.values.begin(), volume.values.end());
  const PaddedView view{volume, options.close_at_border ? 1 : 0,
                        std::min(lowest, static_cast<float>(iso)) - 1.0f};
  TriMesh m = TetMarcher(view, iso).run();
  if (options.largest_component_only && !m.triangles.empty()) m = keep_largest_component(m);
  return m;
}

TriMesh keep_largest_component(const TriMesh& mesh) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::int32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Tri& t : mesh.triangles) {
    parent[find(t[1])] = find(t[0]);
    parent[find(t[2])] = find(t[0]);
  }
  std::vector<std::size_t> count(nv, 0);
  for (const Tri& t : mesh.triangles) ++count[find(t[0])];
  const auto best =
      static_cast<std::int32_t>(std::max_element(count.begin(), count.end()) - count.begin());
  TriMesh out;
  std::vector<std::int32_t> remap(nv, -1);
  for (const Tri& t : mesh.triangles) {
    if (find(t[0]) != best) continue;
    Tri n;
    for (int c = 0; c < 3; ++c) {
      if (remap[t[c]] < 0) {
        remap[t[c]] = static_cast<std::int32_t>(out.positions.size());
        out.positions.push_back(mesh.positions[t[c]]);
      }
      n[c] = remap[t[c]];
    }
    out.triangles.push_back(n);
  }
  std::vector<std::size_t> kept(out.positions.size());
  for (std::size_t v = 0; v < nv; ++v)
    if (remap[v] >= 0) kept[remap[v]] = v;
  if (mesh.normals.size() == nv)
    for (std::size_t v : kept) out.normals.push_back(mesh.normals[v]);
  for (const auto& [name, values] : mesh.properties) {
    std::vector<double> p;
    p.reserve(kept.size());
    for (std::size_t v : kept) p.push_back(values[v]);
    out.properties[name] = std::move(p);
  }
  return out;
}

std::vector<double> distance_to_surface(const TriMesh& from, const TriMesh& to) {
  if (to.triangles.empty()) throw Error("distance_to_surface: the target surface has no triangles");
  const MeshIndex index(to);
  std::vector<double> d(from.num_vertices());
  for (std::size_t v = 0; v < d.size(); ++v)
    d[v] = std::sqrt(index.closest_point(from.positions[v]).distance2);
  return d;
}

std::vector<double> stiffness_from_distance(const std::vector<double>& distance_mm, double k_min,
                                            double k_max, double far_quantile) {
  if (!(k_min > 0 && k_max >= k_min) || !(far_quantile > 0 && far_quantile <= 1))
    throw Error(
        fmt::format("stiffness range must satisfy 0 < k_min <= k_max N/mm and the quantile be in "
                    "(0, 1], got {} {} {}",
                    k_min, k_max, far_quantile));
  std::vector<double> k(distance_mm.size(), k_max);
  if (distance_mm.empty()) return k;
  std::vector<double> sorted = distance_mm;
  const auto q = static_cast<std::size_t>(std::floor(far_quantile * double(sorted.size() - 1)));
  std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
  const double d_far = sorted[q];
  if (!(d_far > 0)) return k;
  const double d_ref = k_min / k_max * d_far;
  for (std::size_t v = 0; v < k.size(); ++v) {
    const double d = distance_mm[v];
    k[v] = d <= d_ref ? k_max : std::clamp(k_max * d_ref / d, k_min, k_max);
  }
  return k;
}

HeadModel head_from_volume(const Volume& volume, const HeadModelOptions& o) {
  HeadModel h;
  TriMesh skin = extract_isosurface(volume, o.skin_iso);
  if (skin.triangles.empty())
    throw Error(fmt::format("the skin isosurface {} is empty", o.skin_iso));
  {
    MeshAdjacency adj = build_adjacency(skin);
    h.skin_components = analyze_topology(skin, adj).components;
  }
  skin = keep_largest_component(skin);
  const TriMesh bone = extract_isosurface(volume, o.bone_iso);
  if (bone.triangles.empty())
    throw Error(fmt::format("the bone isosurface {} is empty", o.bone_iso));
  h.bone_triangles = bone.num_triangles();
  std::vector<double> d = distance_to_surface(skin, bone);
  std::vector<double> k = stiffness_from_distance(d, o.k_min, o.k_max, o.far_quantile);
  {
    std::vector<double> sorted = d;
    const auto q = static_cast<std::size_t>(std::floor(o.far_quantile * double(sorted.size() - 1)));
    std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
    h.distance_far_mm = sorted[q];
  }
  skin.set_property("bone_distance", std::move(d));
  skin.set_property("stiffness", std::move(k));
  h.mesh = std::move(skin);
  return h;
}

double fit_head(HeadModel& head, double fit_mm) {
  TriMesh& m = head.mesh;
  const Box3 b = m.bbox();
  const double side = b.size().maxCoeff();
  const double scale = fit_mm > 0 && side > 0 ? fit_mm / side : 1.0;
  m.transform(scale, fit_mm > 0 ? b.min : Vec3::Zero());
  auto d = m.property("bone_distance");
  for (double& v : d) v *= scale;  // distances in the units of the written mesh
  m.set_property("bone_distance", std::move(d));
  return scale;
}

std::string head_summary_text(const HeadModel& head, const HeadModelOptions& o, double scale) {
  const TriMesh& m = head.mesh;
  const auto& k = m.property("stiffness");
  const auto [klo, khi] = std::minmax_element(k.begin(), k.end());
  const Vec3 s = m.bbox().size();
  return fmt::format(
      "skin        iso {}: {} components, kept the largest: {} triangles, {} vertices\n"
      "bone        iso {}: {} triangles\n"
      "stiffness   {:.3f} .. {:.3f} N/mm, inverse to the skin-to-bone distance (k_max up to {:.1f} "
      "mm, k_min from {:.1f} mm)\n"
      "scaled      x{:.4g} into {:.1f} x {:.1f} x {:.1f} mm\n",
      o.skin_iso, head.skin_components, m.num_triangles(), m.num_vertices(), o.bone_iso,
      head.bone_triangles, *klo, *khi, o.k_min / o.k_max * head.distance_far_mm,
      head.distance_far_mm, scale, s.x(), s.y(), s.z());
}

}  // namespace inhap
