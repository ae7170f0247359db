// Taubin lambda|mu smoothing; see include/inhap/surface/mesh_ops.hpp.
#include <algorithm>
#include <vector>

#include "inhap/surface/mesh_ops.hpp"

namespace inhap {

namespace {

/// Umbrella neighbours per vertex (CSR); boundary vertices get none (they stay where they are).
struct Neighbours {
  std::vector<std::int32_t> offsets, ids;
};

Neighbours umbrella(const TriMesh& mesh) {
  const std::size_t nv = mesh.positions.size();
  // Directed edge counts: an undirected edge seen once is a boundary edge.
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const Tri& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      std::int32_t a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::int32_t, std::int32_t>> unique;
  std::vector<char> boundary_edge;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    unique.push_back(edges[i]);
    boundary_edge.push_back(j - i == 1);
    i = j;
  }
  std::vector<char> on_boundary(nv, 0);
  for (std::size_t e = 0; e < unique.size(); ++e)
    if (boundary_edge[e]) on_boundary[unique[e].first] = on_boundary[unique[e].second] = 1;
  std::vector<std::vector<std::int32_t>> adj(nv);
  for (std::size_t e = 0; e < unique.size(); ++e) {
    auto [a, b] = unique[e];
    if (!on_boundary[a]) adj[a].push_back(b);
    if (!on_boundary[b]) adj[b].push_back(a);
  }
  Neighbours n;
  n.offsets.reserve(nv + 1);
  n.offsets.push_back(0);
  for (const auto& a : adj) {
    n.ids.insert(n.ids.end(), a.begin(), a.end());
    n.offsets.push_back(static_cast<std::int32_t>(n.ids.size()));
  }
  return n;
}

void laplacian_step(std::vector<Vec3>& p, const Neighbours& n, double factor,
                    std::vector<Vec3>& scratch) {
  scratch = p;
  for (std::size_t v = 0; v < p.size(); ++v) {
    const std::int32_t b = n.offsets[v], e = n.offsets[v + 1];
    if (e == b) continue;
    Vec3 mean = Vec3::Zero();
    for (std::int32_t k = b; k < e; ++k) mean += scratch[static_cast<std::size_t>(n.ids[k])];
    mean /= static_cast<double>(e - b);
    p[v] = scratch[v] + factor * (mean - scratch[v]);
  }
}

}  // namespace

void taubin_smooth(TriMesh& mesh, std::size_t iterations, double lambda, double mu) {
  if (iterations == 0 || mesh.triangles.empty()) return;
  const Neighbours n = umbrella(mesh);
  std::vector<Vec3> scratch;
  for (std::size_t it = 0; it < iterations; ++it) {
    laplacian_step(mesh.positions, n, lambda, scratch);
    laplacian_step(mesh.positions, n, mu, scratch);
  }
  mesh.compute_normals();
}

}  // namespace inhap
