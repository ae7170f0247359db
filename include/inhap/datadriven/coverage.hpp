// Coverage of a training recording: where the proxy went over the object and with which forces
// (thesis 4.5 trains on one free exploration; what it did not visit, the model extrapolates).
// Units: mm, N.
//
// The proxy positions q of the in-contact training samples are binned into cubic cells of
// `cell_mm`; each visited cell keeps its sample count and the largest |f| seen there. A query
// (q, |f|) lies inside the training support when a visited cell is within one cell of q's cell
// (so within about 1-2 cells of a training proxy) and |f| <= force_slack * (the largest |f| of
// those cells) + force_margin_n. A diagnostic for reports, not for the servo loop.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::datadriven {

struct CoverageParams {
  double cell_mm = 3.0;
  double force_slack = 1.2;     ///< relative headroom over the neighbourhood's largest |f|
  double force_margin_n = 0.5;  ///< absolute headroom, N
};

struct CoverageCell {
  std::array<int, 3> index{};  ///< cell index: floor(q / cell_mm)
  std::size_t samples = 0;
  double f_max = 0;  ///< largest |f| in the cell, N
};

class CoverageMap {
 public:
  CoverageMap() = default;
  /// Bins q (mm) with forces f (N); throws inhap::Error on sizes or a non-positive cell.
  CoverageMap(const std::vector<Vec3>& q, const std::vector<Vec3>& f, const CoverageParams& p = {});
  /// From cells (as read back from a file).
  CoverageMap(std::vector<CoverageCell> cells, const CoverageParams& p);

  const CoverageParams& params() const { return p_; }
  const std::vector<CoverageCell>& cells() const { return cells_; }
  /// Largest |f| of the visited cells next to q's cell (-1: none visited).
  double neighbourhood_force(const Vec3& q) const;
  /// Outside the support: no visited cell next to q's, or |f| beyond the neighbourhood's range
  /// (f_mag < 0: position only).
  bool outside(const Vec3& q, double f_mag = -1) const;

 private:
  void index_cells();
  static std::uint64_t key(const std::array<int, 3>& i);
  CoverageParams p_;
  std::vector<CoverageCell> cells_;
  std::unordered_map<std::uint64_t, std::size_t> lookup_;
};

/// An unvisited region of the coverage's (x, y) projection (the objects are height fields over
/// the table): a 4-connected set of empty cells inside the visited cells' bounding rectangle.
struct CoverageGap {
  double x_mm = 0, y_mm = 0;  ///< centroid of the empty cells' centres, mm
  std::size_t cells = 0;      ///< empty cells (cell_mm x cell_mm each)
};
/// The largest gaps (at most max_gaps, largest first; ties by position): where to explore more.
std::vector<CoverageGap> coverage_gaps(const CoverageMap& map, std::size_t max_gaps = 5);

/// "model.json" -> "model.coverage.csv" (other names get ".coverage.csv" appended).
std::string coverage_path_for(const std::string& model_path);
/// Writes the cells as CSV (x,y,z = cell centre mm, samples, f_max_n; cell size in a comment
/// and a column) atomically.
void write_coverage(const std::string& path, const CoverageMap& map);
/// Reads write_coverage's file; throws inhap::ParseError naming the file and line.
CoverageMap read_coverage(const std::string& path);

}  // namespace inhap::datadriven
