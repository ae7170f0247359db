// Comparison of two surfaces (thesis sec. 3.3.2, as the Metro tool does): optional rigid ICP
// alignment (point-to-plane), cropping to a common region, one-sided and symmetric Hausdorff,
// mean and RMS distances from dense surface samples, and per-vertex error for colouring.
// Units: mm.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// Points on a mesh: every vertex plus area-uniform random points on the faces (seeded).
struct SurfaceSamples {
  std::vector<Vec3> points;
  std::vector<double> weights;  ///< area represented by each sample, mm^2 (vertices: 0)
  std::vector<Vec3> normals;    ///< unit normal: the vertex normal, or the face's normal
};
/// About `density` face samples per mm^2 (at least one per face) plus the vertices.
SurfaceSamples sample_surface(const TriMesh& mesh, double density, std::uint64_t seed);

/// Rigid transform x -> R x + t.
struct RigidTransform {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  Vec3 apply(const Vec3& x) const { return R * x + t; }
};

struct IcpOptions {
  std::size_t max_iterations = 60;
  std::size_t max_samples = 6000;  ///< points of the moving mesh used (evenly strided)
  double reject_factor = 3.0;      ///< pairs farther than this times the median are ignored
  double tolerance = 1e-6;         ///< stop when the update moves points less than this, mm
};
struct IcpResult {
  RigidTransform transform;  ///< maps the moving mesh onto the fixed one
  std::size_t iterations = 0;
  double rms_before = 0, rms_after = 0;  ///< point-to-surface RMS of the used pairs, mm
};
/// Point-to-plane ICP (Chen & Medioni): moves `moving` onto `fixed`; each iteration solves the
/// linearised 6x6 least-squares problem over the closest-point pairs.
IcpResult icp_point_to_plane(const TriMesh& moving, const TriMesh& fixed,
                             const IcpOptions& options = {});

/// Which surfaces' samples the crops (`region`, `crop_distance`, `exclude_boundary`,
/// `normal_overlap`) apply to. Cropping both sides of a partial reconstruction `a` against a
/// complete reference `b` hides errors: a's samples far from the tapped region (a sheet that
/// bridges an untapped hollow) are never scored, so a -> b cannot exceed the crop radius. With a
/// complete reference, crop only the reference (kB): every sample of the reconstruction counts
/// and only the reference is limited to the tapped part.
enum class CropSides { kBoth, kA, kB };
std::string_view to_string(CropSides sides);
/// "both", "a", "b"; throws Error otherwise.
CropSides crop_sides_from_string(std::string_view text);

struct CompareOptions {
  bool icp = false;  ///< align a onto b first (a is moved)
  IcpOptions icp_options;
  double density = 4.0;  ///< face samples per mm^2 on each surface
  std::uint64_t seed = 1;
  /// Common region: when `region` is non-empty, only samples within `region_radius` of one of
  /// its points count (e.g. the tapped contact points: the surface that was sampled).
  std::vector<Vec3> region;
  double region_radius = 0;
  /// Also drop samples farther than this from the other surface (0: keep all), mm.
  double crop_distance = 0;
  /// Overlap only: drop samples whose closest point on the other surface lies on that
  /// surface's boundary (its open rim), i.e. where the other surface does not continue. This
  /// is the common region of a partial reconstruction and a complete reference without any
  /// radius to tune (used with `region` to leave out far parts such as an unsampled bottom).
  bool exclude_boundary = false;
  /// With exclude_boundary: also drop samples whose closest point lies within this distance of
  /// the rim (mm): near a rim that curls, the closest point of an unsampled far part can fall
  /// just inside the surface instead of exactly on its edge.
  double rim_margin = 0;
  /// Overlap only: drop samples whose normal line (through the sample along its surface
  /// normal, both ways) does not meet the other surface, i.e. where the other surface does not
  /// lie opposite the sample. With a partial reconstruction of the top of an object this drops
  /// the reference's side walls below the sampled rim, whose closest point on the
  /// reconstruction need not lie on its rim (e.g. a groove bottom just inside a rim that curls
  /// up); a sample under a bridging or displaced part of the other surface still counts.
  bool normal_overlap = false;
  CropSides crop_sides = CropSides::kBoth;
};

struct OneSided {
  double max = 0, mean = 0, rms = 0;  ///< over the kept samples, area-weighted mean/RMS, mm
  std::size_t samples = 0;            ///< kept samples
  Vec3 max_at = Vec3::Zero();         ///< the sample (on the "from" surface) where max occurs
};

struct CompareResult {
  OneSided a_to_b, b_to_a;
  double hausdorff = 0;                ///< max of the two one-sided maxima, mm
  double mean = 0;                     ///< mean of the two one-sided means, mm
  double rms = 0;                      ///< sqrt of the mean of the two one-sided mean squares, mm
  RigidTransform transform;            ///< applied to a (identity without ICP)
  std::vector<double> a_vertex_error;  ///< distance of each vertex of (aligned) a to b, mm
  std::vector<double> b_vertex_error;  ///< distance of each vertex of b to (aligned) a, mm
};

/// Throws Error when a mesh has no triangles or no sample survives the cropping.
CompareResult compare_surfaces(const TriMesh& a, const TriMesh& b,
                               const CompareOptions& options = {});

/// The "auto" rule of `inhap shape compare --crop-sides`: when exactly one of the meshes is
/// closed (watertight) it is the complete reference and only it is cropped (kA or kB; the other,
/// partial one is scored whole, so its stray parts cannot hide); otherwise kBoth.
CropSides auto_crop_sides(const TriMesh& a, const TriMesh& b);

/// Which sides `options` actually crops: none when it sets no crop (no region, crop distance,
/// boundary exclusion or normal overlap), else as its crop_sides says.
struct CroppedSides {
  bool a = false, b = false;
};
CroppedSides cropped_sides(const CompareOptions& options);

}  // namespace inhap
