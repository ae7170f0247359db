// Priors, friction cone and fallback of the force model (see force_model_priors.hpp).
// Units: mm, N.
#include "force_model_priors.hpp"

#include <algorithm>

namespace inhap::datadriven::detail {

void fit_priors(const TrainingSet& data, const TrainParams& params, ForceModel& model,
                std::vector<Vec3>& base) {
  const std::size_t n = data.size();
  std::vector<SurfaceFrame> frame(n);
  for (std::size_t i = 0; i < n; ++i) frame[i] = surface_frame(data.n[i]);
  if (params.stiffness_prior) {
    std::vector<double> depth(n), fn(n);
    for (std::size_t i = 0; i < n; ++i) {
      depth[i] = frame[i].n.dot(data.q[i] - data.p[i]);
      fn[i] = frame[i].n.dot(data.f[i]);
    }
    model.prior = fit_stiffness_prior(data.q, depth, fn, params.stiffness);
    for (std::size_t i = 0; i < n; ++i) base[i].z() = model.prior.normal_force(data.q[i], depth[i]);
  }
  if (params.shear_prior) {
    // |u_t| and |f_t| of the samples whose tangential force opposes u_t (within ~25 deg); the
    // others get |u_t| = 0, which the fit leaves out.
    std::vector<double> ut_len(n, 0.0), ft_len(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& nn = frame[i].n;
      const Vec3 ut = tangential_displacement(data.p[i], data.q[i], nn);
      const Vec3 ft = data.f[i] - nn.dot(data.f[i]) * nn;
      const double lu = ut.norm(), lf = ft.norm();
      if (lu > 0 && lf > 0 && -ut.dot(ft) >= 0.9 * lu * lf) ut_len[i] = lu, ft_len[i] = lf;
    }
    model.shear = fit_stiffness_prior(data.q, ut_len, ft_len, params.shear);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 t = frame[i].to_local(shear_force(model.shear, data.p[i], data.q[i], frame[i].n));
      base[i].x() += t.x(), base[i].y() += t.y();
    }
  }
}

namespace {

// The `quantile` of |f_t| / f_n over the samples pressed with f_n >= 1 N (lighter touches are
// mostly noise and onset transients), only those whose proxy slid when `sliding_only`; 0 with
// fewer than `min_samples` of them.
double friction_ratio_quantile(const TrainingSet& data, bool sliding_only, double quantile,
                               std::size_t min_samples) {
  std::vector<double> ratio;
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (sliding_only && !(data.slip[i] > 0)) continue;
    const Vec3 nn = surface_frame(data.n.empty() ? Vec3::UnitZ() : data.n[i]).n;
    const double fn = nn.dot(data.f[i]);
    if (fn >= 1.0) ratio.push_back((data.f[i] - fn * nn).norm() / fn);
  }
  if (ratio.size() < min_samples) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(quantile * static_cast<double>(ratio.size() - 1));
  std::nth_element(ratio.begin(), ratio.begin() + k, ratio.end());
  return ratio[static_cast<std::size_t>(k)];
}

}  // namespace

double fit_friction_cone(const TrainingSet& data) {
  return friction_ratio_quantile(data, false, 0.995, 10);
}

double fit_sliding_mu(const TrainingSet& data) {
  if (data.slip.size() != data.size()) return 0.0;
  const double mu =
      friction_ratio_quantile(data, true, kSlidingFloorQuantile, kSlidingFloorMinSamples);
  return std::isfinite(mu) && mu > 0 ? mu : 0.0;
}

Fallback fit_fallback(const TrainingSet& data, const TrainParams& params,
                      const StiffnessPrior& prior) {
  const std::size_t n = data.size();
  std::vector<double> depth(n), fn(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 nn = surface_frame(data.n[i]).n;
    depth[i] = nn.dot(data.q[i] - data.p[i]);
    fn[i] = nn.dot(data.f[i]) / fallback_scale(prior, data.q[i]);
  }
  Fallback fb;
  fb.law = fit_depth_law(depth, fn);
  if (fb.law.empty()) return {};
  fb.support = make_support_distance(data.q);
  fb.near_mm = params.fallback_near_mm;
  fb.far_mm = params.fallback_far_mm;
  fb.normal_near_mm = params.fallback_normal_near_mm;
  fb.normal_far_mm = params.fallback_normal_far_mm;
  fb.support.build(fb.reach_mm());  // the distance grid: the fallback is complete when returned
  return fb;
}

}  // namespace inhap::datadriven::detail
