#include "inhap/lab/soft_object.hpp"

#include <cmath>

namespace inhap::lab {

double ContactLaw::normal_force(double delta) const {
  return delta > 0 ? k * std::pow(delta, exponent) : 0.0;
}

double ContactLaw::depth_at(double force) const {
  return force > 0 ? std::pow(force / k, 1.0 / exponent) : 0.0;
}

double ContactLaw::effective_stiffness(double force) const {
  const double d = depth_at(force);
  return d > 0 ? force / d : 0.0;
}

double ContactLaw::tangent_stiffness(double force) const {
  const double d = depth_at(force);
  return d > 0 ? exponent * force / d : 0.0;
}

SoftObject::SoftObject(Shape shape, ContactLaw material, std::vector<Inclusion> inclusions)
    : shape_(std::move(shape)), material_(material), inclusions_(std::move(inclusions)) {}

double SoftObject::stiffness_factor(const Vec3& x) const {
  double f = 1.0;
  for (const auto& inc : inclusions_)
    f *= 1.0 + (inc.stiffness_factor - 1.0) *
                   std::exp(-(x - inc.center).squaredNorm() / (inc.radius * inc.radius));
  return f;
}

double SoftObject::mu_factor(const Vec3& x) const {
  double f = 1.0;
  for (const auto& inc : inclusions_)
    if (inc.mu_factor != 1.0)
      f *= 1.0 + (inc.mu_factor - 1.0) *
                     std::exp(-(x - inc.center).squaredNorm() / (inc.radius * inc.radius));
  return f;
}

ContactLaw SoftObject::law_at(const Vec3& x) const {
  ContactLaw law = material_;
  if (inclusions_.empty()) return law;
  const Vec3 s = shape_.query(x).closest;
  const double fk = stiffness_factor(s);
  law.k *= fk;
  law.k_t *= fk;
  law.mu *= mu_factor(s);
  return law;
}

std::string validate_material(const ContactLaw& m) {
  auto fin = [](double v) { return std::isfinite(v); };
  if (!(fin(m.k) && m.k > 0)) return "k: expected a positive stiffness (N/mm^exponent)";
  if (!(fin(m.exponent) && m.exponent >= 1.0 && m.exponent <= 3.0))
    return "exponent: expected a number in [1, 3]";
  if (!(fin(m.damping) && m.damping >= 0)) return "damping: expected a non-negative number (s/mm)";
  if (!(fin(m.k_t) && m.k_t > 0)) return "k_t: expected a positive stiffness (N/mm)";
  if (!(fin(m.mu) && m.mu >= 0)) return "mu: expected a non-negative friction coefficient";
  if (!(fin(m.creep) && m.creep > 0)) return "creep: expected a positive slip viscosity (N s/mm)";
  return "";
}

}  // namespace inhap::lab
