// Force error metrics, eq. 4.27-4.31 (see metrics.hpp).
#include "inhap/datadriven/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "inhap/core/error.hpp"

namespace inhap::datadriven {

double absolute_error(const Vec3& r, const Vec3& m) {
  return (r - m).norm();
}

double relative_error(const Vec3& r, const Vec3& m) {
  const double e = (r - m).norm();
  return e > 0 ? e / std::max(r.norm(), m.norm()) : 0.0;
}

double relative_error(double r, double m) {
  const double e = std::fabs(r - m);
  return e > 0 ? e / std::max(std::fabs(r), std::fabs(m)) : 0.0;
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

BoxStats box_stats(const std::vector<double>& values) {
  BoxStats b;
  b.n = values.size();
  if (values.empty()) return b;
  std::vector<double> v = values;
  std::sort(v.begin(), v.end());
  b.min = v.front();
  b.max = v.back();
  b.q1 = quantile(v, 0.25);
  b.median = quantile(v, 0.5);
  b.q3 = quantile(v, 0.75);
  b.mean = mean(v);
  const double iqr = b.q3 - b.q1, lo = b.q1 - 1.5 * iqr, hi = b.q3 + 1.5 * iqr;
  b.whisker_low = b.q1;
  b.whisker_high = b.q3;
  for (double x : v) {
    if (x < lo || x > hi) {
      ++b.outliers;
      continue;
    }
    b.whisker_low = std::min(b.whisker_low, x);
    b.whisker_high = std::max(b.whisker_high, x);
  }
  return b;
}

ForceErrors force_errors(const std::vector<Vec3>& rendered, const std::vector<Vec3>& measured,
                         double magnitude_bin) {
  if (rendered.size() != measured.size())
    throw Error("force errors: expected as many rendered as measured forces");
  if (rendered.empty()) throw Error("force errors: expected at least one sample, got none");
  if (!(magnitude_bin > 0)) throw Error("force errors: expected a positive magnitude bin width");
  const std::size_t n = rendered.size();
  ForceErrors out;
  out.n = n;
  std::vector<double> ae(n), re(n);
  std::array<std::vector<double>, 3> ae_i, re_i;
  std::array<double, 3> sq{};
  for (auto& v : ae_i) v.resize(n);
  for (auto& v : re_i) v.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    ae[t] = absolute_error(rendered[t], measured[t]);
    re[t] = relative_error(rendered[t], measured[t]);
    for (int a = 0; a < 3; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      const double d = rendered[t][a] - measured[t][a];
      ae_i[ua][t] = std::fabs(d);
      re_i[ua][t] = relative_error(rendered[t][a], measured[t][a]);
      sq[ua] += d * d;
    }
  }
  out.ae_mean = mean(ae);
  out.ae_median = median(ae);
  out.re_mean = mean(re);
  out.re_median = median(re);
  out.re_box = box_stats(re);
  for (std::size_t a = 0; a < 3; ++a) {
    out.rmse[a] = std::sqrt(sq[a] / static_cast<double>(n));
    out.ae_axis_mean[a] = mean(ae_i[a]);
    out.ae_axis_median[a] = median(ae_i[a]);
    out.re_axis_mean[a] = mean(re_i[a]);
    out.re_axis_median[a] = median(re_i[a]);
    out.re_axis_box[a] = box_stats(re_i[a]);
  }
  // Fig. 4.13: RE against measured magnitude, in bins of width magnitude_bin.
  std::vector<std::vector<double>> by_bin;
  for (std::size_t t = 0; t < n; ++t) {
    const auto b = static_cast<std::size_t>(measured[t].norm() / magnitude_bin);
    if (b >= by_bin.size()) by_bin.resize(b + 1);
    by_bin[b].push_back(re[t]);
  }
  for (std::size_t b = 0; b < by_bin.size(); ++b) {
    if (by_bin[b].empty()) continue;
    out.re_by_magnitude.push_back({static_cast<double>(b) * magnitude_bin,
                                   static_cast<double>(b + 1) * magnitude_bin, by_bin[b].size(),
                                   mean(by_bin[b]), median(by_bin[b])});
  }
  return out;
}

namespace {

nlohmann::ordered_json xyz(const std::array<double, 3>& v) {
  return {{"x", v[0]}, {"y", v[1]}, {"z", v[2]}};
}

nlohmann::ordered_json box_json(const BoxStats& b) {
  return {{"n", b.n},
          {"min", b.min},
          {"whisker_low", b.whisker_low},
          {"q1", b.q1},
          {"median", b.median},
          {"q3", b.q3},
          {"whisker_high", b.whisker_high},
          {"max", b.max},
          {"mean", b.mean},
          {"outliers", b.outliers}};
}

}  // namespace

std::string force_errors_json(const ForceErrors& e) {
  nlohmann::ordered_json j;
  j["n"] = e.n;
  j["ae_n"] = {{"mean", e.ae_mean}, {"median", e.ae_median}};
  j["re"] = {{"mean", e.re_mean}, {"median", e.re_median}};
  j["rmse_n"] = xyz(e.rmse);
  j["median_ae_n"] = xyz(e.ae_axis_median);
  j["mean_ae_n"] = xyz(e.ae_axis_mean);
  j["re_axis_mean"] = xyz(e.re_axis_mean);
  j["re_axis_median"] = xyz(e.re_axis_median);
  j["re_box"] = box_json(e.re_box);
  j["re_axis_box"] = {{"x", box_json(e.re_axis_box[0])},
                      {"y", box_json(e.re_axis_box[1])},
                      {"z", box_json(e.re_axis_box[2])}};
  nlohmann::ordered_json mags = nlohmann::ordered_json::array();
  for (const auto& m : e.re_by_magnitude)
    mags.push_back({{"f_min_n", m.f_min},
                    {"f_max_n", m.f_max},
                    {"n", m.n},
                    {"re_mean", m.re_mean},
                    {"re_median", m.re_median}});
  j["re_by_magnitude"] = std::move(mags);
  return j.dump();
}

}  // namespace inhap::datadriven
