// The three real data sets of thesis sec. 5.3 (fig. 5.3, 5.7), loaded as the thesis did:
// the AFM "protein-on-mica" topography (256 x 256 cells -> 131,072 triangles) with a halo
// stiffness map derived from the topography, the Stanford bunny with its per-vertex scan
// confidence mapped to stiffness, and the VTK CT head's skin (simplified to about 57,608
// triangles with CGAL) with stiffness from the skin-to-bone distance. Each model is scaled into
// a 100 mm cube, its stiffness spans up to 1.0 N/mm, and a stated floor keeps it renderable.
// Each data set comes with strokes through the regions the thesis marks (points A-D of fig. 5.7).
// Derivations and numbers: docs/real-data.md.
//
// Units: positions mm, stiffness N/mm, forces N.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::rendering {

struct RealDataOptions {
  double cube_mm = 100.0;  ///< each model is scaled uniformly to fit this cube, mm
  double k_max = 1.0;      ///< maximum stiffness, N/mm
  /// Rendering floor, N/mm: data that maps below it (confidence 0) is rendered this stiff
  /// (1 N then sinks at most 1 / k_floor = 5 mm).
  double k_floor = 0.2;
  // AFM (docs/real-data.md, "AFM halo map").
  int afm_cells = 256;  ///< cells per side (2 * cells^2 triangles)
  double afm_height_mm =
      1.0;  ///< height of the tallest features after scaling, mm (docs/real-data.md)
  double afm_feature_level = 0.3;  ///< features: levelled height above this fraction of the range
  double afm_k_feature = 0.6;      ///< stiffness of the raised features (membrane), N/mm
  double afm_k_halo = 0.25;        ///< stiffness at the feature rim, rising to k_max, N/mm
  double afm_halo_mm = 4.0;        ///< width of the soft halo around each feature, mm
  // CT head.
  std::size_t head_triangles = 57608;  ///< target of the CGAL simplification
  double head_k_min = 0.4;             ///< stiffness far from the bone, N/mm (thesis: 0.4-1.0)
};

/// A point the thesis marks on a stroke (fig. 5.7: A, B on the AFM, C on the bunny, D on the
/// head) as its distance along the stroke, mm.
struct MarkedPoint {
  std::string label;
  double along_mm = 0;
  std::string what;
};

/// A straight stroke in the (x, y) plane; the hand descends along -z onto the model.
struct DataStroke {
  std::string name;
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();  ///< mm
  std::vector<MarkedPoint> marks;
};

struct RealDataset {
  std::string name;            ///< "afm", "bunny", "ct-head"
  std::string file;            ///< the file it was read from
  TriMesh mesh;                ///< scaled into the cube, with `stiffness` (N/mm)
  double scale = 1;            ///< model mm per file unit
  std::string stiffness_from;  ///< one line: how stiffness was derived
  std::vector<DataStroke> strokes;
};

/// WSxM .top topography: plane-levelled, bilinearly resampled to (afm_cells + 1)^2 samples over
/// the cube's side, heights scaled to afm_height_mm; halo stiffness map (docs/real-data.md).
RealDataset load_afm(const std::string& top_path, const RealDataOptions& options = {});
/// Stanford bunny PLY with a `confidence` vertex property: metres -> mm, y-up -> z-up, scaled
/// into the cube; k = max(k_floor, k_max * confidence / max confidence).
RealDataset load_bunny(const std::string& ply_path, const RealDataOptions& options = {});
/// CT head NRRD: skin and bone isosurfaces (head_from_volume), the skin simplified to
/// head_triangles, turned face up (+z), scaled into the cube; k from the skin-bone distance in
/// [head_k_min, k_max].
RealDataset load_head(const std::string& nhdr_path, const RealDataOptions& options = {});

/// The three data sets from DIR/afm-topography/sample_0.top, DIR/bunny/bun_zipper.ply and
/// DIR/headsq/quarter.nhdr, in that order. Throws Error naming a missing file.
std::vector<RealDataset> load_real_datasets(const std::string& dir,
                                            const RealDataOptions& options = {});

/// Edge-collapse simplification (CGAL Surface_mesh_simplification, Lindstrom-Turk placement)
/// of a manifold triangle mesh down to at most `target_triangles`; every vertex property is
/// carried over by barycentric interpolation at the closest point of the input. Throws Error
/// for a non-manifold input.
TriMesh simplify_mesh(const TriMesh& mesh, std::size_t target_triangles);

}  // namespace inhap::rendering
