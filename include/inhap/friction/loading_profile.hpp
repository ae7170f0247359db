// Contact loading profile of one palpation cycle (thesis 4.3.2, fig. 4.6).
// Units: forces N, times s, rates N/s.
//
// The normal load rises over t_N, then the tangential load over t_T, both are held for
// t_plateau, then the tangential load falls over t_T and the normal load over t_N. Every ramp is
// sine-smoothed, s(x) = (1 - cos(pi x)) / 2, so the profile and its slope are continuous at the
// ends of a ramp. Ramp durations follow from fixed rates: t_N = f_N / rate_N, t_T = f_T / rate_T
// (with a floor, so a zero force still gets a well-defined ramp).
#pragma once

namespace inhap::friction {

struct ProfileRates {
  double normal_rate = 10.0;     ///< f_N / t_N, N/s
  double tangential_rate = 5.0;  ///< f_T / t_T, N/s
  double min_ramp = 0.02;        ///< shortest ramp, s
  /// Measurement instant relative to the start of the plateau, s. The default lies inside the
  /// shortest plateau (100 ms), so cycles with different plateaus are measured at the same
  /// point of their loading history.
  double measurement_offset = 0.09;
};

/// One loading-unloading profile. Times are measured from the start of the normal ramp.
class LoadingProfile {
 public:
  LoadingProfile() = default;
  LoadingProfile(double f_normal, double f_tangential, double t_plateau, const ProfileRates& rates);

  double f_normal() const { return fn_; }
  double f_tangential() const { return ft_; }
  double t_normal() const { return tn_; }
  double t_tangential() const { return tt_; }
  double t_plateau() const { return tp_; }
  /// Start of the plateau (end of the tangential loading ramp), s.
  double plateau_start() const { return tn_ + tt_; }
  /// Measurement time t_measurement, s (clamped into the plateau).
  double t_measurement() const { return tm_; }
  /// Total duration 2 t_N + 2 t_T + t_plateau, s.
  double duration() const { return 2.0 * (tn_ + tt_) + tp_; }

  /// Normal load magnitude at time t (0 outside [0, duration]), N.
  double normal(double t) const;
  /// Tangential load magnitude at time t, N.
  double tangential(double t) const;

 private:
  double fn_ = 0, ft_ = 0, tn_ = 0, tt_ = 0, tp_ = 0, tm_ = 0;
};

/// Sine-smoothed unit ramp: 0 for x <= 0, 1 for x >= 1, (1 - cos(pi x)) / 2 between.
double smooth_ramp(double x);

}  // namespace inhap::friction
