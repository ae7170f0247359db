// `inhap eval tca`: the virtual user study of thesis sec. 5.4 and the servo-step timing
// (tca_study.hpp) as one report, its text table and its JSON. Units: mm, N, N/mm, s; step
// times in microseconds.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "inhap/eval/tca_study.hpp"

namespace inhap::eval {

struct TcaEvalReport {
  TcaStudyOptions options;  ///< as run (participants and trials after --quick)
  TcaStudyResult study;
  std::size_t study_triangles = 0, timing_triangles = 0;
  StepTiming cba_t, tca_t;
};

/// Runs the study, then times the servo step of CBA and TCA-MESH on the timing surface of
/// options.seed (or the WSxM file `afm`).
TcaEvalReport run_tca_eval(const TcaStudyOptions& options, const std::string& afm);

/// The table `eval tca` prints: correct classifications beside the thesis', distortion, trial
/// times, confused models, the 12 predicted models, servo-step timing.
std::string tca_eval_text(const TcaEvalReport& r);

/// The report as JSON (keys documented in docs/tca-mesh.md).
nlohmann::json tca_eval_json(const TcaEvalReport& r);

}  // namespace inhap::eval
