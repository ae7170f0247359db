// Recordings as a rig writes them: units by flag, a proxy estimated when the recording has none,
// and every evaluation beside the simple baselines (`inhap model train|eval`, `inhap eval
// recordings`).
//
// Units after conversion: positions mm, forces N, time s.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/datadriven/baselines.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/estimate.hpp"
#include "inhap/datadriven/metrics.hpp"

namespace inhap::eval {

/// The units a recording's t and p columns are in (forces are always N).
struct RecordingUnits {
  std::string time = "s";     ///< "s" or "ms"
  std::string length = "mm";  ///< "mm" or "m"
};

/// Reads a recording and converts its t and p to s and mm. Throws inhap::Error on an unknown
/// unit.
Recording read_recording_in(const std::string& path, const RecordingUnits& units);

/// Converts a recording's t and p (and proxy columns qx,qy,qz) from `units` to s and mm in place.
/// Throws inhap::Error on an unknown unit.
void convert_units(Recording& rec, const RecordingUnits& units);

/// True when the recording has the proxy columns <prefix>x,y,z.
bool has_proxy_columns(const Recording& rec, const std::string& prefix);

/// Contact of each sample from the measured force: |f| > threshold (N).
std::vector<char> force_contact(const Recording& rec, double threshold_n);

/// The proxy track the estimator gives: q on the estimated surface (the yield surfaces' return
/// mapping), the surface normal at q, geometric contact.
datadriven::ProxyTrack estimated_track(const Recording& rec, const friction::SysModel& sys,
                                       const TriMesh& surface);

/// FOAW window cap (samples) for a window of `window_s` seconds at sample period dt_s: at least 1,
/// at most kFoawMaxWindow - 1.
int foaw_window_samples(double window_s, double dt_s);

/// Errors of a model and of each baseline on the same in-contact test samples.
struct Scored {
  std::string name;
  datadriven::ForceErrors errors;
};
struct BaselineReport {
  std::vector<Scored> rows;  ///< the model first, then mean, knn_p, knn_pv
  std::size_t samples = 0;
  /// One line: whether the model beats the best baseline (per axis RMSE and RE median).
  std::string verdict;
};

/// Scores `rendered` (the model's forces on the test samples) and the baselines fitted on the
/// training samples (p, v, f) on the test samples (p, v, measured f), all restricted to `mask`.
BaselineReport score_with_baselines(const std::vector<Vec3>& rendered,
                                    const datadriven::TrainingSet& train, const Recording& test,
                                    const std::vector<Vec3>& test_v, const std::vector<char>& mask,
                                    const datadriven::BaselineParams& params = {});

/// The report's lines: one per row (RMSE x/y/z, RE median) and the verdict.
std::string baseline_text(const BaselineReport& r);

/// {"rmse_n": [x, y, z], "re_median": x, "re_mean": x, "n": n} of one row.
nlohmann::ordered_json brief_json(const datadriven::ForceErrors& e);
/// {"mean": brief, "knn_p": brief, "knn_pv": brief} (the rows after the model).
nlohmann::ordered_json baselines_json(const BaselineReport& r);

}  // namespace inhap::eval
