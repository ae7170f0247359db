// What the thesis' force model needs, estimated from a recording that carries only t, p and f:
// the undeformed (probe-centre) surface, its normals, a proxy on it and the friction the sliding
// phases show. For recordings of a real rig (no palpation cycles, no shape mesh, no proxy
// columns) and for the virtual lab at any rate.
//
// Units: positions mm, forces N, time s, stiffness N/mm.
//
// Surface. The push axis a is first the direction of the mean contact force (the outward normal
// of the region pressed, on average, tilted by friction), then the normal of the plane fitted to
// the surface found about it (twice). Around a the samples are binned on a regular grid of the
// plane perpendicular to it (cell_mm); in each cell (with its 8 neighbours) the position along a
// is fitted against the normal force as s = h - b f_n^gamma (a depth-force law d = b f_n^gamma,
// gamma from 0.4 to 1.2 in steps of 0.05, chosen once for the whole recording by the smallest
// residual) using every sample of the block, its slope b shrunk towards the recording's median b
// (a ridge term, `slope_prior_spread`: a block pressed over a narrow force range takes the
// recording's law and only its offset from the data); h, the position at zero force, is the
// undeformed surface there (samples whose force pulls along -a, e.g. a tool's weight left in
// the readings while it hangs in the air, are left out). A last pass takes each sample's normal
// force and depth along the local normal of that surface (on a slope tilted by t the depth along a
// is the normal depth / cos t), so b is in normal depth as the proxy estimator measures it. Cells
// without enough samples or force spread are filled front by front, each with the plane through the
// fitted cells within 3 cells (a curved surface's slope carries on past the data), then the heights
// are smoothed (3 x 3 mean, `smooth_passes`). A sample that presses lies under the undeformed
// surface: where more than 10 % of a cell's pressing samples lie above it (a surface known to
// less than the depth of a light force, e.g. a force-controlled exploration), the cell is raised
// until 90 % are under it (`hold_quantile`), the raise spread to the neighbours and smoothed. The
// surface is a height field over that plane: a triangle mesh whose normals face +a.
//
// Friction. With the surface, a sliding-yield-surface model with an isotropic Coulomb cone at
// every reference point: f_s radius = mu f_N and g_s radius = c f_N (a tangential spring of
// stiffness mu / c N/mm: the pre-sliding displacement grows with the load), at the depth the
// depth-force law gives for f_N. c (mm/N) is chosen from `radii` (then twice the geometric
// midpoints beside the best) by the smallest residual of the tangential force against
// mu f_n (u_t / r) over the recording, u_t the tangential part of q - p of the proxy that c gives
// and r the g_s radius there; mu is the least-squares fit. Then a slip relaxation time tau
// (viscous creep: the excess beyond g_s relaxes in tau, so a probe sliding at speed v leads the
// proxy by the static range plus v tau) from `relaxation_s` at that c, by the same residual, then
// c refined at that tau and tau refined at that c (geometric midpoints beside the best, twice).
#pragma once

#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/types.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::datadriven {

struct EstimateParams {
  double contact_threshold_n = 0.05;  ///< |f| above it = in contact (samples used), N
  double cell_mm = 2.0;               ///< height-field cell, mm
  double margin_mm = 20.0;            ///< the surface extends this far beyond the data, mm
  int min_cell_samples = 8;           ///< samples (3 x 3 cells) needed to fit a cell
  double min_force_spread_n = 0.15;   ///< force range needed to fit a cell, N
  int smooth_passes = 2;              ///< 3 x 3 mean passes over the heights
  /// Weight of the recording's depth law in each cell's fit: the cell's slope b is shrunk towards
  /// the median b as if the cell's f_n^gamma had this relative spread (0: every cell on its own).
  double slope_prior_spread = 1.0;
  /// Where more than (1 - hold_quantile) of a cell's pressing samples lie above the surface, the
  /// surface is raised until that quantile of them is under it (then smoothed; 0: never).
  double hold_quantile = 0.9;
  /// Candidates of the g_s radius per newton of normal load, mm/N.
  std::vector<double> radii{0.05, 0.08, 0.13, 0.2, 0.33, 0.5, 0.8, 1.3, 2.0, 3.2, 5.0, 8.0};
  /// Candidates of the slip relaxation time (viscous creep beyond g_s), s.
  std::vector<double> relaxation_s{0.01, 0.02, 0.05, 0.1, 0.2};
  void validate() const;  ///< throws inhap::Error on out-of-range values
};

