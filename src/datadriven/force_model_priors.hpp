// Priors, friction cone and fallback of the force model (see force_model.hpp, fallback.hpp):
// private to src/datadriven. Units: mm, N.
#pragma once

#include <cmath>
#include <vector>

#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven::detail {

/// Tangential part of p - q (mm) in world axes, given the unit normal n.
inline Vec3 tangential_displacement(const Vec3& p, const Vec3& q, const Vec3& n) {
  const Vec3 u = p - q;
  return u - n.dot(u) * n;
}

/// Shear prior force (N, world axes): -k_t(q) |u_t|^(beta - 1) u_t.
inline Vec3 shear_force(const StiffnessPrior& shear, const Vec3& p, const Vec3& q, const Vec3& n) {
  const Vec3 ut = tangential_displacement(p, q, n);
  const double len = ut.norm();
  return len > 0 ? Vec3(-shear.force(q, len) / len * ut) : Vec3::Zero();
}

/// Fits the stiffness and shear priors that are asked for; base[i] = their force at sample i in
/// the sample's local frame (t0, t1, n), which the RBFs do not learn.
void fit_priors(const TrainingSet& data, const TrainParams& params, ForceModel& model,
                std::vector<Vec3>& base);

/// |f_t| / f_n of the samples pressed with at least 1 N; the cone is their 99.5 % quantile (0
/// with fewer than 10 such samples).
double fit_friction_cone(const TrainingSet& data);

/// mu_s of TrainParams::sliding_floor: the kSlidingFloorQuantile quantile of |f_t| / f_n over
/// the samples whose proxy slid (TrainingSet::slip > 0), pressed with f_n >= 1 N; 0 with fewer
/// than kSlidingFloorMinSamples such samples or without slip speeds.
inline constexpr double kSlidingFloorQuantile = 0.1;
inline constexpr std::size_t kSlidingFloorMinSamples = 20;
double fit_sliding_mu(const TrainingSet& data);

/// The recording's depth-force law and the training proxies' support (fallback.hpp). With a
/// stiffness prior the law is fitted to f_n / k(q) (k(q) = the prior's local stiffness) and
/// rendered times k(q): the shape of the depth-force law is the data's own, its local scale
/// the prior's map, which follows the stiffness of the data around a gap.
Fallback fit_fallback(const TrainingSet& data, const TrainParams& params,
                      const StiffnessPrior& prior);

/// Exponent of the prior's local stiffness in the fallback's scale (0: one global law, 1: k(q)).
inline constexpr double kFallbackScaleExponent = 1.0;

/// Local stiffness scale of the fallback law at q: k(q)^kFallbackScaleExponent of the prior, 1
/// without one. Servo-safe.
inline double fallback_scale(const StiffnessPrior& prior, const Vec3& q) {
  return prior.empty() ? 1.0 : std::exp(kFallbackScaleExponent * prior.log_stiffness(q));
}

}  // namespace inhap::datadriven::detail
