// Triangle mesh with named per-vertex scalar properties. Units: positions in mm; property units
// are the property's own (`stiffness` is N/mm, `confidence` has none).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {

using Tri = std::array<std::int32_t, 3>;  ///< vertex indices, counter-clockwise seen from outside

struct TriMesh {
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
  /// Unit vertex normals (angle-weighted); empty until compute_normals() or a reader fills them.
  std::vector<Vec3> normals;
  /// Named per-vertex scalars, each of positions.size() values. Ordered: deterministic output.
  std::map<std::string, std::vector<double>> properties;

  std::size_t num_vertices() const { return positions.size(); }
  std::size_t num_triangles() const { return triangles.size(); }

  /// Angle-weighted vertex normals (Thürmer & Wüthrich). Isolated vertices get (0,0,1).
  void compute_normals();
  /// Unit face normal (zero for a degenerate triangle).
  Vec3 face_normal(std::size_t f) const;
  double face_area(std::size_t f) const;

  bool has_property(const std::string& name) const { return properties.count(name) != 0; }
  /// Throws Error when missing.
  const std::vector<double>& property(const std::string& name) const;
  /// Adds or replaces; throws Error when the size differs from num_vertices().
  void set_property(const std::string& name, std::vector<double> values);

  Box3 bbox() const;

  /// Checks indices in range, finite positions/properties, no triangle repeating a vertex,
  /// consistent property sizes. Throws Error prefixed with `source`.
  void validate(const std::string& source) const;

  /// Appends another mesh (indices shifted). Properties missing on one side are filled with
  /// `fill` (NaN by default would poison renderers, so callers choose).
  void append(const TriMesh& other, double fill = 0.0);
  /// Applies p -> scale * (p - origin); normals unchanged.
  void transform(double scale, const Vec3& origin);
};

/// Connectivity needed by local searches on the surface (renderer's graph search, topology
/// reports). Built once per mesh; immutable afterwards.
struct MeshAdjacency {
  /// vertex -> incident faces, CSR: faces of v are vf_faces[vf_offsets[v] .. vf_offsets[v+1]).
  std::vector<std::int32_t> vf_offsets, vf_faces;
  /// face f, edge e (from vertex e to vertex (e+1)%3): neighbouring face across it, -1 on a
  /// boundary, -2 on a non-manifold edge (shared by more than two faces).
  std::vector<std::array<std::int32_t, 3>> face_neighbors;
  /// Undirected edges (a < b) with the number of incident faces.
  struct Edge {
    std::int32_t a, b, faces;
  };
  std::vector<Edge> edges;

  std::span<const std::int32_t> faces_of_vertex(std::int32_t v) const {
    return {vf_faces.data() + vf_offsets[v], vf_faces.data() + vf_offsets[v + 1]};
  }
};

MeshAdjacency build_adjacency(const TriMesh& mesh);

/// Topology summary for `inhap mesh info`.
struct MeshTopology {
  std::size_t edges = 0, boundary_edges = 0, nonmanifold_edges = 0;
  std::size_t nonmanifold_vertices = 0;  ///< vertices whose fan is not a single disk/half-disk
  std::size_t boundary_loops = 0;
  std::size_t components = 0;          ///< connected components of faces
  std::size_t inconsistent_edges = 0;  ///< interior edges whose faces disagree on orientation
  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool watertight() const { return manifold() && boundary_edges == 0; }
  bool oriented() const { return inconsistent_edges == 0; }
};

MeshTopology analyze_topology(const TriMesh& mesh, const MeshAdjacency& adj);

}  // namespace inhap
