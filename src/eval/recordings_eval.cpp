// Train on one recording, render another, score beside the baselines (recordings_eval.hpp).
// Units: mm, N, s.
#include "inhap/eval/recordings_eval.hpp"

#include <fmt/format.h>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"

namespace inhap::eval {

using namespace inhap::datadriven;

namespace {

// Replays e.test with the model of e.train and scores it beside the baselines.
void score(RecordingsEval& e, const TrainFileOptions& o, const std::string& test) {
  const double dt = e.train.model.model.foaw.dt_s;
  e.rate_hz = dt > 0 ? 1.0 / dt : 0.0;
  ProxyTrack track;
  if (e.train.estimate) {
    track = estimated_track(e.test, e.train.estimate->sys, e.train.estimate->mesh);
  } else if (o.proxy.prefix == "p") {
    track =
        position_only_track(e.test, force_contact(e.test, o.proxy.contact_threshold_n), "force");
  } else {
    track = track_of(e.test, test, o.proxy);
    if (e.train.model.model.features == FeatureSet::kLocalFrame)
      add_normals(track, e.test, test, has_normal_columns(e.test) ? std::string() : o.mesh);
  }
  e.rendered = replay(e.train.model.model, e.test, track);
  e.scored = scored_samples(e.test, track, o.proxy);
  e.report = score_with_baselines(e.rendered, e.train.baselines(), e.test,
                                  foaw_velocities(e.test.p, e.train.model.model.foaw), e.scored);
}

}  // namespace

RecordingsEval evaluate_recordings(const TrainFileOptions& o, const std::string& test) {
  RecordingsEval e;
  e.train = train_from_file(o);
  e.test = read_recording_in(test, o.units);
  score(e, o, test);
  return e;
}

RecordingsEval evaluate_recordings(const Recording& train, Recording test,
                                   const TrainFileOptions& o, const std::string& test_name) {
  RecordingsEval e;
  e.train = train_from_recording(train, o);
  e.test = std::move(test);
  score(e, o, test_name);
  return e;
}

nlohmann::ordered_json recordings_json(const RecordingsEval& e, const std::string& test,
                                       const std::string& train) {
  nlohmann::ordered_json j;
  j["train"] = train.empty() ? e.train.model.provenance.recording_path : train;
  j["test"] = test;
  j["units"] = {{"force", "N"}, {"rate", "Hz"}};
  j["samples"] = e.report.samples;
  j["model"] = brief_json(e.report.rows[0].errors);
  j["baselines"] = baselines_json(e.report);
  j["verdict"] = e.report.verdict;
  j["rate_hz"] = e.rate_hz;
  j["estimated"] = e.train.model.provenance.estimated;
  j["proxy_source"] = e.train.model.provenance.proxy_source;
  j["features"] = to_string(e.train.model.model.features);
  j["train_seconds"] = e.train.model.provenance.stats.seconds;
  return j;
}

namespace {

// The scored samples with the best baseline's prediction beside them.
struct Curves {
  std::string baseline;
  std::vector<std::size_t> idx;  // test sample of each row
  std::vector<Vec3> base;        // best baseline's force per row, N
};

Curves curves_of(const RecordingsEval& e) {
  const auto names = baseline_names();
  std::size_t best = 1;
  for (std::size_t k = 2; k < e.report.rows.size(); ++k)
    if (e.report.rows[k].errors.re_median < e.report.rows[best].errors.re_median) best = k;
  const Baselines b = fit_baselines(e.train.set.p, e.train.set.v, e.train.set.f);
  const std::vector<Vec3> all_v = foaw_velocities(e.test.p, e.train.model.model.foaw);
  Curves c;
  c.baseline = names[best - 1];
  std::vector<Vec3> p, v;
  for (std::size_t i = 0; i < e.test.size(); ++i)
    if (e.scored[i]) p.push_back(e.test.p[i]), v.push_back(all_v[i]), c.idx.push_back(i);
  c.base = predict_baselines(b, p, v)[best - 1];
  return c;
}

}  // namespace

void write_recordings_csv(const std::string& path, const RecordingsEval& e) {
  const Curves c = curves_of(e);
  const std::string& bn = c.baseline;
  const std::vector<std::string> comments{"units: t s, forces N; mf measured, f the model, " + bn +
                                          " the best baseline (by RE median)"};
  CsvWriter w(path,
              {"t", "mfx", "mfy", "mfz", "fx", "fy", "fz", bn + "_fx", bn + "_fy", bn + "_fz"},
              comments);
  for (std::size_t k = 0; k < c.idx.size(); ++k) {
    const std::size_t i = c.idx[k];
    const Vec3 &m = e.test.f[i], &f = e.rendered[i], &g = c.base[k];
    w.row({e.test.t[i], m.x(), m.y(), m.z(), f.x(), f.y(), f.z(), g.x(), g.y(), g.z()});
  }
  w.commit();
}

void write_recordings_svg(const std::string& path, const RecordingsEval& e, double seconds) {
  const Curves c = curves_of(e);
  std::vector<std::size_t> rows;
  const double t0 = c.idx.empty() ? 0.0 : e.test.t[c.idx.front()];
  for (std::size_t k = 0; k < c.idx.size(); ++k)
    if (e.test.t[c.idx[k]] <= t0 + seconds) rows.push_back(k);
  constexpr double W = 900, H = 220, L = 60, R = 20, T = 30, B = 30;
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n",
      W, 3 * H);
  const char* colour[3] = {"black", "#1f77b4", "#ff7f0e"};
  const std::string label[3] = {"measured", "model", c.baseline};
  for (int a = 0; a < 3; ++a) {
    double lo = 1e300, hi = -1e300;
    const auto value = [&](std::size_t k, int s) {
      const std::size_t i = c.idx[k];
      return s == 0 ? e.test.f[i][a] : s == 1 ? e.rendered[i][a] : c.base[k][a];
    };
    for (std::size_t k : rows)
      for (int s = 0; s < 3; ++s) lo = std::min(lo, value(k, s)), hi = std::max(hi, value(k, s));
    if (!(hi > lo)) lo -= 1, hi += 1;
    const double y0 = a * H;
    const auto X = [&](double t) { return L + (t - t0) / seconds * (W - L - R); };
    const auto Y = [&](double f) { return y0 + H - B - (f - lo) / (hi - lo) * (H - T - B); };
    svg += fmt::format("<text x='{}' y='{}'>f{} (N), {:.2f}..{:.2f}; t (s) from {:.1f}</text>\n", L,
                       y0 + 18, "xyz"[a], lo, hi, t0);
    for (int s = 0; s < 3; ++s) {
      std::string pts;
      for (std::size_t k : rows)
        pts += fmt::format("{:.1f},{:.1f} ", X(e.test.t[c.idx[k]]), Y(value(k, s)));
      svg += fmt::format("<polyline fill='none' stroke='{}' stroke-width='1' points='{}'/>\n",
                         colour[s], pts);
      svg += fmt::format("<text x='{}' y='{}' fill='{}'>{}</text>\n", W - 260 + 90 * s, y0 + 18,
                         colour[s], label[s]);
    }
  }
  svg += "</svg>\n";
  write_file_atomic(path, svg);
}

}  // namespace inhap::eval
