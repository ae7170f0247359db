// Surface reconstruction from tapped contact points (thesis sec. 3.3.1): k-NN outlier removal,
// local quadric (jet) projection, alpha shape, manifold repair, Taubin smoothing and sqrt(3)
// subdivision. Units: mm.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

struct ReconstructOptions {
  std::size_t outlier_k = 8;    ///< neighbours for the outlier test (0: no outlier removal)
  double outlier_sigmas = 4.0;  ///< robust z-score above which a point is an outlier
  std::size_t jet_k = 18;       ///< neighbours for the jet fit (0: no smoothing)
  double alpha = 0;             ///< alpha radius, mm; 0: automatic (one solid component)
  std::size_t taubin_iterations = 10;
  double taubin_lambda = 0.5, taubin_mu = -0.53;
  std::size_t subdivisions = 1;  ///< sqrt(3) steps
  /// Seeded jitter (mm) of the points before the Delaunay step (0: none; CGAL resolves
  /// degenerate, e.g. exactly cospherical, input symbolically and the alpha scan handles it).
  double jitter_mm = 0;
  std::uint64_t seed = 1;
};

struct ReconstructReport {
  std::size_t points_in = 0, outliers = 0, points_used = 0;
  double alpha = 0;                     ///< alpha radius used, mm
  std::size_t solid_components = 0;     ///< of the alpha shape
  std::size_t duplicated_vertices = 0;  ///< by the manifold repair
  std::size_t components_dropped = 0;   ///< surface pieces other than the largest
  std::size_t vertices = 0, faces = 0;  ///< of the final mesh
};

/// The whole pipeline. Throws Error when fewer than 4 points remain or they span no volume.
TriMesh reconstruct_surface(std::span<const Vec3> points, const ReconstructOptions& options = {},
                            ReconstructReport* report = nullptr);

}  // namespace inhap
