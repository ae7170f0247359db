// The sliding yield surfaces (thesis 4.2-4.3) on files: what `inhap sys fit|table|palpate|proxy`
// and `inhap eval sys` do between reading their flags and writing their outputs.
// Units: mm, N, s, rad.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::eval {

/// The model in a few lines: reference points, f_N levels, directions, the force frame, then one
/// line per point and level with the elastic limit per direction (e = extrapolated, * = no
/// sliding seen).
std::string sys_summary(const friction::SysModel& m);

struct SysFitFileOptions {
  std::string cycles, mesh;  ///< palpation cycles CSV; shape mesh (optional)
  friction::BorderOptions border;
  Vec3 tangent_reference = Vec3::UnitX();
  std::string force_frame = "auto";                    ///< auto | anchor | probe
  double probe_radius_mm = 0.0, load_damping = 0.004;  ///< load_damping in N s/mm
};
struct SysFitFileResult {
  friction::SysModel sys;
  std::size_t cycles = 0;
};
/// Reads the cycles (rows without ncx,ncy,ncz / tx,ty,tz take them from the mesh and the angle
/// column) and fits the sliding yield surfaces.
SysFitFileResult fit_sys_file(const SysFitFileOptions& o);

/// Table 4.1 of a reference point at the f_N level nearest `fn` (N) and direction `dir`: the
/// steps, then the elastic limit and u_elastic_limit, as `sys table` prints it.
std::string table_4_1_text(const friction::SysModel& m, int point, double fn, int dir);

/// Reference points of a device palpation: CSV columns x,y,z (probe centre, mm) and optionally
/// nx,ny,nz (unit); without normals the closest point of `shape` gives point and normal.
/// IoError naming the file for a normal that is not unit length or no rows.
void read_reference_points(const std::string& path, const friction::MeshSurface& shape,
                           std::vector<Vec3>& points, std::vector<Vec3>& normals);
void write_reference_points(const std::string& path, const std::vector<Vec3>& points,
                            const std::vector<Vec3>& normals);

/// `sys proxy`: the proxy of a recording with the sliding yield surfaces and the shape mesh.
struct ProxyFileResult {
  std::size_t contact = 0, sliding = 0;  ///< samples in contact / with the proxy sliding
  std::size_t beyond = 0;                ///< in-contact samples with the probe beyond the mesh rim
  double beyond_max_mm = 0;
};
/// Adds qx,qy,qz (mm; q = p out of contact), contact (0/1) and nx,ny,nz (outward normal at q)
/// unless the recording has them, and beyond_mesh (1: in contact beyond the rim of `mesh`).
ProxyFileResult add_proxy_columns(Recording& rec, const friction::SysModel& sys,
                                  const TriMesh& mesh, double probe_radius_mm, bool creep);

/// `eval sys`: one scene's result as JSON (keys in docs/sliding-yield-surface.md): limit errors
/// (median, max), proxy errors (median, p95, mm), palpation time, and the extras.
nlohmann::json sys_lab_json(const std::string& name, const SysLabResult& res);
/// The table `eval sys` prints for the scenes' JSON, with the targets.
std::string sys_lab_table(const nlohmann::json& objects);

}  // namespace inhap::eval
