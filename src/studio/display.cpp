#include "inhap/studio/display.hpp"

#include <optional>
#include <vector>

#include "inhap/geometry/mesh_index.hpp"

namespace inhap::studio {
namespace {

// Triangles of every grid cell whose four corners exist (vertex index -1: no corner).
TriMesh grid_mesh(int n, const std::vector<std::optional<Vec3>>& nodes,
                  const std::vector<double>* values, const std::string& property) {
  TriMesh m;
  std::vector<int> index(nodes.size(), -1);
  std::vector<double> prop;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i]) continue;
    index[i] = static_cast<int>(m.positions.size());
    m.positions.push_back(*nodes[i]);
    if (values) prop.push_back((*values)[i]);
  }
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const int a = index[r * n + c], b = index[r * n + c + 1], d = index[(r + 1) * n + c],
                e = index[(r + 1) * n + c + 1];
      if (a < 0 || b < 0 || d < 0 || e < 0) continue;
      m.triangles.push_back({a, b, e});
      m.triangles.push_back({a, e, d});
    }
  if (values) m.set_property(property, std::move(prop));
  return m;
}

}  // namespace

TriMesh top_view_mesh(const TriMesh& mesh, const std::string& property, int n,
                      std::size_t max_faces) {
  if (mesh.num_triangles() <= max_faces) return mesh;
  const MeshIndex index(mesh);
  const Box3 b = mesh.bbox();
  const bool has = mesh.has_property(property);
  const std::vector<double>* src = has ? &mesh.property(property) : nullptr;
  std::vector<std::optional<Vec3>> nodes(static_cast<std::size_t>(n * n));
  std::vector<double> values(nodes.size(), 0.0);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = b.min.x() + (b.max.x() - b.min.x()) * c / (n - 1);
      const double y = b.min.y() + (b.max.y() - b.min.y()) * r / (n - 1);
      const auto hit = index.first_hit(Vec3(x, y, b.max.z() + 1), Vec3(x, y, b.min.z() - 1));
      if (!hit) continue;
      const std::size_t i = static_cast<std::size_t>(r * n + c);
      nodes[i] = hit->point;
      if (src) {
        const auto& t = mesh.triangles[static_cast<std::size_t>(hit->triangle)];
        values[i] = hit->bary[0] * (*src)[static_cast<std::size_t>(t[0])] +
                    hit->bary[1] * (*src)[static_cast<std::size_t>(t[1])] +
                    hit->bary[2] * (*src)[static_cast<std::size_t>(t[2])];
      }
    }
  return grid_mesh(n, nodes, src ? &values : nullptr, property);
}

TriMesh top_view_mesh(const lab::Shape& shape, int n) {
  const Box3 b = shape.bounds();
  std::vector<std::optional<Vec3>> nodes(static_cast<std::size_t>(n * n));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = b.min.x() + (b.max.x() - b.min.x()) * c / (n - 1);
      const double y = b.min.y() + (b.max.y() - b.min.y()) * r / (n - 1);
      nodes[static_cast<std::size_t>(r * n + c)] = shape.drop(x, y, 0.0);
    }
  return grid_mesh(n, nodes, nullptr, "");
}

}  // namespace inhap::studio
