// Force-model evaluation on the virtual lab (thesis 4.5), shared by `inhap eval forces` and
// `inhap demo`: record a free-exploration training run and a held-out test run with another seed
// (deep pushes, then a sliding-only last third, fig. 4.10), train the data-driven force model,
// replay the test run through the servo renderer and score it (eq. 4.27-4.31); optionally the
// same pipeline without the proxy (q = p) and with q held at the contact-onset point.
// Units: mm, N, s; step times in microseconds.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/estimate.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/metrics.hpp"
#include "inhap/eval/progress.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"

namespace inhap::eval {

/// Model settings measured best on the lab (docs/force-model.md): the training preset "best"
/// (local-frame features, location weight 5, bins blended over +-1 mm, tangentially mirrored
/// samples, stiffness and shear priors, friction-cone guard, the l1 fit to its certified optimum).
inline datadriven::TrainParams lab_train_params() {
  return datadriven::preset_params("best");
}

struct ForceLabOptions {
  std::string scene;  ///< built-in lab scene (planar, dome, ...)
  std::uint64_t train_seed = 1, test_seed = 2;
  datadriven::TrainParams params = lab_train_params();  ///< training settings (design included)
  bool quick = false;                                   ///< recordings 2x shorter (smoke test)
  bool baselines = true;       ///< also train the no-proxy and onset-proxy models
  std::string keep;            ///< folder for recordings and models ("": none)
  std::string progress_label;  ///< prefix of progress lines ("": the scene name)
  Progress progress;           ///< empty: silent
  /// Where q and contact come from: "estimated" (the friction module's proxy estimator with the
  /// sliding yield surfaces of a palpation of the scene, geometric contact with the palpated
  /// shape mesh), "recording" (surface, normals, friction and proxy estimated from the training
  /// recording alone, datadriven/estimate.hpp: no palpation cycles, no mesh) or "truth" (the
  /// lab's true proxy and contact flag).
  std::string proxy = "estimated";
  /// Logging rate of both recordings, Hz (servo and physics at 1 kHz; lab_files.hpp
  /// downsample_recording); the FOAW window is kept at 16 ms.
  double rate_hz = 1000;
  /// Training run: "coverage" (the explore operator's coverage-driven training mode) or
  /// "random" (the ordinary random exploration, as the test run).
  std::string train_operator = "coverage";
  lab::Physics physics = lab::Physics::kBuiltin;  ///< contact physics of the lab device
  double coverage_share = 0.65;   ///< lab::ExploreOptions::coverage_share of the training run
  double seconds_per_spot = 1.5;  ///< lab::ExploreOptions::seconds_per_spot
  /// lab::ExploreOptions::coverage_force_min/max (slides between spots and strokes), N
  double coverage_force_min = lab::ExploreOptions{}.coverage_force_min;
  double coverage_force_max = lab::ExploreOptions{}.coverage_force_max;
};

/// `eval forces --design thesis`: the thesis' model settings (sec. 4.4) for every setting whose
/// flag was not given (`given("--bins")` ...): 5 bins, no tail, weights 1 1 1, ridge 0, box margin
/// 0.1, hard bin switch, no tangent mirror, no priors, no friction cone. (The features,
/// ue_q_v unless given, are the caller's.)
void apply_thesis_settings(datadriven::TrainParams& p,
                           const std::function<bool(const std::string& flag)>& given);

/// Servo replay of a test recording: forces per sample, step latency of in-contact steps.
struct ForceReplay {
  std::vector<Vec3> forces;
  std::vector<double> step_us;
};

/// One model variant (with proxy, without, onset anchor): trained, replayed, scored.
struct ForceVariant {
  datadriven::ForceModel model;
  datadriven::ForceModelProvenance provenance;  ///< its training parameters and statistics
  ForceReplay replay;
  std::size_t train_contact = 0;
  datadriven::ForceErrors all, sliding;
};

/// How well the training run spans the test run (with-proxy model, scored test samples).
struct ForceSupport {
  std::size_t samples = 0;  ///< scored test samples in the track's contact
  /// Fractions of those samples with a normalised feature outside its bin's training range:
  /// any group, then per group (q - p, q, pdot).
  double outside_any = 0;
  std::array<double, 3> outside{};
  std::array<double, 3> sse_share_outside{};  ///< their share of the squared error per axis
  /// ||q - p|| (mm) and ||pdot|| (mm/s): p99 and max of the training and test contact samples,
  /// and the fraction of test samples beyond the training maximum.
  double train_depth_p99 = 0, train_depth_max = 0, test_depth_p99 = 0, test_depth_max = 0;
  double train_speed_p99 = 0, train_speed_max = 0, test_speed_p99 = 0, test_speed_max = 0;
  double beyond_depth = 0, beyond_speed = 0;
};

struct ForceLabResult {
  std::string name;
  lab::LabRecording train, test;
  datadriven::ProxyTrack train_track, test_track;
  double t_slide = 0;  ///< start of the sliding-only last third of the test run, s
  ForceVariant proxy;
  ForceVariant no_proxy, onset;     ///< empty models when !baselines
  datadriven::ForceErrors covered;  ///< proxy model on test samples the training run covered
  ForceSupport support;             ///< training vs test ranges
  std::vector<datadriven::SupportCheck> test_support;  ///< per test sample (bin -1: not checked)
  double palpation_s = 0;            ///< wall time of the palpation (estimated proxy), s
  std::size_t reference_points = 0;  ///< palpated reference points (estimated proxy)
  /// Estimated vs true proxy on the test run, where both are in contact: RMS of q_est - q_true
  /// (mm) and contact-flag agreement (fraction of samples); NaN with the true proxy.
  double proxy_rms_mm = 0, contact_agreement = 0;
  /// Proxy "recording": what was estimated from the training recording.
  std::optional<datadriven::RecordingEstimate> estimate;
};

/// Runs the whole evaluation of one scene. Throws inhap::Error (unknown scene, no contact).
ForceLabResult evaluate_forces_on_lab(const ForceLabOptions& options);

/// The training run's support as `model train` writes and `model eval` reports it: a
/// datadriven::CoverageMap of the training run's in-contact proxies and forces, the share of the
/// in-contact test samples outside it, and where the training run left the largest unvisited
/// areas (x, y projection: explore there).
struct ForceCoverage {
  double outside = 0;  ///< share of the in-contact test samples outside the training support
  std::vector<datadriven::CoverageGap> gaps;
  double cell_mm = 0;           ///< cell size of the map (a gap's area is cells * cell_mm^2)
  datadriven::CoverageMap map;  ///< the training recording's cells (proxy positions x largest |f|)
};
ForceCoverage training_coverage(const ForceLabResult& d);

/// The per-object report of `inhap eval forces` as the text of one JSON object: errors with and
/// without the proxy (all, sliding-only, covered), servo-step times, proxy vs truth, training vs
/// test support, the model's settings and the training coverage (training_coverage()).
std::string force_lab_json(const ForceLabResult& d);

}  // namespace inhap::eval
