// Palpation of a virtual-lab scene for `inhap sys palpate`, `inhap eval sys|forces` and the demo
// (thesis 4.2-4.3). Units: mm, N, s.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "inhap/eval/progress.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

struct ScenePalpationOptions {
  std::string scene;                ///< built-in scene name
  std::string scene_file;           ///< or a scene JSON file
  std::string points;               ///< grid:RxC[:H], rings:1,6,11[:R], file:xy.csv ("": default)
  std::uint64_t seed = 1;           ///< device noise
  bool quick = false;               ///< f_N {1, 3} N, 4 directions (tests)
  std::string physics = "builtin";  ///< lab contact physics: builtin | mujoco
  std::string progress_label;       ///< "what" of the progress calls
  Progress progress;                ///< empty: silent
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

/// Probe-centre height field of a scene on a 1 mm grid over the square of half side `half` (mm)
/// around its region (the shape model a real lab gets from chapter 3); the table (z = 0 plus
/// the probe radius) where the probe misses the object. Normals computed.
TriMesh shape_height_field(const lab::Scene& scene, double probe_radius, double half);

/// The protocol settings of `sys palpate` (quick: f_N {1, 3} N, 4 directions).
friction::PalpationConfig palpation_config(bool quick);

/// Palpation through any Device (the lab's with the hand detached, or a real one over the
/// bridge): each reference point (probe centre on `shape`, with its normal) in turn. The protocol
/// steps only on fresh device states: a faulted tick (a late bridge datagram) commands zero force
/// and does not advance it. Throws inhap::Error when a point fails.
struct DevicePalpation {
  std::vector<friction::CycleRecord> cycles;
  long ticks = 0;     ///< protocol ticks (1 ms)
  double wall_s = 0;  ///< wall time, s
  double cpu_s = 0;   ///< CPU time of this process, s
};
DevicePalpation palpate_points(Device& device, const friction::MeshSurface& shape,
                               const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                               const friction::PalpationConfig& config, const Progress& progress,
                               const std::string& label);
/// The sliding yield surfaces of palpation cycles (thesis 4.3.2).
friction::SysModel fit_palpation(const std::vector<friction::CycleRecord>& cycles,
                                 const friction::MeshSurface& shape,
                                 const friction::PalpationConfig& config);

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

/// The estimated proxy of a lab recording (friction::proxy_track with the palpated sliding yield
/// surfaces and shape) against the lab's true tangential anchor.
struct ProxyErrors {
  std::vector<double> err;  ///< |q - true anchor| per sample where the truth is in contact, mm
  std::size_t missed = 0;   ///< of those, samples the estimator had out of contact
};
ProxyErrors proxy_errors(const ScenePalpation& palpation, const lab::LabRecording& lab, bool creep);

/// `inhap eval sys` on one built-in scene (thesis 4.3): palpate, score every elastic limit
/// against the lab's mu * f_N, record a free exploration and score the estimated proxy (with and
/// without creep) against the true anchor.
struct SysLabOptions {
  std::string scene = "planar";
  double seconds = 60.0;            ///< exploration length, s (at most 10 s with quick)
  std::uint64_t seed = 1;           ///< device noise and operator
  bool quick = false;               ///< few reference points, f_N {1, 3} N, 4 directions (tests)
  std::string physics = "builtin";  ///< lab contact physics: builtin | mujoco
  Progress progress;                ///< empty: silent
};
struct SysLabResult {
  ScenePalpation palpation;
  std::vector<double> limit_rel;           ///< |f_limit - mu f_N| / (mu f_N), every limit
  std::vector<double> limit_rel_measured;  ///< the same, measured (not extrapolated) limits
  ProxyErrors proxy;                       ///< with creep (the default estimator)
  ProxyErrors proxy_rate_independent;      ///< without creep
  double exploration_s = 0;                ///< length of the exploration recording, s
};
SysLabResult evaluate_sys_on_lab(const SysLabOptions& options);

/// Reference point positions (x, y) on the scene's region from a --points spec.
std::vector<Vec2> reference_xy(const lab::Scene& scene, const std::string& spec);

}  // namespace inhap::eval
