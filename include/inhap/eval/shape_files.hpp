// Shape modeling by tapping (thesis ch. 3) on files: the reports `inhap shape contacts |
// reconstruct | compare` print and write. Units: mm, N, s.
#pragma once

#include <string>

#include "inhap/contact/tapping.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::eval {

/// "N taps (n by true-contact estimation, m by thresholding); force: ..." for `shape contacts`.
std::string contacts_summary(const TappingResult& r);

/// Points, outliers, mode, alpha (given or auto), mesh size and dropped pieces of a
/// reconstruction; `mode` as given on the command line, `by_directions` whether the shell's
/// normals were oriented by the contact directions.
std::string reconstruct_summary(const ReconstructReport& rep, const ReconstructOptions& o,
                                const std::string& mode, bool by_directions);

/// `shape compare`: the mesh files `a`, `b` and what was compared.
struct CompareReport {
  std::string a, b;
  CompareOptions options;
  CroppedSides cropped;
  bool auto_sides = false;  ///< the cropped sides were chosen automatically
  CompareResult result;
};
/// Distances both ways (max with where, mean, rms, samples), what was cropped, the ICP transform.
std::string compare_text(const CompareReport& r);
/// The same as JSON text (keys in docs/shape.md).
std::string compare_json(const CompareReport& r);

}  // namespace inhap::eval
