// Thesis sec. 5.3 on real data (fig. 5.7): constant-force strokes through the regions the
// thesis marks on each data set, TCA-MESH vs CBA, with the shape distortion measured against
// the original, untranslated surface.
//
// Shape distortion: for every sliding sample in contact, the HIP's signed offset from the
// original surface along the local normal at its closest point (what the hand feels as a dip
// or a bump); RMS over a stroke with the stroke's mean offset removed (the mean is the steady
// penetration f / k, felt by neither algorithm as shape). Height jump: the largest change of
// that offset over `jump_window_mm` of travel where the stiffness under the HIP changes by at
// least `boundary_dk` (a stiffness boundary).
//
// Units: mm, N, N/mm, s; step times in microseconds.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/rendering/real_data.hpp"
#include "inhap/rendering/renderer.hpp"
#include "inhap/rendering/stroke.hpp"

namespace inhap::eval {

struct MetricOptions {
  double margin_mm = 1.0;       ///< samples nearer than this to either end are left out, mm
  double jump_window_mm = 2.0;  ///< travel over which a height jump is measured, mm
  double boundary_dk = 0.1;     ///< stiffness change (N/mm) that makes a window a boundary
};

/// The sliding samples of one stroke against the original surface.
struct SurfaceTrace {
  std::vector<double> along_mm;   ///< distance along the stroke, mm
  std::vector<double> offset_mm;  ///< HIP offset from the original surface along its normal, mm
  std::vector<double> k;          ///< stiffness of the original surface under the HIP, N/mm
};

/// Offsets of the HIPs of `samples` (a stroke from `from` to `to`) from `model`'s own,
/// untranslated surface: in contact and at least margin_mm from both ends.
SurfaceTrace surface_trace(const rendering::Model& model,
                           const std::vector<rendering::StrokeSample>& samples, const Vec2& from,
                           const Vec2& to, const MetricOptions& options = {});

struct StrokeMetrics {
  double distortion_rms_mm = 0;  ///< RMS of the offset, its mean removed, mm
  double mean_offset_mm = 0;     ///< the removed mean (the steady penetration), mm
  double max_jump_mm = 0;        ///< largest offset change across a stiffness boundary, mm
  long boundary_windows = 0;     ///< windows that counted as a stiffness boundary
  long samples = 0;
};

StrokeMetrics stroke_metrics(const SurfaceTrace& trace, const MetricOptions& options = {});

struct StrokeRun {
  std::string stroke;
  double speed_mm_s = 0;
  rendering::DataStroke line;
  std::vector<rendering::StrokeSample> samples_tca, samples_cba;  ///< only with keep_samples
  SurfaceTrace trace_tca, trace_cba;
  StrokeMetrics tca, cba;
};

struct StrokesConfig {
  std::vector<double> speeds_mm_s = {10.0, 20.0, 40.0};
  double force_n = 1.0;
  std::uint64_t seed = 1;
  MetricOptions metric;
  rendering::Params params;  ///< a_s = 0.05, a_t = 0.5 as in the thesis
  bool keep_samples = false;
};

/// The configuration of `eval strokes`: one speed (20 mm/s) when `quick`, else `speeds_mm_s`.
/// Error naming --speeds for a speed that is not > 0.
StrokesConfig strokes_config(const std::vector<double>& speeds_mm_s, double force_n,
                             std::uint64_t seed, bool quick);

struct DatasetResult {
  std::string name;
  std::size_t triangles = 0;
  int strokes = 0;
  /// Pooled over every stroke and speed: sqrt(sum n_i rms_i^2 / sum n_i), mm.
  double distortion_tca = 0, distortion_cba = 0;
  double jump_tca = 0, jump_cba = 0;  ///< largest over every stroke and speed, mm
  double step_p50_us = 0, step_p99_us = 0, step_max_us = 0;
  long timed_steps = 0;
  std::vector<StrokeRun> runs;
};

/// Every stroke of the data set at every speed with both algorithms; the servo step is timed by
/// replaying each stroke's HIP sequence through rendering::step (both algorithms).
DatasetResult run_dataset(const rendering::Model& model, const rendering::RealDataset& dataset,
                          const StrokesConfig& config = {});

/// {"datasets": [{"name", "triangles", "strokes", "distortion_rms_mm": {"tca", "cba"},
/// "max_jump_mm": {"tca", "cba"}, "step_us": {"p50", "p99"}}, ...]} plus per-stroke detail.
nlohmann::json to_json(const std::vector<DatasetResult>& results);

/// The table `eval strokes` prints: the header line, and one line per data set (triangles,
/// strokes, distortion and largest jump TCA / CBA in mm, servo step p50 / p99 in us).
std::string strokes_table_header();
std::string strokes_table_row(const DatasetResult& r);

}  // namespace inhap::eval
