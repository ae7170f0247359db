// Virtual lab, MuJoCo backend (internal to src/lab): the contact between the device's probe
// and a soft object computed by MuJoCo 2.2 (see include/inhap/lab/physics.hpp and
// docs/lab-mujoco.md). Units at this interface: mm, mm/s, N, s.
//
// Model: a sphere "probe" body (3 slide joints, mass m) is coupled to the device position p by
// a spring that is stiff along the surface normal (k_n) and has the material's pre-sliding
// stiffness k_t across it, both critically-ish damped; the probe body touches the object
// geom with MuJoCo's soft contact (negative solref = (-k_s, -b_s), solimp) and an elliptic
// friction cone (condim 3). Stiffness and friction vary over the object: before every MuJoCo
// step the object geom's solref and friction are set from the material at the probe body, so
// that the static depth at 5 N equals the scene's (ContactLaw::depth_at(5)).
// The force on the device is minus the coupling force; the true proxy q is the probe body
// projected onto the offset surface (where the device would come to rest if unloaded).
#pragma once

#include <memory>

#include "inhap/lab/physics.hpp"
#include "inhap/lab/soft_contact.hpp"

namespace inhap::lab {

class MujocoContact {
 public:
  /// Builds the MuJoCo model of `object` (cylinder, dome, hemisphere, sphere and box shapes;
  /// others throw inhap::Error naming the shape) for a probe of radius `probe_radius` (mm, 0 =
  /// sharp tip), stepping `dt` s. Throws inhap::Error when MuJoCo is not available.
  MujocoContact(const SoftObject& object, double probe_radius, double dt,
                const MujocoParams& params);
  ~MujocoContact();
  MujocoContact(const MujocoContact&) = delete;
  MujocoContact& operator=(const MujocoContact&) = delete;

  /// Puts the probe body at p (mm) at rest; the contact state is recomputed.
  void place(const Vec3& p, ContactState& state, double t);
  /// One MuJoCo step of `dt` with the device at p moving at v; returns the force on the device,
  /// N, and fills `state` (ground truth). No allocation, no exceptions.
  Vec3 step(const Vec3& p, const Vec3& v, double t, ContactState& state);

  /// MuJoCo's static soft-contact force (N) at penetration r (mm) of the probe body for the
  /// material at x: F = K d(r)^2 r / ((1 - d(r)) w), w = the probe's inverse mass (MuJoCo's
  /// diagApprox), K = k_s / dmax^2 (docs/lab-mujoco.md).
  double static_force(const Vec3& x, double r_mm) const;
  /// Position of the probe body (mm).
  Vec3 probe_position() const;
  /// MuJoCo warnings raised so far (instability, solver limits).
  int warnings() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace inhap::lab
