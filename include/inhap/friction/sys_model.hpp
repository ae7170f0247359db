// Sliding yield surfaces of an object: the reference points, their elastic borders, f_s and
// g_s, and the triangulation that interpolates them over the surface (thesis 4.3.2). Fitted
// from palpation cycles (simulated or recorded on a real device); stored as sys.json.
// Units: mm, N, s, rad.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/friction/elastic_border.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/reference_mesh.hpp"
#include "inhap/friction/yield_surface.hpp"

namespace inhap::friction {

/// The sweep of one (f_N, direction) pair at a reference point and its elastic border.
struct SysBorder {
  double f_normal = 0;  ///< N
  int direction = 0;
  std::vector<BorderStep> steps;
  BorderResult result;
};

struct SysPoint {
  int id = 0;                      ///< reference point id (from the cycles)
  Vec3 position = Vec3::Zero();    ///< probe-centre position on the undeformed surface, mm
  Vec3 normal = Vec3::UnitZ();     ///< outward unit normal n_c
  std::vector<SysBorder> borders;  ///< L x K, index level * K + direction
  YieldSurface fs;                 ///< sliding yield surface (force space)
  YieldSurface gs;                 ///< elastic displacement limit surface (displacement space)
  /// Slip viscosity c_v past the limit, N s/mm (slip speed = excess tangential force / c_v),
  /// from the plateau growth; 0 when unknown (rate-independent return mapping).
  double creep_viscosity = 0;
  /// Tangential elastic stiffness f_limit / radius (median over the borders), N/mm.
  double tangential_stiffness = 0;
  /// Relaxation time c_v / k_t of the elastic displacement beyond g_s, s (0: instantaneous).
  double creep_tau() const {
    return tangential_stiffness > 0 ? creep_viscosity / tangential_stiffness : 0.0;
  }
};

/// Normal at which the measured force of a step is split into f_n and |f_t| for its elastic
/// limit. Where the friction cone of a stuck contact lives depends on the material (and on the
/// physics of a simulator): at n_c, the normal where the stuck patch began (kAnchor: a patch
/// that is carried along by shear, e.g. the MuJoCo lab), or at the surface under the displaced
/// probe (kProbe: the built-in lab). The two differ only on curved parts, by about the angle the
/// probe moved over the surface (pre-sliding displacement / radius). kAuto picks, over the
/// whole fit, the frame in which the limit ratio f_T / f_N of each (point, direction) depends
/// least on f_N (Coulomb: not at all). Without a shape both are n_c.
enum class ForceFrame { kAuto, kAnchor, kProbe };
const char* to_string(ForceFrame f);
/// "auto" | "anchor" | "probe"; throws inhap::Error naming the accepted spellings.
ForceFrame force_frame_from_string(const std::string& s);

struct SysModel {
  static constexpr int kFormatVersion = 1;
  std::vector<double> f_normal_levels;  ///< L levels f_N, N (increasing)
  std::vector<double> angles;           ///< K direction angles from t_0, rad (increasing)
  std::vector<double> plateaus;         ///< short and long t_plateau, s
  Vec3 tangent_reference = Vec3::UnitX();
  BorderOptions border_options;
  /// Frame the limits' forces were decomposed in (kAnchor or kProbe; files without the field:
  /// kProbe, the rule before the choice existed).
  ForceFrame force_frame = ForceFrame::kProbe;
  std::vector<SysPoint> points;
  ReferenceMesh reference_mesh;

  const SysBorder& border(std::size_t point, std::size_t level, std::size_t direction) const {
    return points[point].borders[level * angles.size() + direction];
  }
  /// Index of the point with this id; throws inhap::Error naming the ids present.
  std::size_t point_index(int id) const;
  /// Rebuilds fs/gs of every point from its borders and the reference triangulation from the
  /// positions (keeps `triangles` when given). Throws inhap::Error on inconsistent data.
  void rebuild(const std::vector<Tri>* triangles = nullptr);
};

class ShapeQuery;

struct FitOptions {
  BorderOptions border;
  /// Damping the palpation added while loading (PalpationConfig::load_damping), N s/mm;
  /// subtracted from the measured creep viscosity.
  double load_damping = 0.004;
  /// Undeformed surface (probe-centre) of the object, optional: when given, depths of g_s are
  /// measured from it (geometric, as the proxy estimator does) instead of from p_c.
  const ShapeQuery* shape = nullptr;
  Vec3 tangent_reference = Vec3::UnitX();
  double angle_tolerance = 0.05;  ///< rad: direction k must be at the same angle at every point
  ForceFrame force_frame = ForceFrame::kAuto;
};

/// Fits the sliding yield surfaces from palpation cycles. Cycles with status no_contact,
/// saturated or bad_input are ignored; a step needs one cycle per plateau (the shortest and the
/// longest). Per reference point: borders with a single sliding step are refined with the median
/// growth slope of the others; a border beyond the force range (no step slid) is extrapolated
/// from the highest measured level of the same direction with the same ratio f_T / f_N (flag
/// `extrapolated`); the creep viscosity follows from the median slope. Throws inhap::Error when
/// a reference point lacks a level or direction.
SysModel fit_sys(std::span<const CycleRecord> cycles, const FitOptions& options = {});

/// sys.json: versioned JSON ("format": "inhap-sys", "version": 1); see
/// docs/sliding-yield-surface.md. Writes atomically.
void write_sys_json(const std::string& path, const SysModel& model);
/// Reads and validates sys.json (format, version, sizes, finite numbers, unit normals,
/// triangles); throws ParseError naming the file and the offending entry.
SysModel read_sys_json(const std::string& path);

/// One row of Table 4.1.
struct TableRow {
  double f_tangential = 0, u_short = 0, u_long = 0, growth = 0;
  int label = 0;  ///< 0 elastic, 1 sliding (final border: step index >= split)
};
/// Table 4.1 of a reference point (by id) at a level f_N (nearest) and direction index.
std::vector<TableRow> table_4_1(const SysModel& model, int point_id, double f_normal,
                                int direction);

}  // namespace inhap::friction
