// One object of the shape study (thesis 3.3, Table 3.1), shared by `inhap eval shape` and the
// demo: the lab operator taps a scene's object, the surface is reconstructed from the estimated
// and from the thresholded contact points, and both are scored against the exact reference
// mesh; plus the tap coverage and pace. The program writes the files (points, meshes, JSON,
// CSV). Units: mm, N, s.
#pragma once

#include <cstdint>
#include <string>

#include "inhap/eval/progress.hpp"
#include "inhap/eval/shape_lab.hpp"

namespace inhap::eval {

struct ShapeObjectOptions {
  std::size_t taps = 200;
  std::uint64_t seed = 1;
  lab::Physics physics = lab::Physics::kBuiltin;
  lab::TapOptions tap;  ///< tap.whole_object: taps all over what a stylus reaches
  /// Comparison settings; `reachable_reference` is set by run_shape_object() when
  /// `score_reachable_part` (the reference -> reconstruction side then uses only the reference's
  /// reachable part).
  ShapeCompareOptions compare;
  bool score_reachable_part = true;
  std::size_t coverage_samples = 20000;  ///< tap_coverage() samples
  double coverage_radius_mm = 5.0;
  bool count_entry_sides = false;  ///< also run count_far_side_contacts()
  /// Whole-object taps (an even, blue-noise sampling): the reconstruction's alpha local to the
  /// spacing (ReconstructOptions::local_alpha) when the compare options leave it at 0.
  double whole_object_local_alpha = 1.0;
  /// Fractions: recording 0..0.8 ("taps"), then "reconstruct" at 0.8, "done" at 1.
  Progress progress;
};

struct ShapeObjectResult {
  TriMesh reference;                 ///< exact mesh of the object (reference_mesh())
  ShapeVariant estimate, threshold;  ///< from estimated / thresholded contact points
  double coverage = 0;               ///< share of the reachable surface near a tap
  double taps_per_minute = 0;
  double recording_s = 0;  ///< simulated length of the recording
  EntrySideCounts sides;   ///< when count_entry_sides
};

/// Records `options.taps` taps on `scene` and reconstructs and scores both variants. Throws
/// inhap::Error when the operator keeps missing.
ShapeObjectResult run_shape_object(const lab::Scene& scene, const ShapeObjectOptions& options);

}  // namespace inhap::eval
