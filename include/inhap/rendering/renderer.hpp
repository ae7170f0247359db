// Haptic rendering of a mesh carrying a stiffness map (thesis ch. 5): the constraint-based
// god-object algorithm (CBA) and TCA-MESH on top of it.
//
// Units: positions mm, forces N, stiffness N/mm (per-vertex property `stiffness`), time s.
// Model/state split: a Model is immutable and may be shared by many States; step() is the servo
// call (1 kHz): no allocation, no exceptions, no I/O, bounded time.
#pragma once

#include <cstdint>

#include "inhap/core/types.hpp"
#include "inhap/geometry/mesh_index.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::rendering {

enum class Algorithm { kCBA, kTCA };

/// The stiffest surface a model may carry, N/mm: 100 times the thesis' maximum (1.0 N/mm), and
/// below v * dt * k = 6.2 N, i.e. 310 N/mm, where a probe arriving at 20 mm/s (0.02 mm per 1 ms
/// tick) is asked for more than the device's force limit on its first tick of contact and the
/// force sits at the clamp while the hand backs out. Model refuses a stiffness map or a default
/// stiffness above it, or not finite, with an error naming the vertex.
inline constexpr double kMaxStiffnessNmm = 100.0;

struct Params {
  double a_s = 0.05;           ///< height restoration slope of s(n) (eq. 5.11), dimensionless
  double a_t = 0.5;            ///< mesh restoration ratio of t(n) (eq. 5.15), dimensionless
  double force_limit_n = 6.2;  ///< output force clamp (device limit), N
  double default_stiffness =
      1.0;  ///< N/mm (at most kMaxStiffnessNmm), when the mesh has no `stiffness` property
  double min_stiffness = 1e-3;  ///< N/mm, floor applied to k(q) (k = 0 would divide by zero in 5.4)
  bool force_shading = true;    ///< interpolate vertex normals for the force direction
  // --- added by the renderer implementation (append-only) ---
  /// A HIP step of at least this length in one tick (mm) is treated as a tracking glitch: zero
  /// force and a state reset; contact is then re-detected from outside. 20 mm/tick = 20 m/s.
  double max_jump_mm = 20.0;
  /// Budget of triangle moves of the local surface search per tick before the global
  /// closest-point fallback (bounds the worst-case step time).
  std::uint32_t max_walk_steps = 1024;
  /// Options of the model's spatial index. The renderer finds contacts with segment queries and
  /// closest points with a local walk from the previous answer (its closest-point fallback is
  /// bounded by the walk's distance), so the seed grid, which only speeds up unrelated
  /// closest-point queries and costs build time per model, is off by default.
  MeshIndexOptions index{.seed_shell = 0};
  /// Reorder the model's vertices and faces along a Morton curve (sort_spatially) so that the
  /// local search touches few cache lines per tick on large meshes. The surface is the same;
  /// only the numbering changes: Model::mesh() and the triangle ids in State are the reordered
  /// ones. Off: the mesh keeps the caller's numbering.
  bool spatial_order = true;
};

/// Immutable rendering model: mesh with per-vertex stiffness and normals, adjacency, index.
class Model {
 public:
  /// Takes the mesh (needs triangles; computes normals if missing; reorders it when
  /// Params::spatial_order). Throws Error on bad input.
  Model(TriMesh mesh, Params params = {});
  const TriMesh& mesh() const { return mesh_; }
  const MeshIndex& index() const { return index_; }
  const MeshAdjacency& adjacency() const { return adjacency_; }
  const Params& params() const { return params_; }
  /// Per-vertex stiffness of mesh(), N/mm (the `stiffness` property or default_stiffness).
  const std::vector<double>& vertex_stiffness() const { return stiffness_; }
  /// Barycentric interpolation of the vertex stiffness, N/mm (floored at min_stiffness).
  double stiffness(const SurfacePoint& q) const;
  /// Force-shaded unit normal at q (interpolated vertex normals), or the face normal when
  /// force shading is off.
  Vec3 normal(const SurfacePoint& q) const;

 private:
  TriMesh mesh_;
  Params params_;
  MeshIndex index_;
  MeshAdjacency adjacency_;
  std::vector<double> stiffness_;
};

/// Everything that changes per servo tick (thesis notation in brackets).
struct State {
  bool has_prev = false;         ///< p(n-1) valid
  Vec3 hip_prev = Vec3::Zero();  ///< p(n-1), mm
  bool collision = false;        ///< COLLISION
  SurfacePoint ihip;             ///< q(n) on M^t(n) (point includes the translation t), mm
  Vec3 cihip = Vec3::Zero();     ///< q'(n) = q(n) + s(n) n(n), mm
  Vec3 normal = Vec3::UnitZ();   ///< n(n)
  double k = 0;                  ///< k(n), N/mm
  double k_prev = 0;             ///< k(n-1), N/mm
  double s = 0;                  ///< s(n), signed point compensation, mm
  Vec3 t = Vec3::Zero();         ///< t(n), mesh compensation vector, mm
  Vec3 force = Vec3::Zero();     ///< last output force, N
  std::uint32_t resets = 0;      ///< how many times bad input forced a reset
  // --- added by the renderer implementation (append-only) ---
  /// Previous HIP in mesh coordinates, p(n-1) - t (the t the mesh had when p(n-1) was seen): the
  /// contact test sweeps the HIP's motion *relative to* M^t, so a restoring mesh cannot jump over
  /// a hovering probe.
  Vec3 hip_prev_mesh = Vec3::Zero();
  std::uint32_t walk_steps = 0;  ///< triangles crossed by the local search in the last tick
  std::uint32_t fallbacks = 0;   ///< global closest-point fallbacks since the last reset

  void reset() {
    const std::uint32_t n = resets + 1;
    *this = State{};
    resets = n;
  }
};

/// One servo tick: HIP position p (mm) in, force (N) out. CBA ignores s and t (they stay 0).
Vec3 step(const Model& model, State& state, const Vec3& p, Algorithm algorithm);

/// Cache warm-up for the next tick, for the idle part of a servo period (after the force has gone
/// out): reads what step() will read if the next HIP is near `p_next` (mm) — the local search
/// from the current IHIP, or the contact sweep from the previous HIP and the search from its hit,
/// and the normals and stiffness at the answer — and changes nothing. On a large map a step is
/// bound by memory latency (each tick reaches triangles not seen for a while); warmed with a
/// prediction of the next HIP, those misses leave the force's critical path. The servo loop
/// calls it with p + (p - p_prev). Returns the triangles walked (0 when there is nothing to
/// warm: no previous tick, a non-finite or glitch-sized prediction, no contact ahead).
/// Allocation-free, exception-free, bounded like step() (Params::max_walk_steps).
std::uint32_t prefetch(const Model& model, const State& state, const Vec3& p_next) noexcept;

}  // namespace inhap::rendering
