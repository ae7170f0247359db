// Virtual lab: which physics computes the probe-object contact.
//   builtin  inhap's own law (soft_contact.hpp: Hunt-Crossley normal force, elastic tangential
//            anchor, Coulomb sliding with creep);
//   mujoco   MuJoCo 2.2 (Debian libmujoco-dev): a probe body coupled to the device by a stiff
//            normal / compliant tangential spring touches the object with MuJoCo's soft contact
//            (solref/solimp) and elliptic friction cone; see docs/lab-mujoco.md.
// Units: mm, N, s (MuJoCo itself runs in m, kg, s inside src/lab/mujoco_contact.cpp).
#pragma once

#include <string>

#include "inhap/lab/shape.hpp"

namespace inhap::lab {

enum class Physics { kBuiltin, kMujoco };

const char* to_string(Physics p);
/// Parses "builtin" or "mujoco"; throws inhap::Error otherwise.
Physics physics_from_string(const std::string& s);
/// True when this build links MuJoCo (otherwise Physics::kMujoco throws when a device is built).
bool mujoco_available();
/// True when the MuJoCo backend can represent the shape (cylinder, dome, hemisphere, sphere,
/// box; not the ridged slab or meshes).
bool mujoco_represents(const Shape& shape);

/// Settings of the MuJoCo backend (defaults documented in docs/lab-mujoco.md).
struct MujocoParams {
  double probe_mass_kg = 0.005;            ///< mass of the probe body behind the coupling, kg
  double coupling_normal_n_per_mm = 50.0;  ///< device-probe spring along the surface normal
  double coupling_damping_ratio = 0.7;     ///< of both coupling springs (with the probe mass)
  /// solimp (d0, dmax, width mm, midpoint, power): impedance rising with depth, so the contact
  /// stiffens with depth (MuJoCo's law F = m K d(r)^2 r / (1 - d(r)), see docs).
  double solimp_d0 = 0.5, solimp_dmax = 0.8, solimp_width_mm = 6.0, solimp_mid = 0.5,
         solimp_power = 2.0;
  double contact_damping_ratio = 0.5;  ///< sets the solref damping from the local stiffness
  double impratio = 1.0;               ///< MuJoCo's friction-to-normal impedance ratio
  /// MuJoCo's noslip post-processing iterations: 0 leaves MuJoCo's soft friction (which slips
  /// viscously far inside the cone, docs/lab-mujoco.md); > 0 makes it hard Coulomb friction.
  int noslip_iterations = 20;
  double tip_radius_mm = 0.25;  ///< sphere radius standing in for a sharp tip (object shrunk by it)
};

}  // namespace inhap::lab
