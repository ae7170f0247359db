// The virtual user study of thesis sec. 5.4 (TCA-MESH vs CBA on the 25 shape-stiffness models,
// shape and stiffness tasks) and the servo-step timing on a large height map, shared by
// `inhap eval tca` and `inhap demo`. Units: mm, N, N/mm, s; step times in microseconds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "inhap/eval/progress.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/rendering/experiment.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::eval {

struct TcaStudyOptions {
  std::uint64_t seed = 1;  ///< seed of participants and layouts
  int participants = 16;   ///< virtual participants (the thesis: 16)
  int trials = 5;          ///< trials per session, one session per algorithm and task (thesis: 5)
  int threads = 2;         ///< worker threads (participants run in parallel; results do not
                           ///< depend on it)
  Progress progress;       ///< "d of n trials"; empty: silent
};

struct TcaStudyResult {
  rendering::StudyConfig config;
  std::vector<rendering::TrialResult> trials;  ///< participant by participant, in schedule order
  rendering::StudySummary summary;
  long incomplete = 0;  ///< trials that ended before every model was labelled
  double study_s = 0;   ///< wall time of the study, s
};

/// Runs the study. Throws inhap::Error when participants or trials < 1.
TcaStudyResult run_tca_study(const TcaStudyOptions& options);

/// The study's four conditions (algorithm x task). Throws inhap::Error when one was not run.
struct TcaConditions {
  const rendering::ConditionSummary &tca_shape, &cba_shape, &tca_stiffness, &cba_stiffness;
};
TcaConditions tca_conditions(const rendering::StudySummary& summary);

/// Servo-step timing of one algorithm (microseconds per rendering::step call).
struct StepTiming {
  double p50 = 0, p99 = 0, max = 0;
  long steps = 0, contact_steps = 0;
};

/// The timing surface: the AFM-like synthetic map of `seed` (afm empty), or a WSxM file
/// (levelled) resampled to 257 x 257 over 100 mm with its height range scaled to 10 mm and
/// stiffness from height (1.0 N/mm at the lowest point to 0.2 N/mm at the highest) — a stand-in
/// for timing only, the file has no stiffness channel.
TriMesh tca_timing_surface(std::uint64_t seed, const std::string& afm);

/// Times rendering::step call by call while a force-regulated probe (1.5 N) strokes rows 10 mm
/// apart across the model at 40 mm/s (1 kHz).
StepTiming time_servo_steps(const rendering::Model& model, rendering::Algorithm algorithm);

}  // namespace inhap::eval
