// Mesh post-processing for reconstructed surfaces (thesis sec. 3.3.1). Units: mm.
#pragma once

#include <cstddef>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

struct ManifoldReport {
  std::size_t duplicated_vertices = 0;  ///< split to resolve non-manifold vertices and edges
  std::size_t dropped_faces = 0;        ///< degenerate, duplicate or in smaller components
  std::size_t components = 0;           ///< connected components before keeping the largest
  std::size_t kept_components = 0;      ///< connected components of the result
};

/// Makes a triangle soup a consistently oriented 2-manifold: removes degenerate and duplicate
/// faces, splits non-manifold edges/vertices (CGAL orient_polygon_soup), keeps the largest
/// connected component (by area) when `keep_largest` (else every component with at least
/// `min_component_faces` faces), and orients closed meshes outward.
/// Properties are dropped; normals recomputed.
TriMesh make_manifold(const TriMesh& soup, bool keep_largest = true,
                      ManifoldReport* report = nullptr, std::size_t min_component_faces = 0);

/// Closes the small holes of a manifold mesh: every boundary loop with at most `max_edges`
/// edges (and at most `max_fraction` of the vertices on it, so the rim of a small open patch
/// stays open) is triangulated (CGAL triangulate_hole, minimum-area weight). Returns the
/// number of holes filled.
std::size_t fill_small_holes(TriMesh& mesh, std::size_t max_edges, double max_fraction = 0.1);

/// Taubin lambda|mu smoothing (Taubin 1995) with the uniform umbrella Laplacian:
/// each iteration p += lambda * L(p), then p += mu * L(p) (mu < -lambda < 0), which attenuates
/// high frequencies without the shrinkage of plain Laplacian smoothing. Boundary vertices stay
/// fixed: a rim crossing ridges and grooves is a zigzag, and smoothing it along itself (a 1D
/// Laplacian over two neighbours) lowers its peaks and lifts its valleys far more than the
/// interior is changed (up to 3 mm on the lab's ridged slab).
void taubin_smooth(TriMesh& mesh, std::size_t iterations, double lambda = 0.5, double mu = -0.53);

/// sqrt(3) subdivision (Kobbelt 2000), `iterations` times (CGAL Sqrt3_subdivision). Each step
/// triples the faces. The mesh must be a manifold (see make_manifold). Properties dropped.
TriMesh sqrt3_subdivide(const TriMesh& mesh, std::size_t iterations);

}  // namespace inhap
