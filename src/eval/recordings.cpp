// Recordings as a rig writes them, the estimated proxy track and the baselines (recordings.hpp).
// Units: mm, N, s.
#include "inhap/eval/recordings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "inhap/core/error.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/proxy_track.hpp"

namespace inhap::eval {

using namespace inhap::datadriven;

namespace {

// Factors to s and mm of a recording's units; Error on an unknown unit.
std::pair<double, double> unit_scales(const RecordingUnits& u) {
  double ts = 1.0, ls = 1.0;
  if (u.time == "ms")
    ts = 1e-3;
  else if (u.time != "s")
    throw Error(fmt::format("expected time unit 's' or 'ms', got '{}'", u.time));
  if (u.length == "m")
    ls = 1e3;
  else if (u.length != "mm")
    throw Error(fmt::format("expected length unit 'mm' or 'm', got '{}'", u.length));
  return {ts, ls};
}

}  // namespace

Recording read_recording_in(const std::string& path, const RecordingUnits& u) {
  unit_scales(u);  // an unknown unit is said before the file is read
  Recording rec = read_recording(path);
  convert_units(rec, u);
  return rec;
}

void convert_units(Recording& rec, const RecordingUnits& u) {
  const auto [ts, ls] = unit_scales(u);
  if (ts != 1.0)
    for (double& t : rec.t) t *= ts;
  if (ls != 1.0) {
    for (Vec3& p : rec.p) p *= ls;
    for (const char* n : {"qx", "qy", "qz"})  // proxy columns are positions too
      for (std::size_t c = 0; c < rec.extra_names.size(); ++c)
        if (rec.extra_names[c] == n)
          for (double& v : rec.extra[c]) v *= ls;
  }
}

bool has_proxy_columns(const Recording& rec, const std::string& prefix) {
  return rec.find_extra(prefix + "x") && rec.find_extra(prefix + "y") &&
         rec.find_extra(prefix + "z");
}

std::vector<char> force_contact(const Recording& rec, double threshold_n) {
  std::vector<char> c(rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) c[i] = rec.f[i].norm() > threshold_n;
  return c;
}

ProxyTrack estimated_track(const Recording& rec, const friction::SysModel& sys,
                           const TriMesh& surface) {
  const friction::MeshSurface shape(surface, 0.0);
  const friction::ProxyColumns pc = friction::proxy_track({.sys = &sys, .shape = &shape}, rec);
  ProxyTrack t;
  t.q = pc.q;
  t.n = pc.n;
  t.contact = pc.contact;
  t.proxy_source = "estimated";
  t.contact_source = "estimated surface";
  return t;
}

int foaw_window_samples(double window_s, double dt_s) {
  if (!(window_s > 0) || !(dt_s > 0) || !std::isfinite(window_s / dt_s)) return 1;
  return std::clamp(static_cast<int>(std::lround(window_s / dt_s)), 1, kFoawMaxWindow - 1);
}

namespace {

std::string verdict_of(const std::vector<Scored>& rows) {
  const ForceErrors& m = rows[0].errors;
  std::string lost;
  for (int a = 0; a < 3; ++a) {
    std::size_t best = 1;
    for (std::size_t k = 2; k < rows.size(); ++k)
      if (rows[k].errors.rmse[a] < rows[best].errors.rmse[a]) best = k;
    if (m.rmse[a] > rows[best].errors.rmse[a])
      lost += fmt::format("{}{} RMSE {:.3f} > {:.3f} N ({})", lost.empty() ? "" : ", ", "xyz"[a],
                          m.rmse[a], rows[best].errors.rmse[a], rows[best].name);
  }
  std::size_t best = 1;
  for (std::size_t k = 2; k < rows.size(); ++k)
    if (rows[k].errors.re_median < rows[best].errors.re_median) best = k;
  const double ratio = rows[best].errors.re_median > 0 ? m.re_median / rows[best].errors.re_median
                                                       : std::numeric_limits<double>::infinity();
  if (m.re_median > rows[best].errors.re_median)
    lost += fmt::format("{}RE median {:.3f} > {:.3f} ({})", lost.empty() ? "" : ", ", m.re_median,
                        rows[best].errors.re_median, rows[best].name);
  if (lost.empty())
    return fmt::format(
        "the model beats every baseline: RMSE no worse on any axis, RE median {:.3f} = {:.0f} % "
        "of the best baseline's ({}, {:.3f})",
        m.re_median, 100 * ratio, rows[best].name, rows[best].errors.re_median);
  return "warning: the model loses to a baseline: " + lost;
}

}  // namespace

BaselineReport score_with_baselines(const std::vector<Vec3>& rendered, const TrainingSet& train,
                                    const Recording& test, const std::vector<Vec3>& test_v,
                                    const std::vector<char>& mask, const BaselineParams& params) {
  if (rendered.size() != test.size() || test_v.size() != test.size() || mask.size() != test.size())
    throw Error("baselines: expected one rendered force, velocity and flag per test sample");
  const Baselines b = fit_baselines(train.p, train.v, train.f, params);
  std::vector<Vec3> p, v, measured, model;
  for (std::size_t i = 0; i < test.size(); ++i)
    if (mask[i]) {
      p.push_back(test.p[i]);
      v.push_back(test_v[i]);
      measured.push_back(test.f[i]);
      model.push_back(rendered[i]);
    }
  if (p.empty()) throw Error("baselines: expected in-contact test samples, got none");
  const auto pred = predict_baselines(b, p, v);
  BaselineReport r;
  r.samples = p.size();
  r.rows.push_back({"model", force_errors(model, measured)});
  const auto names = baseline_names();
  for (std::size_t k = 0; k < 3; ++k) r.rows.push_back({names[k], force_errors(pred[k], measured)});
  r.verdict = verdict_of(r.rows);
  return r;
}

std::string baseline_text(const BaselineReport& r) {
  std::string s = fmt::format("{} contact samples, RMSE x / y / z (N), RE median:\n", r.samples);
  for (const Scored& row : r.rows)
    s += fmt::format("  {:<7} {:.3f} / {:.3f} / {:.3f}   {:.3f}\n", row.name, row.errors.rmse[0],
                     row.errors.rmse[1], row.errors.rmse[2], row.errors.re_median);
  return s + r.verdict + "\n";
}

nlohmann::ordered_json brief_json(const ForceErrors& e) {
  return {{"rmse_n", {e.rmse[0], e.rmse[1], e.rmse[2]}},
          {"re_median", e.re_median},
          {"re_mean", e.re_mean},
          {"n", e.n}};
}

nlohmann::ordered_json baselines_json(const BaselineReport& r) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (std::size_t k = 1; k < r.rows.size(); ++k) j[r.rows[k].name] = brief_json(r.rows[k].errors);
  return j;
}

}  // namespace inhap::eval
