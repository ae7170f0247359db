// The force envelope of a model's training data: no rendered force the data never showed.
//
// Units: mm, N.
//
// The training samples' force magnitudes are kept on a grid of proxy positions q (cells of
// `cell_mm`) and elastic displacements ||q - p|| (steps of `depth_step_mm`): cell (i, j, k,
// depth bin b) holds the largest |f| among the samples within one cell of it (the 3 x 3 x 3 block)
// and at most one depth step deeper than bin b (a cumulative maximum over depth, so the envelope
// never falls with depth). A rendered force is capped at
//     limit = (1 + margin_rel) envelope + margin_n
// where the state lies. Deeper than the block's deepest sample (bin D) the envelope grows as a
// Hertzian contact would, envelope(D) ((b + 1) / (D + 1))^1.5, so a push deeper than the
// training went at that place is not cut off; a cell with no training sample in its block, and a
// q outside the grid, take the same rule over the whole recording. One table lookup: servo-safe (no
// allocation, no exception).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

struct ForceEnvelope {
  double cell_mm = 8.0;        ///< grid cell of q, mm
  double depth_step_mm = 0.5;  ///< depth bin of ||q - p||, mm
  double margin_rel = 0.25;    ///< stated relative margin
  double margin_n = 0.25;      ///< stated absolute margin, N
  Vec3 origin = Vec3::Zero();  ///< low corner of the grid, mm
  std::array<int, 3> dims{0, 0, 0};
  int depth_bins = 0;
  /// dims[0] x dims[1] x dims[2] x depth_bins values (depth fastest, then x, y, z), N; NaN where
  /// the block held no sample (the global value of the depth bin applies).
  std::vector<float> f_max;
  std::vector<float> global;  ///< per depth bin: the largest |f| at most one step deeper, N
  /// Per cell: the deepest bin with a sample in its block (-1: none); global_deepest likewise.
  std::vector<std::int16_t> deepest;
  int global_deepest = -1;

  bool empty() const { return global.empty(); }
  /// The cap on |f| for proxy q and elastic displacement magnitude `key` = ||q - p|| (mm), N;
  /// +infinity when empty; 0 for a non-finite input.
  double limit(const Vec3& q, double key) const noexcept;
};

/// The envelope of training samples (proxy q, probe p, force f; same lengths). Empty when there
/// are no samples.
ForceEnvelope make_force_envelope(const std::vector<Vec3>& q, const std::vector<Vec3>& p,
                                  const std::vector<Vec3>& f, double cell_mm = 8.0,
                                  double depth_step_mm = 0.5);

/// Checks sizes and values; throws inhap::Error prefixed with `where`.
void validate_envelope(const ForceEnvelope& e, const std::string& where);

}  // namespace inhap::datadriven
