#include "inhap/geometry/trimesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "inhap/core/error.hpp"

namespace inhap {

Vec3 TriMesh::face_normal(std::size_t f) const {
  const Tri& t = triangles[f];
  Vec3 n = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
  double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double TriMesh::face_area(std::size_t f) const {
  const Tri& t = triangles[f];
  return 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).norm();
}

void TriMesh::compute_normals() {
  normals.assign(positions.size(), Vec3::Zero());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    Vec3 n = face_normal(f);
    if (n.isZero()) continue;
    const Tri& t = triangles[f];
    for (int c = 0; c < 3; ++c) {
      Vec3 e1 = positions[t[(c + 1) % 3]] - positions[t[c]];
      Vec3 e2 = positions[t[(c + 2) % 3]] - positions[t[c]];
      double l1 = e1.norm(), l2 = e2.norm();
      if (l1 == 0 || l2 == 0) continue;
      double cosang = std::clamp(e1.dot(e2) / (l1 * l2), -1.0, 1.0);
      normals[t[c]] += std::acos(cosang) * n;
    }
  }
  for (auto& n : normals) {
    double len = n.norm();
    n = len > 0 ? Vec3(n / len) : Vec3(0, 0, 1);
  }
}

const std::vector<double>& TriMesh::property(const std::string& name) const {
  auto it = properties.find(name);
  if (it == properties.end()) {
    std::string have;
    for (const auto& [k, v] : properties) have += (have.empty() ? "" : ", ") + k;
    throw Error(fmt::format("mesh has no vertex property '{}' (has: {})", name,
                            have.empty() ? "none" : have));
  }
  return it->second;
}

void TriMesh::set_property(const std::string& name, std::vector<double> values) {
  if (values.size() != positions.size())
    throw Error(fmt::format("vertex property '{}' has {} values, mesh has {} vertices", name,
                            values.size(), positions.size()));
  properties[name] = std::move(values);
}

Box3 TriMesh::bbox() const {
  Box3 b;
  for (const auto& p : positions) b.extend(p);
  return b;
}

void TriMesh::validate(const std::string& source) const {
  const auto nv = static_cast<std::int64_t>(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!positions[i].allFinite())
      throw Error(fmt::format("{}: vertex {}: expected finite coordinates, got ({}, {}, {})",
                              source, i, positions[i].x(), positions[i].y(), positions[i].z()));
  // The size must be finite too: vertices at -1e308 and +1e308 gave a size of inf.
  if (!positions.empty()) {
    Vec3 lo = positions.front(), hi = lo;
    for (const Vec3& p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Vec3 size = hi - lo;
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(size[a]))
        throw Error(
            fmt::format("{}: the vertices span {:g} to {:g} mm along {}: expected a finite size",
                        source, lo[a], hi[a], "xyz"[a]));
  }
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const Tri& t = triangles[f];
    for (int c = 0; c < 3; ++c)
      if (t[c] < 0 || t[c] >= nv)
        throw Error(
            fmt::format("{}: face {}: vertex index {} out of range [0, {})", source, f, t[c], nv));
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Error(
          fmt::format("{}: face {}: repeats a vertex ({}, {}, {})", source, f, t[0], t[1], t[2]));
  }
  if (!normals.empty() && normals.size() != positions.size())
    throw Error(
        fmt::format("{}: {} normals for {} vertices", source, normals.size(), positions.size()));
  for (const auto& [name, v] : properties) {
    if (v.size() != positions.size())
      throw Error(fmt::format("{}: property '{}' has {} values for {} vertices", source, name,
                              v.size(), positions.size()));
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw Error(
            fmt::format("{}: vertex {}: property '{}' is not finite ({})", source, i, name, v[i]));
  }
}

void TriMesh::append(const TriMesh& other, double fill) {
  const auto base = static_cast<std::int32_t>(positions.size());
  const std::size_t n0 = positions.size(), n1 = other.positions.size();
  for (auto& [name, v] : properties)
    if (!other.has_property(name)) v.resize(n0 + n1, fill);
  for (const auto& [name, v] : other.properties) {
    auto& mine = properties[name];
    mine.resize(n0, fill);
    mine.insert(mine.end(), v.begin(), v.end());
  }
  bool keep_normals = (!normals.empty() || n0 == 0) && !other.normals.empty();
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  if (keep_normals)
    normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  else
    normals.clear();
  for (Tri t : other.triangles) {
    for (auto& i : t) i += base;
    triangles.push_back(t);
  }
}

void TriMesh::transform(double scale, const Vec3& origin) {
  for (auto& p : positions) p = scale * (p - origin);
}

