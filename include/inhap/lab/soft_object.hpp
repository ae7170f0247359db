// Virtual lab: a soft object = undeformed shape + material fields over its surface, with the
// ground-truth queries every estimator is scored against.
//
// Units: mm, N, s. Stiffness k is in N/mm^exponent (the Hunt-Crossley law
// f = k delta^e (1 + c delta_dot), delta = penetration of the probe centre's offset surface in
// mm); "effective stiffness" is the secant F / depth(F) in N/mm (thesis fig. 3.3 quotes it at
// F = 5 N).
//
// Inclusions are smooth blobs inside the object: a point x of the surface gets the factor
//     s(x) = prod_i (1 + (factor_i - 1) exp(-|x - c_i|^2 / r_i^2))
// on k and k_t (and likewise mu_factor on mu), so a blob whose centre lies d below the surface
// changes the surface right above it by 1 + (factor - 1) exp(-d^2 / r^2).
#pragma once

#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/lab/shape.hpp"

namespace inhap::lab {

/// Contact law of the probe against the material at one surface point.
struct ContactLaw {
  double k = 0.35;         ///< normal stiffness, N/mm^exponent
  double exponent = 1.5;   ///< 1.5: Hertz sphere; 1.0: linear spring
  double damping = 0.004;  ///< Hunt-Crossley damping c, s/mm
  double k_t = 0.5;        ///< tangential pre-sliding stiffness, N/mm
  double mu = 1.2;         ///< Coulomb friction coefficient
  double creep = 0.02;     ///< slip viscosity c_v, N s/mm: slip speed = (|f_t| - mu f_n) / c_v

  /// Static normal force at penetration depth delta (mm), N.
  double normal_force(double delta) const;
  /// Static penetration depth at normal force f (N), mm.
  double depth_at(double force) const;
  /// Effective (secant) stiffness F / depth(F) at force F, N/mm.
  double effective_stiffness(double force = 5.0) const;
  /// Tangent stiffness df/ddelta at force F, N/mm.
  double tangent_stiffness(double force) const;
};

/// A smooth blob that scales the material of the surface above it.
struct Inclusion {
  Vec3 center = Vec3::Zero();     ///< blob centre (inside the object), mm
  double radius = 10.0;           ///< 1/e radius of the Gaussian weight, mm
  double stiffness_factor = 1.0;  ///< multiplies k and k_t (< 1 softer, > 1 stiffer)
  double mu_factor = 1.0;         ///< multiplies mu
};

class SoftObject {
 public:
  SoftObject() = default;
  SoftObject(Shape shape, ContactLaw material, std::vector<Inclusion> inclusions = {});

  const Shape& shape() const { return shape_; }
  const ContactLaw& material() const { return material_; }
  const std::vector<Inclusion>& inclusions() const { return inclusions_; }

  /// Undeformed surface: signed distance, outward normal, closest point (mm).
  SurfaceQuery query(const Vec3& p) const { return shape_.query(p); }
  /// Closest point of the undeformed surface to p.
  Vec3 surface_point(const Vec3& p) const { return shape_.query(p).closest; }
  Vec3 surface_normal(const Vec3& p) const { return shape_.query(p).normal; }

  /// Blob weight product on stiffness (1 when there are no inclusions) at point x.
  double stiffness_factor(const Vec3& x) const;
  double mu_factor(const Vec3& x) const;
  /// Contact law at the surface point closest to x (allocation-free).
  ContactLaw law_at(const Vec3& x) const;
  double mu_at(const Vec3& x) const { return law_at(x).mu; }
  /// Effective stiffness F / depth(F) at the surface point closest to x, N/mm.
  double stiffness_at(const Vec3& x, double force = 5.0) const {
    return law_at(x).effective_stiffness(force);
  }
  /// Static indentation depth of the probe centre under normal force F at x, mm.
  double indentation_depth(const Vec3& x, double force) const { return law_at(x).depth_at(force); }

 private:
  Shape shape_;
  ContactLaw material_;
  std::vector<Inclusion> inclusions_;
};

/// Checks the material (positive k, exponent in [1, 3], non-negative damping/creep/mu...);
/// returns an error message or an empty string.
std::string validate_material(const ContactLaw& law);

}  // namespace inhap::lab
