// `inhap eval taps`: how the tapping operator covers a scene (any scene: built-in or a scene
// file, mesh scenes included): taps, taps per simulated minute, coverage of the reachable
// surface and the contact-point error. Units: mm, N, s.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/eval/lab_objects.hpp"
#include "inhap/eval/tap_study.hpp"
#include "inhap/lab/operators.hpp"

namespace {

using namespace inhap;
using namespace inhap::eval;
using inhap::cli::eval_group;

struct EvalTapsArgs {
  std::string scene, scene_file, recording, json_out;
  LabRecordRequest req;
  TapScoreOptions score;
};

void run_eval_taps(const EvalTapsArgs& a) {
  const lab::Scene scene = pick_scene(a.scene, a.scene_file);
  if (!a.json_out.empty()) check_output_path(a.json_out);
  lab::LabRecording rec;
  TapScoreOptions so = a.score;
  LabRecordRequest req = a.req;
  req.op = "tap";
  const lab::RecordSpec spec = lab_record_spec(req);
  so.probe_radius_mm = spec.probe.kind == lab::ProbeKind::kTip ? 0.0 : spec.probe.radius_mm;
  if (!a.recording.empty()) {
    rec.rec = read_recording(a.recording);
    rec.truth = lab::read_truth(lab::truth_path_for(a.recording));
  } else {
    rec = lab::record_scene(scene, spec, [&](const std::string&, double f, double) {
      cli::progress("eval taps " + scene.name, f, 0);
    });
  }
  const TapScore s = score_taps(rec, scene.object, so);
  fmt::print("{:<21} {:>6} {:>8} {:>8} {:>9} | {:>23} | {:>23} | {:>4}\n", "scene", "taps", "min",
             "taps/min", "coverage", "estimate mm med/p95", "threshold mm med/p95", "far");
  fmt::print(
      "{:<21} {:>6} {:>8.2f} {:>8.1f} {:>9.3f} | {:>11.3f} {:>11.3f} | {:>11.3f} {:>11.3f} | "
      "{:>4}\n",
      scene.name, s.taps, s.seconds / 60.0, s.taps_per_minute, s.coverage, s.estimate.median,
      s.estimate.p95, s.threshold.median, s.threshold.p95, s.sides.far_side_first_contacts);
  if (!a.json_out.empty()) {
    const nlohmann::json j = {{"scene", scene.name},
                              {"taps", s.taps},
                              {"seconds", s.seconds},
                              {"taps_per_minute", s.taps_per_minute},
                              {"coverage", s.coverage},
                              {"coverage_radius_mm", so.radius_mm},
                              {"matched", s.matched},
                              {"false_detections", s.false_detections},
                              {"estimate_mm", error_summary_json(s.estimate)},
                              {"threshold_mm", error_summary_json(s.threshold)},
                              {"far_side_first_contacts", s.sides.far_side_first_contacts}};
    write_file_atomic(a.json_out, j.dump(2) + "\n");
    fmt::print("wrote {}\n", a.json_out);
  }
}

void register_eval_taps(CLI::App& app) {
  auto a = std::make_shared<EvalTapsArgs>();
  a->req.op = "tap";
  a->req.probe = "tip";
  a->req.seconds = 600;
  auto* c = eval_group(app)->add_subcommand(
      "taps",
      "The tapping operator on any scene (built-in or a scene file, mesh scenes included): "
      "records\n"
      "it (or scores --recording) and prints the true taps, taps per simulated minute, coverage\n"
      "(share of the reachable surface, lab/reach.hpp, within --radius of a true contact point)\n"
      "and the contact-point error of true-contact estimation and of thresholding (median, p95,\n"
      "as `eval contacts`), and the far-side first contacts. Units: mm, N, s.");
  c->add_option("--scene", a->scene, "built-in scene (see `inhap lab scenes`)");
  c->add_option("--scene-file", a->scene_file, "scene JSON file");
  c->add_option("--recording", a->recording,
                "score this lab recording (and its .truth.csv) instead of recording one");
  c->add_option("--seconds", a->req.seconds, "simulated seconds to record")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  c->add_option("--seed", a->req.seed, "random seed of the lab")->capture_default_str();
  c->add_option("--probe", a->req.probe,
                "sphere (8 mm radius) | tip (with --recording: the probe it was recorded with)")
      ->capture_default_str()
      ->check(CLI::IsMember({"sphere", "tip"}));
  c->add_option("--region", a->req.region,
                "reachable: every surface a stylus reaches on the object as it rests (the thesis'\n"
                "protocol) | top: the scene's region seen from above (the top-cap protocol)")
      ->capture_default_str()
      ->check(CLI::IsMember({"reachable", "top"}));
  cli::add_physics_option(*c, a->req.physics, "lab contact physics: builtin | mujoco");
  c->add_option("--radius", a->score.radius_mm, "coverage radius, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  c->add_option("--json", a->json_out, "write the numbers as JSON");
  c->callback([a] { run_eval_taps(*a); });
}

}  // namespace

INHAP_COMMAND(81, "eval-taps", register_eval_taps);
