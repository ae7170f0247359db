// Train on one recording, render another, score beside the baselines (recordings_eval.hpp).
// Units: mm, N, s.
#include "inhap/eval/recordings_eval.hpp"

#include <fmt/format.h>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"

namespace inhap::eval {

using namespace inhap::datadriven;

RecordingsEval evaluate_recordings(const TrainFileOptions& o, const std::string& test) {
  RecordingsEval e;
  e.train = train_from_file(o);
  const double dt = e.train.model.model.foaw.dt_s;
  e.rate_hz = dt > 0 ? 1.0 / dt : 0.0;
  e.test = read_recording_in(test, o.units);
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
  e.report = score_with_baselines(e.rendered, e.train.set, e.test,
                                  foaw_velocities(e.test.p, e.train.model.model.foaw), e.scored);
  return e;
}

nlohmann::ordered_json recordings_json(const RecordingsEval& e, const std::string& test) {
  nlohmann::ordered_json j;
  j["train"] = e.train.model.provenance.recording_path;
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

void write_recordings_csv(const std::string& path, const RecordingsEval& e) {
  const auto names = baseline_names();
  std::size_t best = 1;
  for (std::size_t k = 2; k < e.report.rows.size(); ++k)
    if (e.report.rows[k].errors.re_median < e.report.rows[best].errors.re_median) best = k;
  const Baselines b = fit_baselines(e.train.set.p, e.train.set.v, e.train.set.f);
  std::vector<Vec3> p, v;
  const std::vector<Vec3> all_v = foaw_velocities(e.test.p, e.train.model.model.foaw);
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < e.test.size(); ++i)
    if (e.scored[i]) p.push_back(e.test.p[i]), v.push_back(all_v[i]), idx.push_back(i);
  const auto pred = predict_baselines(b, p, v);
  const std::vector<Vec3>& base = pred[best - 1];
  const std::string bn = names[best - 1];
  const std::vector<std::string> comments{"units: t s, forces N; mf measured, f the model, " + bn +
                                          " the best baseline (by RE median)"};
  CsvWriter w(path,
              {"t", "mfx", "mfy", "mfz", "fx", "fy", "fz", bn + "_fx", bn + "_fy", bn + "_fz"},
              comments);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const std::size_t i = idx[k];
    const Vec3 &m = e.test.f[i], &f = e.rendered[i], &g = base[k];
    w.row({e.test.t[i], m.x(), m.y(), m.z(), f.x(), f.y(), f.z(), g.x(), g.y(), g.z()});
  }
  w.commit();
}

}  // namespace inhap::eval
