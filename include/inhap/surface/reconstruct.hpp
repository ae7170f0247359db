// Surface reconstruction from tapped contact points (thesis sec. 3.3.1): k-NN outlier removal,
// local quadric (jet) projection, alpha shape, manifold repair, Taubin smoothing and sqrt(3)
// subdivision. Units: mm.
//
// Two ways to turn the alpha shape into the surface:
//  - Solid (the thesis): the boundary of the alpha solid of the points. Right for objects
//    sampled all around; a partial sampling (the top of an object resting on a table) gets
//    closed by large "bridging" facets, and a nearly flat patch needs a huge alpha for one
//    component, which fills its concavities (the thesis' ridged silicone, 4.9 mm).
//  - Shell (default): every point gets an inner twin at depth d along its inward normal
//    (PCA normal oriented by the contact force direction when known, else by the solid's
//    boundary), the alpha shape of points + twins is a thin closed shell whose outer side is
//    the sampled surface: alpha stays at the scale of the sampling, concavities survive, and
//    nothing is invented where no point was sampled. The faces touching a twin are dropped;
//    the result is an open (or, for an all-round sampling, closed) oriented 2-manifold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

enum class SurfaceMode { kSolid, kShell };

struct ReconstructOptions {
  SurfaceMode mode = SurfaceMode::kShell;
  std::size_t outlier_k = 8;    ///< neighbours for the outlier test (0: no outlier removal)
  double outlier_sigmas = 6.0;  ///< robust z-score above which a point is an outlier
  std::size_t jet_k = 14;       ///< neighbours for the jet fit (0: no smoothing)
  /// With directions: a jet is fitted only to neighbours whose direction is within this of the
  /// point's (deg): the flanks of a sharp crest (80 deg apart on the ridged slab) and the two
  /// sides of a thin part are not averaged.
  double jet_max_angle_deg = 60;
  /// With directions, > 0: where a point's jet moves it more than this x the median move (a
  /// sharp feature in the neighbourhood), refit on the nearer half and keep the smaller move.
  /// 0: off (tried on the lab objects, no better; see docs/shape-modeling.md).
  double jet_feature_factor = 0;
  /// With directions: the final projection fits each vertex's jet only to neighbours on the side
  /// of its nearest point (within jet_max_angle_deg). Off by default (no better on the lab).
  bool sided_final_projection = false;
  double alpha = 0;  ///< alpha radius, mm; 0: automatic (see `patches`)
  /// Shell, automatic alpha: a tap set of a whole object is patchy (head, back, haunches...
  /// tapped apart from each other). true: alpha is the smallest putting every point on the
  /// shell (set by the sparsest local spacing), the shell may have several components, and
  /// every component of at least `min_patch_faces` faces is kept, so no sheet spans a hollow
  /// that was never tapped. false: one connected solid (the thesis' rule), largest piece kept.
  bool patches = true;
  std::size_t min_patch_faces = 12;
  /// Patches: alpha = this x the median 6-NN spacing (0: the smallest alpha putting every
  /// point on the shell, scanned up to a closed manifold of one or more components).
  double patch_alpha_factor = 0;
  /// Shell, patches, automatic alpha, > 0: alpha local to the spacing: a tetrahedron of the
  /// shell is solid when its circumradius is at most this x the mean local spacing of its four
  /// points (each point's mean distance to its 6 nearest neighbours, averaged over it and those
  /// neighbours; a twin has its point's), so the sparsest spot no longer sets one alpha for the
  /// densely sampled creases (a bunny's cheek and ear bases). Needs an even sampling (a
  /// person's taps, blue noise): a uniformly random one has voids that open holes at 1.0 (the
  /// noisy-sphere and V-groove tests), so it is off by default; `inhap eval shape` uses 1.0 on
  /// whole-object tap sets. 0: one alpha for all (above).
  double local_alpha = 0;
  bool local_alpha_scan = false;
  bool local_spacing_max = true;
  /// Shell: drop a face whose normal is more than this from one of its points' normals (a face
  /// across a thin part sampled on both sides, e.g. an ear, joins points facing away from it);
  /// 0 or >= 180: keep every face.
  double max_face_normal_deg = 0;
  double shell_depth = 0;  ///< Shell: twin depth, mm; 0: the median 6-NN spacing
  /// Shell: each twin at most this x the distance, along its inward normal, to the nearest of
  /// its 24 neighbours whose normal is opposite (a thin part sampled on both sides: a deeper
  /// twin lands near the far side and the outer faces there go missing); floored at 0.2 x the
  /// depth. 0: every twin at the full depth.
  double thin_part_depth = 0.4;
  /// Shell, with directions: drop faces two of whose points face each other across air
  /// (faces_each_other with this cosine: a sheet between two separately tapped parts).
  /// Below -1: keep them.
  double air_gap_cos = -0.3;
  std::size_t taubin_iterations = 10;
  double taubin_lambda = 0.5, taubin_mu = -0.53;
  std::size_t subdivisions = 1;  ///< sqrt(3) steps
  /// Finally move every vertex onto the jet of its jet_k nearest (smoothed) points, by at most
  /// half the shell depth: Taubin and sqrt(3) pull a sparse mesh inward on convex parts.
  bool final_projection = true;
  /// Seeded jitter (mm) of the points before the Delaunay step (0: none; CGAL resolves
  /// degenerate, e.g. exactly cospherical, input symbolically and the alpha scan handles it).
  double jitter_mm = 0;
  std::uint64_t seed = 1;
};

struct ReconstructReport {
  std::size_t points_in = 0, outliers = 0, points_used = 0;
  std::vector<char> used;               ///< per input point: 0 = non-finite or outlier
  double alpha = 0;                     ///< alpha radius used, mm
  double shell_depth = 0;               ///< mm (Shell)
  std::size_t solid_components = 0;     ///< of the alpha shape
  std::size_t duplicated_vertices = 0;  ///< by the manifold repair
  std::size_t components_dropped = 0;   ///< surface pieces dropped (not the largest / too small)
  std::size_t components = 0;           ///< surface pieces kept
  std::size_t holes_filled = 0;         ///< Shell: small holes closed (<= 10 edges)
  std::size_t vertices = 0, faces = 0;  ///< of the final mesh
};

/// True when two sampled points with outward directions `da`, `db` face each other across air:
/// the directions are opposed (cosine below `max_cos`) and each points toward the other point
/// (a sheet between a bunny's two ears joins such points). Two sides of a thin part (material
/// between them) point away from each other; neighbours on one surface, or the two flanks of a
/// groove (cosine above `max_cos`), are not opposed.
bool faces_each_other(const Vec3& a, const Vec3& da, const Vec3& b, const Vec3& db, double max_cos);

/// The whole pipeline. `directions` (empty, or one per point) are outward directions known
/// from the measurement (the contact force direction): only their sign is used, to orient the
/// normals. Throws Error when fewer than 4 points remain or they span no volume.
TriMesh reconstruct_surface(std::span<const Vec3> points, std::span<const Vec3> directions,
                            const ReconstructOptions& options = {},
                            ReconstructReport* report = nullptr);
inline TriMesh reconstruct_surface(std::span<const Vec3> points,
                                   const ReconstructOptions& options = {},
                                   ReconstructReport* report = nullptr) {
  return reconstruct_surface(points, {}, options, report);
}

}  // namespace inhap