// ---------------------------------------------------------------------------------------------
MeshAdjacency build_adjacency(const TriMesh& mesh) {
  MeshAdjacency adj;
  const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
  adj.vf_offsets.assign(nv + 1, 0);
  for (const Tri& t : mesh.triangles)
    for (auto v : t) ++adj.vf_offsets[v + 1];
  std::partial_sum(adj.vf_offsets.begin(), adj.vf_offsets.end(), adj.vf_offsets.begin());
  adj.vf_faces.resize(adj.vf_offsets.back());
  std::vector<std::int32_t> fill(adj.vf_offsets.begin(), adj.vf_offsets.end() - 1);
  for (std::size_t f = 0; f < nf; ++f)
    for (auto v : mesh.triangles[f]) adj.vf_faces[fill[v]++] = static_cast<std::int32_t>(f);

  // Edges: sort half-edges by undirected key.
  struct Half {
    std::uint64_t key;
    std::int32_t face, edge;
  };
  std::vector<Half> halves;
  halves.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int e = 0; e < 3; ++e) {
      auto a = static_cast<std::uint32_t>(mesh.triangles[f][e]);
      auto b = static_cast<std::uint32_t>(mesh.triangles[f][(e + 1) % 3]);
      if (a > b) std::swap(a, b);
      halves.push_back({(std::uint64_t(a) << 32) | b, static_cast<std::int32_t>(f), e});
    }
  std::sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) {
    return x.key < y.key || (x.key == y.key && x.face < y.face);
  });
  adj.face_neighbors.assign(nf, {-1, -1, -1});
  for (std::size_t i = 0; i < halves.size();) {
    std::size_t j = i;
    while (j < halves.size() && halves[j].key == halves[i].key) ++j;
    const auto count = static_cast<std::int32_t>(j - i);
    adj.edges.push_back({static_cast<std::int32_t>(halves[i].key >> 32),
                         static_cast<std::int32_t>(halves[i].key & 0xffffffffu), count});
    if (count == 2) {
      adj.face_neighbors[halves[i].face][halves[i].edge] = halves[i + 1].face;
      adj.face_neighbors[halves[i + 1].face][halves[i + 1].edge] = halves[i].face;
    } else if (count > 2) {
      for (std::size_t k = i; k < j; ++k) adj.face_neighbors[halves[k].face][halves[k].edge] = -2;
    }
    i = j;
  }
  return adj;
}

MeshTopology analyze_topology(const TriMesh& mesh, const MeshAdjacency& adj) {
  MeshTopology topo;
  topo.edges = adj.edges.size();
  std::vector<std::vector<std::int32_t>> boundary_next(mesh.positions.size());
  for (const auto& e : adj.edges) {
    if (e.faces == 1) ++topo.boundary_edges;
    if (e.faces > 2) ++topo.nonmanifold_edges;
  }
  // Orientation: an interior edge is consistent when its two faces traverse it in opposite
  // directions. Boundary half-edges give the boundary graph for loop counting.
  const std::size_t nf = mesh.triangles.size();
  for (std::size_t f = 0; f < nf; ++f)
    for (int e = 0; e < 3; ++e) {
      std::int32_t g = adj.face_neighbors[f][e];
      std::int32_t a = mesh.triangles[f][e], b = mesh.triangles[f][(e + 1) % 3];
      if (g == -1) {
        boundary_next[a].push_back(b);
      } else if (g >= 0 && static_cast<std::size_t>(g) > f) {
        const Tri& t = mesh.triangles[g];
        for (int k = 0; k < 3; ++k)
          if (t[k] == a && t[(k + 1) % 3] == b) ++topo.inconsistent_edges;
      }
    }
  // Boundary loops: connected components of the boundary-edge graph.
  {
    std::vector<std::int32_t> parent(mesh.positions.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::int32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::vector<char> on_boundary(mesh.positions.size(), 0);
    for (std::size_t a = 0; a < boundary_next.size(); ++a)
      for (auto b : boundary_next[a]) {
        on_boundary[a] = on_boundary[b] = 1;
        parent[find(static_cast<std::int32_t>(a))] = find(b);
      }
    for (std::size_t v = 0; v < parent.size(); ++v)
      if (on_boundary[v] && find(static_cast<std::int32_t>(v)) == static_cast<std::int32_t>(v))
        ++topo.boundary_loops;
  }
  // Face components (across manifold and non-manifold edges alike: shared vertices of an edge).
  {
    std::vector<std::int32_t> comp(nf, -1);
    std::vector<std::int32_t> stack;
    for (std::size_t s = 0; s < nf; ++s) {
      if (comp[s] >= 0) continue;
      const auto c = static_cast<std::int32_t>(topo.components++);
      stack.push_back(static_cast<std::int32_t>(s));
      comp[s] = c;
      while (!stack.empty()) {
        auto f = stack.back();
        stack.pop_back();
        for (auto v : mesh.triangles[f])
          for (auto g : adj.faces_of_vertex(v))
            if (comp[g] < 0) {
              comp[g] = c;
              stack.push_back(g);
            }
      }
    }
  }
  // Non-manifold vertices: the faces around v must form one edge-connected fan.
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    auto faces = adj.faces_of_vertex(static_cast<std::int32_t>(v));
    if (faces.size() < 2) continue;
    std::vector<std::int32_t> seen{faces[0]}, stack{faces[0]};
    while (!stack.empty()) {
      auto f = stack.back();
      stack.pop_back();
      for (int e = 0; e < 3; ++e) {
        auto g = adj.face_neighbors[f][e];
        if (g < 0) continue;
        // neighbour must also contain v and the edge must contain v
        const Tri& t = mesh.triangles[f];
        if (t[e] != static_cast<std::int32_t>(v) && t[(e + 1) % 3] != static_cast<std::int32_t>(v))
          continue;
        if (std::find(seen.begin(), seen.end(), g) == seen.end()) {
          seen.push_back(g);
          stack.push_back(g);
        }
      }
    }
    if (seen.size() != faces.size()) ++topo.nonmanifold_vertices;
  }
  return topo;
}

}  // namespace inhap
