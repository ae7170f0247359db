// `inhap eval recordings`: train on one recording, render another, score the model beside the
// baselines (mean force, k-nearest neighbours on p and on (p, pdot)). Units: mm, N, s.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/eval/model_files.hpp"

namespace inhap::eval {

struct RecordingsEval {
  TrainFileResult train;
  Recording test;
  std::vector<Vec3> rendered;  ///< per test sample, N
  std::vector<char> scored;    ///< samples scored
  BaselineReport report;
  double rate_hz = 0;  ///< of the training recording (1 / median dt)
};

/// Trains with `o` (as `model train` does, nothing written), replays `test` (same units) and
/// scores. Throws inhap::Error / ParseError naming the file on bad input.
RecordingsEval evaluate_recordings(const TrainFileOptions& o, const std::string& test);

/// The same on recordings in memory (t s, p mm: convert_units), `o.recording` and `test_name`
/// naming them in messages (train_from_recording).
RecordingsEval evaluate_recordings(const Recording& train, Recording test,
                                   const TrainFileOptions& o, const std::string& test_name);

/// {"train", "test", "model": {"rmse_n", "re_median", ...}, "baselines": {...}, "verdict",
/// "rate_hz", "estimated": [...], "samples": n}. "train" is `train` when given, else the
/// training recording the model names.
nlohmann::ordered_json recordings_json(const RecordingsEval& e, const std::string& test,
                                       const std::string& train = {});

/// Measured against rendered force per axis for the model and the best baseline (by RE median),
/// as CSV rows: t, measured x/y/z, model x/y/z, baseline x/y/z (N), scored samples only.
void write_recordings_csv(const std::string& path, const RecordingsEval& e);

/// The same as a figure: three panels (x, y, z), force (N) against time (s) over the first
/// `seconds` of the test recording, measured (black), the model (blue) and the best baseline
/// (orange); SVG, written atomically.
void write_recordings_svg(const std::string& path, const RecordingsEval& e, double seconds = 20.0);

}  // namespace inhap::eval
