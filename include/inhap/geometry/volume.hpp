// Scalar volumes (CT scans): NRRD reader, isosurface extraction by marching tetrahedra, distance
// from one isosurface to another, and the thesis' stiffness map for the CT head (fig. 5.3c:
// stiffness 0.4-1.0 N/mm inversely proportional to the skin-to-bone distance).
//
// Units: positions, spacings and distances mm; stiffness N/mm; sample values are the file's own
// (CT numbers). Voxel (i, j, k) sits at origin + (i * sx, j * sy, k * sz).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

struct Volume {
  int nx = 0, ny = 0, nz = 0;
  Vec3 spacing = Vec3::Ones();  ///< mm per voxel along x, y, z
  Vec3 origin = Vec3::Zero();   ///< mm
  std::vector<float> values;    ///< x fastest: values[(k * ny + j) * nx + i]

  std::size_t index(int i, int j, int k) const { return (std::size_t(k) * ny + j) * nx + i; }
  float at(int i, int j, int k) const { return values[index(i, j, k)]; }
  Vec3 position(int i, int j, int k) const {
    return origin + Vec3(i * spacing.x(), j * spacing.y(), k * spacing.z());
  }
};

/// Reads a NRRD volume: a detached header (.nhdr) or an attached .nrrd. Supports dimension 3,
/// types (un)signed char/short/int, float, double; encoding raw; endian little/big; "spacings"
/// or diagonal "space directions"; "space origin"; "data file" as one file, a printf pattern
/// with min max step ("quarter.%d 1 93 1", one slice per file) or "LIST" followed by file
/// names. A left-handed space (3D-left-handed, LPS with negative x) is stored as given: the
/// caller sees i, j, k as x, y, z. Throws ParseError naming the file and line.
Volume read_nrrd(const std::string& path);

struct IsosurfaceOptions {
  /// Pad the volume with one layer of outside voxels so the surface closes at the volume
  /// boundary (watertight even where the object touches the border).
  bool close_at_border = true;
  /// Keep only the connected component with the most triangles.
  bool largest_component_only = false;
};

/// Isosurface {v = iso} by marching tetrahedra (each voxel cube split into 6 tetrahedra around
/// its main diagonal, a conforming Kuhn triangulation): vertices are welded (one per crossed
/// grid edge), the surface is watertight, and triangles face outward, from v >= iso ("inside")
/// towards v < iso. Vertex normals are computed.
TriMesh extract_isosurface(const Volume& volume, double iso, const IsosurfaceOptions& options = {});

/// Copy of `mesh` restricted to its largest connected component (by triangle count); vertex
/// properties and normals follow the kept vertices.
TriMesh keep_largest_component(const TriMesh& mesh);

/// Distance (mm) from every vertex of `from` to the closest point of the surface `to`.
std::vector<double> distance_to_surface(const TriMesh& from, const TriMesh& to);

/// Stiffness inversely proportional to distance: k(d) = clamp(k_max * d_ref / d, k_min, k_max)
/// with d_ref = (k_min / k_max) * d_far, so k = k_max up to d_ref and k_min from d_far on;
/// d_far is the `far_quantile` of the distances (robust to a few stray far vertices).
std::vector<double> stiffness_from_distance(const std::vector<double>& distance_mm, double k_min,
                                            double k_max, double far_quantile = 0.98);

struct HeadModelOptions {
  double skin_iso = 500;            ///< CT number of the skin surface
  double bone_iso = 1150;           ///< CT number of the bone surface
  double k_min = 0.4, k_max = 1.0;  ///< N/mm
  double far_quantile = 0.98;
};

struct HeadModel {
  TriMesh mesh;  ///< skin (largest component) with `stiffness` and `bone_distance`
  std::size_t skin_components = 0;  ///< components of the raw skin isosurface
  std::size_t bone_triangles = 0;
  double distance_far_mm = 0;  ///< d_far used by the stiffness map
};

/// The thesis' CT head (fig. 5.3c): skin isosurface, distance of each skin vertex to the bone
/// isosurface, stiffness from that distance. Throws Error when an isosurface is empty.
HeadModel head_from_volume(const Volume& volume, const HeadModelOptions& options = {});

/// Scales the head so its largest side is `fit_mm` mm with the box minimum at the origin
/// (`fit_mm` 0: the scanner's mm, unmoved), `bone_distance` with it; returns the scale.
double fit_head(HeadModel& head, double fit_mm);

/// What `mesh from-volume` prints about a head built from `volume` with `options` and scaled by
/// `scale`: skin (components, triangles, vertices), bone triangles, the stiffness range and the
/// distances it was mapped from (mm), the scaled size.
std::string head_summary_text(const HeadModel& head, const HeadModelOptions& options, double scale);

}  // namespace inhap
