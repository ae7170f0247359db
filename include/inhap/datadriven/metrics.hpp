// Force error metrics of thesis eq. 4.27-4.31 (the same definitions everywhere in inhap).
//
// Units: forces N; relative errors are dimensionless.
//   AE    = ||f_r - f_m||                                              (4.27)
//   RE    = ||f_r - f_m|| / max(||f_r||, ||f_m||), 0 when f_r = f_m      (4.28)
//   AE_i  = |f_ri - f_mi|                                              (4.29)
//   RE_i  = |f_ri - f_mi| / max(|f_ri|, |f_mi|), 0 when equal            (4.30)
//   RMSE_i = sqrt(mean_t (f_mi - f_ri)^2)                              (4.31)
// with f_r the rendered (model) force and f_m the measured force. Medians and quartiles use
// linear interpolation between order statistics (type 7); box-plot whiskers reach the most
// extreme samples within 1.5 IQR of the quartiles (fig. 4.14); fig. 4.13 (RE against the
// measured force magnitude) is summarised per magnitude bin.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "inhap/core/stats.hpp"

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

double absolute_error(const Vec3& rendered, const Vec3& measured);  ///< eq. 4.27
double relative_error(const Vec3& rendered, const Vec3& measured);  ///< eq. 4.28
double relative_error(double rendered, double measured);            ///< eq. 4.30

/// Quantile (type 7, NaN for no values) and median: inhap/core/stats.hpp.
using inhap::median;
using inhap::quantile;
double mean(const std::vector<double>& values);

struct BoxStats {
  std::size_t n = 0;
  double min = 0, q1 = 0, median = 0, q3 = 0, max = 0, mean = 0;
  double whisker_low = 0, whisker_high = 0;  ///< extreme samples within 1.5 IQR
  std::size_t outliers = 0;                  ///< samples beyond the whiskers
};
BoxStats box_stats(const std::vector<double>& values);

/// RE summarised over a range of measured force magnitude (fig. 4.13).
struct MagnitudeBin {
  double f_min = 0, f_max = 0;  ///< N
  std::size_t n = 0;
  double re_mean = 0, re_median = 0;
};

struct ForceErrors {
  std::size_t n = 0;
  double ae_mean = 0, ae_median = 0;
  double re_mean = 0, re_median = 0;
  std::array<double, 3> rmse{}, ae_axis_mean{}, ae_axis_median{}, re_axis_mean{}, re_axis_median{};
  BoxStats re_box;                      ///< eq. 4.28 ("3D" in fig. 4.14)
  std::array<BoxStats, 3> re_axis_box;  ///< eq. 4.30 per axis
  std::vector<MagnitudeBin> re_by_magnitude;
};

/// Errors of `rendered` against `measured` (same length, > 0). `magnitude_bin` is the width of
/// the fig. 4.13 bins, N. Throws inhap::Error on mismatched or empty input.
ForceErrors force_errors(const std::vector<Vec3>& rendered, const std::vector<Vec3>& measured,
                         double magnitude_bin = 0.5);

/// The report as a JSON object text: {"n", "ae": {"mean","median"}, "re": {"mean","median"},
/// "rmse_n": {"x","y","z"}, "median_ae_n", "mean_ae_n", "re_axis_mean", "re_axis_median",
/// "re_box": {...}, "re_axis_box": {"x": {...}, ...}, "re_by_magnitude": [...]}.
std::string force_errors_json(const ForceErrors& e);

}  // namespace inhap::datadriven
