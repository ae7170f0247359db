// Palpation of a virtual-lab scene for `inhap sys palpate` and `inhap eval sys` (implemented in
// cmd_sys.cpp). Units: mm, N, s.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::cli {

struct ScenePalpationOptions {
  std::string scene;           ///< built-in scene name
  std::string scene_file;      ///< or a scene JSON file
  std::string points;          ///< grid:RxC[:H], rings:1,6,11[:R], file:xy.csv ("": default)
  std::uint64_t seed = 1;      ///< device noise
  bool quick = false;          ///< f_N {1, 3} N, 4 directions (tests)
  std::string physics = "builtin";  ///< lab contact physics: builtin | mujoco
  std::string progress_label;  ///< progress line on stderr ("": none)
};

struct ScenePalpation {
  lab::Scene scene;
  TriMesh shape_mesh;  ///< probe-centre height field (1 mm grid) of the object and its table
  std::unique_ptr<friction::MeshSurface> shape;
  std::vector<Vec3> points, normals;  ///< reference points (probe centre) and n_c
  std::vector<friction::CycleRecord> cycles;
  friction::SysModel sys;
  long ticks = 0;     ///< simulated servo ticks (1 ms)
  double wall_s = 0;  ///< wall time of the palpation
  double cpu_s = 0;   ///< CPU time of the palpation (wall time without other processes' load)
};

/// Builds the shape mesh, chooses the reference points, palpates each one through the device
/// interface (hand detached) and fits the sliding yield surfaces. Throws inhap::Error.
ScenePalpation palpate_scene(const ScenePalpationOptions& options);

/// One elastic limit of a palpated lab scene against the lab's truth mu * f_N.
struct LimitError {
  std::size_t point = 0, level = 0, direction = 0;  ///< indices into sys points / f_N / angles
  double f_limit = 0, truth = 0;                    ///< N
  double rel = 0;                                   ///< |f_limit - truth| / truth
  bool extrapolated = false;                        ///< the border lay beyond the largest f_T step
  bool measured = false;  ///< found by the border (not extrapolated, sliding seen)
};

/// Every elastic limit of `p.sys` against the scene's mu at its reference point.
std::vector<LimitError> limit_errors(const ScenePalpation& p);

/// Reference point positions (x, y) on the scene's region from a --points spec.
std::vector<Vec2> reference_xy(const lab::Scene& scene, const std::string& spec);

}  // namespace inhap::cli
