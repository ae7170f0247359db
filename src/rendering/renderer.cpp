// CBA (constraint-based god-object rendering) and TCA-MESH (thesis ch. 5.2, Algorithm 1).
// Units: mm, N, N/mm. See docs/rendering.md for the algorithm and the decisions taken where the
// thesis is loose.
#include "inhap/rendering/renderer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/spatial_order.hpp"
#include "surface_walk.hpp"

namespace inhap::rendering {

namespace {

// Coordinates beyond 1 km are not a haptic device reading: treated like NaN.
constexpr double kAbsurdCoordinateMm = 1e6;
// How far past an exiting surface crossing the entry search restarts, and how far off the
// surface the release sweep starts (mm).
constexpr double kSurfaceEpsMm = 1e-6;
// Exiting crossings skipped on one sweep before giving up (thin shells, overlapping sheets).
constexpr int kMaxSweepCrossings = 8;

TriMesh checked(TriMesh mesh, const Params& params) {
  if (mesh.triangles.empty()) throw Error("rendering model: the mesh has no triangles");
  mesh.validate("rendering model");
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(params.force_limit_n) || params.force_limit_n > kDeviceForceLimitN)
    throw Error(fmt::format(
        "rendering params: expected force_limit_n in (0, {}] N (the device's limit), got {}",
        kDeviceForceLimitN, params.force_limit_n));
  if (!positive(params.default_stiffness) || params.default_stiffness > kMaxStiffnessNmm)
    throw Error(fmt::format("rendering params: expected default_stiffness in (0, {}] N/mm, got {}",
                            kMaxStiffnessNmm, params.default_stiffness));
  if (mesh.has_property("stiffness")) {
    // Below min_stiffness (zero, negative) is floored when rendering; above the maximum or not
    // finite is a bad map.
    const std::vector<double>& k = mesh.property("stiffness");
    for (std::size_t v = 0; v < k.size(); ++v)
      if (!(std::isfinite(k[v]) && k[v] <= kMaxStiffnessNmm))
        throw Error(
            fmt::format("rendering model: vertex {}: stiffness {} N/mm, expected a finite "
                        "value of at most {} N/mm (the stiffest surface rendered)",
                        v, k[v], kMaxStiffnessNmm));
  }
  if (!positive(params.min_stiffness))
    throw Error(fmt::format("rendering params: expected min_stiffness > 0 N/mm, got {}",
                            params.min_stiffness));
  if (!std::isfinite(params.a_s) || params.a_s < 0)
    throw Error(fmt::format("rendering params: expected a_s >= 0, got {}", params.a_s));
  if (!std::isfinite(params.a_t) || params.a_t < 0)
    throw Error(fmt::format("rendering params: expected a_t >= 0, got {}", params.a_t));
  if (!positive(params.max_jump_mm))
    throw Error(
        fmt::format("rendering params: expected max_jump_mm > 0 mm, got {}", params.max_jump_mm));
  if (mesh.normals.size() != mesh.positions.size()) mesh.compute_normals();
  if (params.spatial_order) sort_spatially(mesh);
  return mesh;
}

}  // namespace

Model::Model(TriMesh mesh, Params params)
    : mesh_(checked(std::move(mesh), params)),
      params_(params),
      index_(mesh_, params.index),
      adjacency_(build_adjacency(mesh_)) {
  if (mesh_.has_property("stiffness"))
    stiffness_ = mesh_.property("stiffness");
  else
    stiffness_.assign(mesh_.num_vertices(), params_.default_stiffness);
}

double Model::stiffness(const SurfacePoint& q) const {
  if (!q.valid()) return params_.min_stiffness;
  const Tri& t = mesh_.triangles[static_cast<std::size_t>(q.triangle)];
  const double k =
      q.bary[0] * stiffness_[t[0]] + q.bary[1] * stiffness_[t[1]] + q.bary[2] * stiffness_[t[2]];
  return std::isfinite(k) ? std::max(k, params_.min_stiffness) : params_.min_stiffness;
}

Vec3 Model::normal(const SurfacePoint& q) const {
  if (!q.valid()) return Vec3::UnitZ();
  const auto f = static_cast<std::size_t>(q.triangle);
  const Vec3 face = mesh_.face_normal(f);
  if (params_.force_shading) {
    const Tri& t = mesh_.triangles[f];
    const Vec3 n = q.bary[0] * mesh_.normals[t[0]] + q.bary[1] * mesh_.normals[t[1]] +
                   q.bary[2] * mesh_.normals[t[2]];
    const double len = n.norm();
    // Opposite vertex normals (a folded sheet) cancel, and a vertex normal facing away from the
    // face (bad normals in a file) would flip inside and outside: use the face normal then.
    if (len > 1e-6 && std::isfinite(len) && (face.isZero() || n.dot(face) > 0)) return n / len;
  }
  return face.isZero() ? Vec3(Vec3::UnitZ()) : face;
}

