// Alpha-shape surface of a point set (thesis sec. 3.3.1, Edelsbrunner & Mücke). Units: mm.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

struct AlphaShapeOptions {
  /// Alpha as a radius in mm (a simplex is kept when its empty circumsphere is smaller).
  /// 0: automatic, the smallest alpha giving one connected solid component with every point
  /// on its boundary or inside (CGAL's find_optimal_alpha(1)).
  double alpha = 0;
  /// Automatic alpha only: from the one-component alpha upwards (steps of `scan_step`,
  /// relative), take the first alpha whose boundary is a closed 2-manifold; this removes the
  /// holes and pinches that surface slivers cause at the bare one-component alpha (and the
  /// degenerate case of exactly cospherical points, where every tetrahedron's circumradius
  /// equals the sphere's up to rounding). Up to `scan_max_factor` times the start.
  bool require_closed_manifold = true;
  /// Automatic alpha: require one connected solid (the thesis, CGAL's find_optimal_alpha(1)).
  /// false: only require every point on the solid (the alpha then follows the sparsest local
  /// spacing, not the gaps between separately sampled patches), and the closed-manifold scan
  /// accepts several components, each a closed 2-manifold.
  bool one_component = true;
  double scan_step = 0.02;
  double scan_max_factor = 3.0;
  /// Empty, or one length per input point (mm): each tetrahedron's circumradius is then divided
  /// by the mean length of its four points, and alpha (given or automatic) is in units of that
  /// length — an alpha local to the point spacing, so a sparse spot does not set the alpha of a
  /// densely sampled crease.
  std::vector<double> point_scale;
};

struct AlphaShapeResult {
  TriMesh mesh;  ///< outward-oriented boundary of the regularized alpha solid
  std::vector<std::int32_t> input_index;  ///< input point of each mesh vertex
  double alpha = 0;  ///< radius used, mm (with point_scale: in units of the points' lengths)
  double alpha_one_component = 0;  ///< automatic mode: the bare one-component alpha, mm
  bool closed_manifold = false;    ///< the boundary is a closed 2-manifold
  std::size_t solid_components = 0;
  std::size_t points_on_surface = 0;  ///< input points that are vertices of `mesh`
};

/// Boundary triangles of the regularized alpha shape, each oriented with its normal pointing
/// out of the solid. The raw boundary may be non-manifold where solids touch at an edge or a
/// vertex; make_manifold() (mesh_ops.hpp) repairs that. Points must not be all coplanar.
AlphaShapeResult alpha_shape(std::span<const Vec3> points, const AlphaShapeOptions& options);

}  // namespace inhap
