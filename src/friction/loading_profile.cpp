#include "inhap/friction/loading_profile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace inhap::friction {

double smooth_ramp(double x) {
  if (!(x > 0.0)) return 0.0;
  if (x >= 1.0) return 1.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * x));
}

LoadingProfile::LoadingProfile(double f_normal, double f_tangential, double t_plateau,
                               const ProfileRates& rates)
    : fn_(std::max(0.0, f_normal)),
      ft_(std::max(0.0, f_tangential)),
      tn_(std::max(rates.min_ramp, fn_ / rates.normal_rate)),
      tt_(std::max(rates.min_ramp, ft_ / rates.tangential_rate)),
      tp_(std::max(0.0, t_plateau)) {
  tm_ = plateau_start() + std::clamp(rates.measurement_offset, 0.0, tp_);
}

double LoadingProfile::normal(double t) const {
  const double up = smooth_ramp(t / tn_);
  const double down_start = tn_ + 2.0 * tt_ + tp_;
  const double down = smooth_ramp((t - down_start) / tn_);
  return fn_ * (up - down);
}

double LoadingProfile::tangential(double t) const {
  const double up = smooth_ramp((t - tn_) / tt_);
  const double down = smooth_ramp((t - (tn_ + tt_ + tp_)) / tt_);
  return ft_ * (up - down);
}

}  // namespace inhap::friction