// ---------------------------------------------------------------------------------------------
// The servo step.

namespace {

struct Tick {
  const Model& model;
  State& st;
  const Vec3& p;  // HIP, world, mm
  bool tca;
  Vec3 frame_t;  // t(n): the translation of M this tick (0 for CBA)
};

// First entering crossing of the segment a->b (mesh coordinates) with the surface; exiting
// crossings (the probe leaving an object from inside) are skipped.
bool find_entry(const MeshIndex& index, Vec3 a, const Vec3& b, SurfacePoint& hit) {
  for (int i = 0; i < kMaxSweepCrossings; ++i) {
    const Vec3 d = b - a;
    const double len = d.norm();
    if (!(len > 0)) return false;
    const auto h = index.first_hit(a, b);
    if (!h) return false;
    if (h->entering) {
      hit = *h;
      return true;
    }
    const double along = h->t * len + kSurfaceEpsMm;
    if (along >= len) return false;
    a = a + (along / len) * d;
  }
  return false;
}

// IHIP update: local graph search from triangle `start`, with the global fallback when the walk
// runs out of budget (accepted only when it agrees on inside/outside, so the fallback can never
// pull the proxy through a thin wall to the far side).
detail::WalkResult find_ihip(Tick& tk, std::int32_t start, const Vec3& pl) {
  const Model& m = tk.model;
  detail::WalkResult w = detail::local_closest(
      m.mesh(), m.adjacency(), start, pl, m.params().max_walk_steps, m.vertex_stiffness().data());
  tk.st.walk_steps = w.steps;
  if (w.converged) return w;
  const ClosestPoint g = m.index().closest_point(pl, std::sqrt(w.distance2));
  if (!g.valid() || g.distance2 >= w.distance2) return w;
  const double side_walk = (w.q.point - pl).dot(m.normal(w.q));
  const double side_global = (g.point - pl).dot(m.normal(g));
  ++tk.st.fallbacks;
  if ((side_walk >= 0) != (side_global >= 0)) return w;
  w.q = g;
  w.distance2 = g.distance2;
  return w;
}

// Sets the contact outputs of the state and returns the force (before clamping).
Vec3 render_contact(Tick& tk, const SurfacePoint& ql, double k, const Vec3& n, double x) {
  State& st = tk.st;
  st.collision = true;
  st.ihip = ql;
  st.ihip.point = ql.point + tk.frame_t;
  st.normal = n;
  st.k = k;
  st.cihip = st.ihip.point + st.s * n;
  if (tk.model.params().force_shading) return k * (x + st.s) * n;  // eq. 5.5
  return k * (st.cihip - tk.p);                                    // Algorithm 1, line 25
}

void set_free(State& st, const Vec3& p) {
  st.collision = false;
  st.ihip = SurfacePoint{};
  st.ihip.point = p;  // in free space the god-object coincides with the HIP
  st.cihip = p;
  st.k = 0;
  st.k_prev = 0;
  st.s = 0;
}

// Algorithm 1 lines 3-7: contact made by the sweep a->b (mesh coordinates). Returns true and the
// force when the probe ends inside; the local search may show that it does not (it crossed a
// sheet's edge and ended outside): then it stays free.
bool first_contact(Tick& tk, const Vec3& a, const Vec3& b, Vec3& force) {
  SurfacePoint hit;
  if (!find_entry(tk.model.index(), a, b, hit)) return false;
  const detail::WalkResult w = find_ihip(tk, hit.triangle, b);
  const double k = tk.model.stiffness(w.q);
  const Vec3 n = tk.model.normal(w.q);
  const double x = (w.q.point - b).dot(n);
  if (x < 0) return false;
  tk.st.s = 0;
  tk.st.k_prev = k;  // erratum: no k(n-1) at first contact, so Δs(n1) = 0
  force = render_contact(tk, w.q, k, n, x);
  return true;
}

// Eq. 5.4, 5.11-5.13: the point compensation s(n).
double update_s(const State& st, const Vec3& p, double k, const Vec3& n, double x, double a_s) {
  const double ds = (st.k_prev - k) / k * (x + st.s);
  const double d_s = (p - st.hip_prev).cross(n).norm();
  const double lim = a_s * d_s;
  double dr;
  if (st.s > lim)
    dr = -lim;
  else if (st.s < -lim)
    dr = lim;
  else
    dr = -st.s;
  return st.s + ds + dr;
}

// Algorithm 1 lines 12-22 (and CBA with s = 0): contact maintained or released.
Vec3 contact_tick(Tick& tk) {
  State& st = tk.st;
  const Vec3 pl = tk.p - tk.frame_t;
  const detail::WalkResult w = find_ihip(tk, st.ihip.triangle, pl);
  const double k = tk.model.stiffness(w.q);
  const Vec3 n = tk.model.normal(w.q);
  const double x = (w.q.point - pl).dot(n);
  st.k_prev = st.k;  // k(n-1)
  const double s = tk.tca ? update_s(st, tk.p, k, n, x, tk.model.params().a_s) : 0.0;
  if (x + s >= 0) {  // eq. 5.14
    st.s = s;
    return render_contact(tk, w.q, k, n, x);
  }
  if (tk.tca)
    tk.frame_t += s * n;  // t(n+1) = t(n) + s(n) n(n); the surface stays where it was felt
  // God-object rule: the proxy moves from where it was toward p and stops at the first surface
  // crossing; p may have passed into another part of the surface in this tick.
  const Vec3 goal = tk.p - tk.frame_t;
  const Vec3 dir = goal - w.q.point;
  const double len = dir.norm();
  set_free(st, tk.p);
  Vec3 force = Vec3::Zero();
  if (len > kSurfaceEpsMm &&
      first_contact(tk, w.q.point + (kSurfaceEpsMm / len) * dir, goal, force))
    return force;
  return Vec3::Zero();
}

// Eq. 5.15-5.17: mesh restoration while free.
Vec3 restore_t(const Vec3& t, double d_t, double a_t) {
  const double len = t.norm();
  const double r = a_t * d_t;
  if (len <= r) return Vec3::Zero();
  return t - (r / len) * t;
}

Vec3 clamp_force(const Vec3& f, double limit) {
  const double mag = f.norm();
  if (!std::isfinite(mag)) return Vec3::Zero();
  return mag > limit ? Vec3(f * (limit / mag)) : f;
}

}  // namespace