/// The undeformed probe-centre surface as a height field over the plane perpendicular to `axis`.
struct SurfaceEstimate {
  Vec3 axis = Vec3::UnitZ();                                           ///< outward push axis (unit)
  Vec3 origin = Vec3::Zero(), e1 = Vec3::UnitX(), e2 = Vec3::UnitY();  ///< plane frame
  double cell_mm = 2.0;
  Grid height;         ///< position along `axis` at cell centres (origin + (i + 0.5) cell e1 + ...)
  double gamma = 1.0;  ///< exponent of the depth-force law d = b f_n^gamma
  double b_median = 0;  ///< median b over the fitted cells (mm / N^gamma)
  std::size_t cells_fitted = 0, cells_filled = 0;
  std::size_t cells_raised = 0;  ///< cells raised to hold the samples pressing there
  double raised_max_mm = 0;      ///< the largest raise (after smoothing), mm

  /// Height (along axis) at plane coordinates (u, v), bilinear, clamped to the grid, mm.
  double height_at(double u, double v) const;
  /// Depth of p below the surface along `axis` (> 0 inside), mm.
  double depth(const Vec3& p) const;
  /// Depth d (mm) at which the recording's depth-force law gives normal force f_n (N).
  double depth_for_force(double f_n) const;
  /// Normal force (N) the depth-force law gives at depth d (mm); 0 for d <= 0.
  double force_at_depth(double d) const;
  /// The surface as a mesh in world coordinates (vertices at cell centres, normals towards +axis).
  TriMesh mesh() const;
};

struct FrictionEstimate {
  double mu = 0;              ///< Coulomb coefficient |f_t| / f_n when sliding
  double radius_per_n = 1.0;  ///< g_s radius per newton of normal load, mm/N
  double tau_s = 0;           ///< slip relaxation time (creep), s; 0: rate-independent
  double rmse_t_n = 0;        ///< residual of the tangential force, N
  double rmse_t0_n = 0;       ///< the tangential force's RMS without friction (mu = 0), N
  std::size_t samples = 0;    ///< samples of the fit
};

/// Everything `model train` estimates for a recording without a proxy.
struct RecordingEstimate {
  SurfaceEstimate surface;
  FrictionEstimate friction;
  friction::SysModel sys;  ///< the Coulomb-cone yield surfaces of `friction`
  TriMesh mesh;            ///< surface.mesh()
  /// Mean force of the samples more than kAirMm above the surface (in the air: it should be
  /// zero; an uncompensated tool weight or a sensor offset shows here), N, and their count.
  Vec3 air_force = Vec3::Zero();
  std::size_t air_samples = 0;
  static constexpr double kAirMm = 5.0;
  /// Samples that press the surface (normal force along the push axis above the contact
  /// threshold), those of them above the estimated surface (the model renders them as free
  /// space), and the 5 % and 95 % quantiles of their normal force, N.
  std::size_t pressing_samples = 0, pressing_above = 0;
  double pressing_fn_p5 = 0, pressing_fn_p95 = 0;
  /// A pressing force spanning less than this (5-95 %) is one force held: N.
  static constexpr double kNarrowForceN = 0.5;
};

/// The surface (see file comment). Throws inhap::Error naming `path` when the recording has too
/// few contact samples to fit a surface.
SurfaceEstimate estimate_surface(const Recording& rec, const EstimateParams& params,
                                 const std::string& path);

/// Yield surfaces with an isotropic Coulomb cone (g_s radius = radius_per_n x f_N, f_s radius =
/// mu f_N) at reference points spread over the surface.
friction::SysModel cone_sys(const SurfaceEstimate& surface, double radius_per_n, double mu,
                            double tau_s = 0.0);

/// Surface, friction and the sys model of a recording.
RecordingEstimate estimate_recording(const Recording& rec, const EstimateParams& params,
                                     const std::string& path);

/// One line on what was estimated: surface cells, depth law, normals' spread, mu and radius_per_n.
std::string estimate_note(const RecordingEstimate& e);

/// A warning when the force in the air (see air_force) averages more than 0.03 N over at least
/// 50 samples, else empty (also when estimate_contact_warning has one: then the surface cannot
/// tell the air from contact).
std::string estimate_warning(const RecordingEstimate& e);

/// A warning when more than 5 % of at least 50 pressing samples lie above the estimated surface
/// (a surface known to less than the depth the recorded force gives), or when their normal force
/// spans less than kNarrowForceN (5-95 %: a force-controlled exploration at one light force,
/// which determines neither the depth-force law nor the surface well), else empty.
std::string estimate_contact_warning(const RecordingEstimate& e);

}  // namespace inhap::datadriven
