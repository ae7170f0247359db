// Data sets of the TCA-MESH user study (thesis sec. 5.4, Table 5.1, fig. 5.8-5.9): 25
// shape-stiffness models M0..M24 embedded in a 5 x 5 array on one flat surface, plus an
// AFM-like "protein-on-mica" height/stiffness map for servo timing (fig. 5.3a).
//
// Units: positions and heights mm, stiffness N/mm, forces N.
//
// Model numbering follows Table 5.1: M = 5 * H + K with shape H0..H4 (flat, smooth bump, bump
// with sharp edges, smooth hole, hole with sharp edges) and stiffness K0..K4 (constant, softer
// centre smooth/sharp, harder centre smooth/sharp). The chosen numbers, and why they make CBA
// misjudge exactly the 12 models the thesis predicts, are in docs/tca-experiment.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::rendering {

inline constexpr int kNumModels = 25;
inline constexpr int kGridCells = 5;  ///< the array is kGridCells x kGridCells

enum class ShapeClass : int { kFlat = 0, kBump = 1, kHole = 2 };
enum class StiffnessClass : int { kSame = 0, kHarder = 1, kSofter = 2 };

const char* to_string(ShapeClass c);
const char* to_string(StiffnessClass c);

/// Shape index H (0..4) and stiffness index K (0..4) of model M (Table 5.1).
inline int shape_index(int model) {
  return model / 5;
}
inline int stiffness_index(int model) {
  return model % 5;
}
/// What a correct participant answers for model M.
ShapeClass true_shape_class(int model);
StiffnessClass true_stiffness_class(int model);

/// Numbers of the 25 models (defaults documented in docs/tca-experiment.md).
struct DatasetParams {
  int cells = kGridCells;        ///< cells per side
  double cell_mm = 28.0;         ///< cell size, mm (the surface is cells * cell_mm wide)
  double spacing_mm = 1.0;       ///< grid spacing, mm (141 x 141 samples -> 39,200 triangles)
  double height_mm = 1.2;        ///< bump height = hole depth, mm
  double shape_radius_mm = 8.0;  ///< outer radius of bumps and holes, mm
  double sharp_top_radius_mm =
      6.5;                   ///< H2/H4: flat top (bottom) radius; a straight wall to shape_radius
  double k_surround = 0.25;  ///< stiffness of the flat surface and every model's surround, N/mm
  double k_soft = 0.12;      ///< K1/K2 centre stiffness, N/mm
  double k_hard = 1.0;       ///< K3/K4 centre stiffness, N/mm
  double smooth_stiffness_radius_mm = 6.0;  ///< K1/K3: raised-cosine radius, mm
  double sharp_stiffness_radius_mm = 4.0;   ///< K2/K4: radius of the uniform centre disc, mm
};

/// Height (mm, relative to the flat surface) of model M at distance r (mm) from its centre.
double model_height(const DatasetParams& p, int model, double r);
/// Stiffness (N/mm) of model M at distance r (mm) from its centre.
double model_stiffness(const DatasetParams& p, int model, double r);

/// Which model sits in which cell. Cell c = row * cells + col, its centre at
/// ((col + 0.5) * cell_mm, (row + 0.5) * cell_mm).
struct Layout {
  std::array<int, kNumModels> model_at_cell{};
  /// Inverse map: the cell holding model M.
  int cell_of(int model) const;
};
/// M_c in cell c (the layout of Table 5.1 read row by row).
Layout identity_layout();
/// A uniformly random permutation (Fisher-Yates with inhap::Rng): same seed, same layout.
Layout shuffled_layout(std::uint64_t seed);

/// The 5 x 5 surface for one layout, with ground truth for tests and metrics.
class StudySurface {
 public:
  StudySurface(const DatasetParams& params, const Layout& layout);

  const DatasetParams& params() const { return params_; }
  const Layout& layout() const { return layout_; }
  /// The triangle mesh (grid_to_mesh of the sampled heights) with a `stiffness` property.
  TriMesh mesh() const;
  int samples_per_side() const { return n_; }

  Vec2 cell_centre(int cell) const;
  /// Cell containing (x, y), -1 outside the surface.
  int cell_at(double x, double y) const;
  /// Model under (x, y), -1 outside.
  int model_at(double x, double y) const;
  /// Analytic height / stiffness (the functions the grid samples), mm and N/mm.
  double analytic_height(double x, double y) const;
  double analytic_stiffness(double x, double y) const;
  /// Height of the rendered mesh itself at (x, y): linear interpolation on the same triangles
  /// grid_to_mesh builds (ground truth for distortion metrics), mm. Clamped to the surface.
  double mesh_height(double x, double y) const;
  double mesh_stiffness(double x, double y) const;

 private:
  double interpolate(const std::vector<double>& v, double x, double y) const;
  DatasetParams params_;
  Layout layout_;
  int n_ = 0;                               // samples per side
  std::vector<double> height_, stiffness_;  // n_ x n_, row-major (y * n_ + x)
};

/// Perception parameters shared by the renderer-independent design check below and the
/// virtual participant (defaults and sources in docs/tca-experiment.md).
struct ShapePerception {
  double centre_half_mm = 2.0;      ///< centre window |u| <= this along a stroke through the centre
  double surround_inner_mm = 10.0;  ///< surround windows inner_mm <= |u| <= outer_mm
  double surround_outer_mm = 13.0;
  /// Centre-minus-surround height difference noticed, mm: the slope detection threshold 0.09
  /// (Cheon et al. 2008, the thesis' [16]) over the 6 mm flank between the centre window and a
  /// feature's rim (0.09 x 6 mm = 0.54 mm).
  double threshold_mm = 0.54;
};
/// bump if contrast > threshold, hole if < -threshold, else flat.
ShapeClass classify_height_contrast(double contrast_mm, double threshold_mm);

/// Renderer-independent prediction of the centre-minus-surround HIP height (mm) felt along a
/// straight stroke through the centre of model M, for an ideal force-constant user (normal
/// force `force_n` exactly constant) and a 1-D vertical version of the algorithm: CBA puts the
/// HIP at h - F/k; TCA applies eqs. 5.3-5.4 and 5.11-5.13 (restoration slope a_s) with the
/// HIP at h + s - F/k. `step_mm` is the lateral travel per servo tick.
double predicted_contrast(const DatasetParams& p, int model, double force_n, Algorithm algorithm,
                          const ShapePerception& perception, double a_s = 0.05,
                          double step_mm = 0.04);

/// The 12 models the thesis expects CBA to misjudge (sec. 5.4.1, fig. 5.11).
std::vector<int> thesis_cba_confusions();

/// AFM-like "protein-on-mica" surface for servo timing (fig. 5.3a): an n x n grid over
/// size_mm, flat stiff mica (1.0 N/mm), raised membrane patches (0.6 N/mm) with soft
/// lower halos (0.15 N/mm); n = 257 gives 131,072 triangles.
TriMesh afm_like_surface(std::uint64_t seed, int n = 257, double size_mm = 100.0);

}  // namespace inhap::rendering
