// Contact-point error of a lab tapping recording (thesis fig. 3.4, `inhap demo`): simple
// thresholding vs the two-segment (knee) estimate of the true contact instant, against the
// lab's true contact points. Units: mm, N, s.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/eval/progress.hpp"
#include "inhap/lab/physics.hpp"
#include "inhap/lab/recorder.hpp"

namespace inhap::eval {

/// Probe centre at time `at` (s), linear between samples, mm. Needs >= 2 samples.
Vec3 position_at(const Recording& rec, double at);

struct TapErrors {
  std::vector<double> threshold, knee;  ///< mm, one per detected tap
};

/// Detects taps without the truth (|f| rising through 0.5 N, re-armed below 0.1 N), fits the knee
/// over the 100 ms before each crossing, and compares the threshold instant and the knee estimate
/// with the true contact point. (The demo's own hysteresis detector, moved here unchanged. It is
/// not the contact module's detector, which `inhap eval contacts` uses; switching would change
/// the demo's fig. 3.4 numbers and was left for a separate change.)
TapErrors tap_errors(const lab::LabRecording& lab);

/// Median, 95th percentile (linear between order statistics) and maximum of a sample; zeros
/// when empty.
struct ErrorSummary {
  double median = 0, p95 = 0, max = 0;
};
ErrorSummary summarize_errors(std::vector<double> v);

/// `inhap eval contacts` (thesis fig. 3.4) on one lab tapping object: the contact module's
/// detector with true-contact estimation and with plain thresholding, matched to the true taps.
struct ContactObjectOptions {
  std::size_t taps = 100;
  std::uint64_t seed = 1;
  double eps = 0.2;          ///< contact threshold, N
  std::size_t window = 100;  ///< knee-fit window, samples
  lab::Physics physics = lab::Physics::kBuiltin;
  Progress progress;  ///< while recording ("taps")
};

struct ContactObjectResult {
  std::string name;
  /// The physics cannot represent the object (MuJoCo): nothing recorded, `skipped_shape` names
  /// the shape type.
  bool skipped = false;
  std::string skipped_shape;
  double stiffness_n_per_mm = 0;  ///< median effective stiffness at 5 N under the taps
  std::size_t taps = 0;           ///< matched estimate contacts
  std::size_t false_detections = 0;
  ErrorSummary estimate, threshold;  ///< contact-point error, mm
};

/// Records `taps` taps on the built-in scene `scene` and scores both methods. Throws
/// inhap::Error for an unknown scene or when the operator keeps missing.
ContactObjectResult run_contact_object(const std::string& scene, const ContactObjectOptions& o);

}  // namespace inhap::eval
