// Contact-point error of a lab tapping recording (thesis fig. 3.4, `inhap demo`): simple
// thresholding vs the two-segment (knee) estimate of the true contact instant, against the
// lab's true contact points. Units: mm, N, s.
#pragma once

#include <vector>

#include "inhap/core/csv.hpp"
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

}  // namespace inhap::eval
