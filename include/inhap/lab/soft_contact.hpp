// Virtual lab: the ground-truth contact law between the probe and a soft object.
// Units: mm, N, s. Model/state split: contact_step(const SoftObject&, ContactState&, ...) is
// allocation-free and exception-free.
//
// With d = signed distance of the probe centre p to the undeformed surface, R the probe radius
// (0 for a sharp tip) and n the outward normal at p:
//   penetration      delta = R - d  (contact when delta > 0)
//   normal force     f_n = max(0, k delta^e (1 + c delta_dot)),  delta_dot = -n . v
//   proxy (anchor)   q: the probe-centre position the probe would return to if unloaded now
//                    (thesis eq. 4.4); set to the first-contact point, always kept on the
//                    offset surface d = R
//   tangential       u_t = (p - q) - ((p - q) . n) n,   f_t = -k_t u_t   (pre-sliding)
//   sliding          if |f_t| > mu f_n, q slides toward p with speed (|f_t| - mu f_n) / c_v,
//                    integrated implicitly, so |f_t| = mu f_n + c_v * slip speed
//   force on probe   f = f_n n + f_t
// Side memory: a contact remembers the side it entered from (the outward normal and surface
// point under the proxy). While the closest surface faces that side (normal within 60 deg of
// it) d and n are the exact ones; otherwise (the probe is past the middle of a thin part, or
// deeper under a rim than the wall beside it) the penetration is measured from the tangent
// plane of the entry side, delta = R - (p - x_side) . n_side, and the force keeps pushing along
// n_side. Thin parts therefore deform instead of being passed through: the probe never leaves
// a contact through the far side, and the contact ends only when it is back out of the side it
// entered. The side memory follows the proxy as it slips, but never onto a side facing away
// (more than 90 deg) from the normal where the episode began, and a closest surface facing away
// from it is never the entry side: a tip pressed obliquely near a thin rim (the base of a
// bunny's ear) drags the proxy round the rim, and the memory would otherwise follow it, step by
// step, onto the far side and let the tip out there.
// k, k_t, mu, c, c_v are those of the material at q (SoftObject::law_at), so a stuck contact
// is conservative (plus Hunt-Crossley damping): a loading-unloading cycle cannot create energy.
#pragma once

#include <cstdint>
#include <limits>

#include "inhap/lab/soft_object.hpp"

namespace inhap::lab {

/// Persistent contact state (one per probe).
struct ContactState {
  bool in_contact = false;
  Vec3 proxy = Vec3::Zero();  ///< q, mm (valid while in_contact)
  ContactLaw law;             ///< material at the proxy
  Vec3 normal{0, 0, 1};
  Vec3 side_normal{0, 0, 1};       ///< outward normal of the entry side under the proxy
  Vec3 side_point = Vec3::Zero();  ///< surface point under the proxy, mm
  Vec3 entry_normal{0, 0, 1};      ///< outward normal where the episode began
  bool side_plane = false;         ///< the last step measured delta from the entry side's plane
  double delta = 0.0;              ///< current penetration, mm
  double normal_force = 0.0;       ///< f_n, N
  Vec3 force = Vec3::Zero();       ///< force on the probe, N
  bool slipping = false;
  // First contact of the current contact episode, interpolated between evaluations.
  double start_time = std::numeric_limits<double>::quiet_NaN();
  Vec3 start_point = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  std::int64_t episode = -1;  ///< counts contact onsets since construction (-1: none yet)
  // Previous evaluation (for the crossing interpolation).
  bool has_prev = false;
  double prev_delta = 0.0, prev_time = 0.0;
  Vec3 prev_point = Vec3::Zero();

  void reset() { *this = ContactState{}; }
};

/// Evaluates the contact for probe centre p moving at v at time t; dt is the time since the
/// previous evaluation (slip integration). Returns the force on the probe, N. Non-finite input
/// -> zero force and a state reset.
Vec3 contact_step(const SoftObject& object, double probe_radius, ContactState& state, const Vec3& p,
                  const Vec3& v, double t, double dt);

/// Puts q back on the offset surface d = R (closest point + R n).
Vec3 project_to_offset(const SoftObject& object, double probe_radius, const Vec3& q);

}  // namespace inhap::lab
