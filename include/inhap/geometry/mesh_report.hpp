// What `inhap mesh info|convert|heightmap` compute between reading and writing a mesh: the mesh's
// report (counts, bounding box, properties, topology) as text and JSON, the linear map of a
// property onto stiffness, scaling / centring, and the mesh of a height map. Units: mm, N/mm.
#pragma once

#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// The report of `mesh info` on `mesh` read from `file`: the text it prints.
std::string mesh_info_text(const std::string& file, const TriMesh& mesh);
/// The same as JSON text (keys: file, vertices, faces, edges, bbox_mm, properties, manifold,
/// watertight, oriented, boundary_loops, boundary_edges, components).
std::string mesh_info_json(const std::string& file, const TriMesh& mesh);

/// `values` mapped linearly from their [min, max] onto [lo, hi]; all `hi` when they are all
/// equal (or empty input: empty output).
std::vector<double> map_linear(const std::vector<double>& values, double lo, double hi);

/// Scales the mesh uniformly so its largest bounding-box side is `scale_to` mm (0: no scaling)
/// and, when `center`, moves the box centre to the origin. Error naming `what` for a mesh of zero
/// size that should be scaled.
void scale_and_center(TriMesh& mesh, double scale_to, bool center, const std::string& what);

/// `mesh convert --stiffness-from PROP --k-range KMIN KMAX`: sets the 'stiffness' property to
/// PROP mapped linearly onto [KMIN, KMAX] N/mm (map_linear). `prop` empty: nothing, but a
/// non-empty `k_range` is then an error. Errors name the flags.
void stiffness_from_property(TriMesh& mesh, const std::string& prop,
                             const std::vector<double>& k_range);

/// "wrote OUT: V vertices, F faces, size X x Y x Z mm[, stiffness in [lo, hi] N/mm]\n".
std::string mesh_written_text(const std::string& out, const TriMesh& mesh);

/// One warning line per vertex property the format of `path` could not store.
std::string dropped_properties_text(const std::string& path,
                                    const std::vector<std::string>& dropped);

/// `mesh heightmap`: a height map (and optionally a stiffness map of the same size) to a mesh.
struct HeightmapMeshOptions {
  std::string height;     ///< height map file (PGM, CSV, WSxM; heightmap.hpp)
  std::string stiffness;  ///< stiffness map file, optional
  double spacing_mm = 0, height_scale = 1.0;
  int downsample = 1;                 ///< block size (after levelling and the stiffness mapping)
  std::vector<double> k_range;        ///< map the stiffness map's levels onto [KMIN, KMAX] N/mm
  std::vector<double> k_from_height;  ///< or stiffness from the heights mapped onto [KMIN, KMAX]
  bool level = false;                 ///< subtract the least-squares plane first
};
struct HeightmapMesh {
  TriMesh mesh;
  int width = 0, height = 0;  ///< grid size after downsampling
};
/// "wrote OUT: WxH grid, V vertices, T triangles, size X x Y x Z mm\n".
std::string heightmap_written_text(const std::string& out, const HeightmapMesh& h);
/// Reads the maps and builds the mesh. Throws inhap::Error for both stiffness sources or maps of
/// different sizes; ParseError / IoError for a bad file.
HeightmapMesh heightmap_mesh(const HeightmapMeshOptions& o);

}  // namespace inhap
