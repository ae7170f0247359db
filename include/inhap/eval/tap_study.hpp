// How well a tapping recording covers an object (`inhap eval taps`): true taps, taps per
// simulated minute, share of the reachable surface within a radius of a tap, and the contact
// module's contact-point error (true-contact estimate and plain thresholding) against the lab's
// true contact points. Works on any scene, built-in or a scene file (mesh scenes included).
// Units: mm, N, s.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "inhap/eval/contacts_lab.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

struct TapScoreOptions {
  double radius_mm = 5.0;       ///< coverage: a surface point within this of a tap is covered
  std::size_t samples = 20000;  ///< coverage: area-uniform surface samples (seeded)
  double eps = 0.2;             ///< contact threshold, N (as `eval contacts`)
  std::size_t window = 100;     ///< knee-fit window, samples (as `eval contacts`)
  /// The recording's probe radius (0: the sharp tip). A sphere's true contact point is its
  /// centre: coverage uses the surface point closest to it, over the surface the sphere reaches.
  double probe_radius_mm = 0.0;
};

struct TapScore {
  std::size_t taps = 0;  ///< true taps (contact episodes numbered by the truth)
  double seconds = 0;    ///< length of the recording, s
  double taps_per_minute = 0;
  double coverage = 0;      ///< share of the reachable surface within radius_mm of a tap
  std::size_t matched = 0;  ///< detected contacts matched to distinct true taps (estimate)
  std::size_t false_detections = 0;
  ErrorSummary estimate, threshold;  ///< contact-point error, mm
  EntrySideCounts sides;
};

/// The true contact point of each tap of a lab recording, in tap order (the first truth row of
/// each tap number).
std::vector<Vec3> true_tap_points(const lab::LabRecording& rec);

/// Scores a lab tapping recording of `object` (see the header comment).
TapScore score_taps(const lab::LabRecording& rec, const lab::SoftObject& object,
                    const TapScoreOptions& options = {});

}  // namespace inhap::eval