std::uint32_t prefetch(const Model& model, const State& state, const Vec3& p_next) noexcept {
  if (!state.has_prev || !p_next.allFinite() ||
      !((p_next - state.hip_prev).norm() < model.params().max_jump_mm))
    return 0;
  const Vec3 pl = p_next - state.t;
  std::int32_t start = -1;
  if (state.collision && state.ihip.valid()) {
    start = state.ihip.triangle;
  } else {
    SurfacePoint hit;
    if (find_entry(model.index(), state.hip_prev_mesh, pl, hit)) start = hit.triangle;
  }
  if (start < 0) return 0;
  const detail::WalkResult w =
      detail::local_closest(model.mesh(), model.adjacency(), start, pl,
                            model.params().max_walk_steps, model.vertex_stiffness().data());
  // What the force reads at the answer; the volatile store keeps the reads.
  volatile double sink = model.stiffness(w.q) + model.normal(w.q).z();
  static_cast<void>(sink);
  return w.steps;
}

Vec3 step(const Model& model, State& state, const Vec3& p, Algorithm algorithm) {
  const Params& prm = model.params();
  if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kAbsurdCoordinateMm) {
    state.reset();
    return Vec3::Zero();
  }
  const bool tca = algorithm == Algorithm::kTCA;
  if (!tca) state.t.setZero();
  if (!state.has_prev || (p - state.hip_prev).norm() >= prm.max_jump_mm) {
    if (state.has_prev) state.reset();  // a glitch: forget everything, re-detect from outside
    set_free(state, p);
    state.has_prev = true;
    state.hip_prev = p;
    state.hip_prev_mesh = p - state.t;
    state.force.setZero();
    return Vec3::Zero();
  }
  Tick tk{model, state, p, tca, state.t};
  state.walk_steps = 0;
  Vec3 force = Vec3::Zero();
  bool restore = false;
  if (state.collision && state.ihip.valid()) {
    force = contact_tick(tk);
  } else if (!first_contact(tk, state.hip_prev_mesh, p - tk.frame_t, force)) {
    set_free(state, p);
    restore = tca;
  }
  const double d_t = (p - state.hip_prev).norm();
  state.hip_prev = p;
  state.hip_prev_mesh = p - tk.frame_t;
  state.t = restore ? restore_t(tk.frame_t, d_t, prm.a_t) : tk.frame_t;
  force = clamp_force(force, effective_force_limit(prm.force_limit_n));
  if (!force.allFinite() || !state.cihip.allFinite() || !std::isfinite(state.s)) {
    state.reset();
    return Vec3::Zero();
  }
  state.force = force;
  return force;
}

}  // namespace inhap::rendering
