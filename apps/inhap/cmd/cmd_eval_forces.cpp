// inhap eval forces: thesis sec. 4.5 on the virtual lab. For each object (planar, dome) record
// a free-exploration training run and a held-out test run with another seed (deep pushes and a
// sliding-only last third, fig. 4.10), train the data-driven force model, replay the test run
// through the servo renderer and report the errors of eq. 4.27-4.31, the training time and
// the servo-step latency; the same model trained without the proxy (q = p at contact onset,
// the pre-thesis approach) shows what the proxy buys on sliding.
// Units: mm, N, s; step times in microseconds.
//
// Proxy and contact (see src/eval/forces_lab.cpp): --proxy estimated (default) palpates the scene
// and runs the friction module's proxy estimator over both recordings; --proxy truth uses the lab's
// true proxy and contact flag. The JSON says which ("proxy_source", "contact_source"). The training
// run is the explore operator's coverage-driven mode unless --train-operator random.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/stats.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/metrics.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/datadriven/servo.hpp"
#include "inhap/eval/forces_lab.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "model_flags.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::datadriven;
using namespace inhap::eval;
using json = nlohmann::ordered_json;

struct EvalForcesOptions {
  std::string json_path, keep;
  std::vector<std::string> scenes{"planar", "dome"};
  std::uint64_t train_seed = 1, test_seed = 2;
  std::string design = to_string(TrainParams{}.design);
  std::string features = to_string(lab_train_params().features);
  TrainParams params = lab_train_params();
  bool quick = false, baselines = true;
  double coverage_share = 0.65, seconds_per_spot = 1.5;
  std::vector<double> coverage_force{lab::ExploreOptions{}.coverage_force_min,
                                     lab::ExploreOptions{}.coverage_force_max};
  std::string proxy = "estimated", train_operator = "coverage", physics = "builtin";
};

json evaluate_object(const EvalForcesOptions& o, const std::string& name) {
  ForceLabOptions fo;
  fo.scene = name;
  fo.train_seed = o.train_seed;
  fo.test_seed = o.test_seed;
  fo.params = o.params;
  fo.params.design = design_from_string(o.design);
  fo.params.features = feature_set_from_string(o.features);
  fo.quick = o.quick;
  fo.keep = o.keep;
  fo.proxy = o.proxy;
  fo.baselines = o.baselines;
  fo.coverage_share = o.coverage_share;
  fo.seconds_per_spot = o.seconds_per_spot;
  fo.coverage_force_min = o.coverage_force[0];
  fo.coverage_force_max = o.coverage_force[1];
  fo.train_operator = o.train_operator;
  fo.progress = cli::progress;
  fo.physics = lab::physics_from_string(o.physics);
  const ForceLabResult d = evaluate_forces_on_lab(fo);
  const ForceVariant& v = d.proxy;
  fmt::print(
      "{}: RMSE x/y/z {:.3f} {:.3f} {:.3f} N, median AE {:.3f} {:.3f} {:.3f} N, RE mean {:.3f} "
      "median {:.3f}; sliding-only RE median {:.3f} (no proxy {:.3f}, onset proxy {:.3f}); "
      "train {:.1f} s; step p50 {:.2f} us p99 {:.2f} us; proxy {} (palpation {:.1f} s); outside "
      "training range {:.3f} (SSE share {:.2f} {:.2f} {:.2f})\n",
      name, v.all.rmse[0], v.all.rmse[1], v.all.rmse[2], v.all.ae_axis_median[0],
      v.all.ae_axis_median[1], v.all.ae_axis_median[2], v.all.re_mean, v.all.re_median,
      v.sliding.re_median, d.no_proxy.sliding.re_median, d.onset.sliding.re_median,
      v.model.stats.seconds, quantile(v.replay.step_us, 0.5), quantile(v.replay.step_us, 0.99),
      d.train_track.proxy_source, d.palpation_s, d.support.outside_any,
      d.support.sse_share_outside[0], d.support.sse_share_outside[1],
      d.support.sse_share_outside[2]);
  return json::parse(force_lab_json(d));
}

void run_eval_forces(const EvalForcesOptions& o) {
  json out;
  out["units"] = {{"force", "N"}, {"time", "s"}, {"step", "us"}};
  const bool est = o.proxy == "estimated";
  out["physics"] = o.physics;
  out["proxy_source"] = est ? "estimated:sys" : "truth";
  out["contact_source"] = est ? "estimated:geometric" : "truth";
  out["note"] =
      "estimated: q, the normal at q and contact from the friction module's proxy estimator "
      "(sliding yield surfaces of a palpation of the scene, geometric contact with the palpated "
      "shape mesh); truth: the virtual lab's true proxy (anchor ax,ay,az) and contact flag; "
      "errors against the measured force on the truly-in-contact test samples; no_proxy = the "
      "same model trained on (p, pdot) only (q = p); onset_proxy = q held at the contact-onset "
      "position (u = p - p_c "
      "of earlier methods); sliding_only = last third of the test run (the explore operator's "
      "sliding-only passage); step_us = servo steps of the with-proxy model in contact";
  out["objects"] = json::array();
  for (const auto& s : o.scenes) out["objects"].push_back(evaluate_object(o, s));
  write_file_atomic(o.json_path, out.dump(1) + "\n");
  fmt::print("report -> {}\n", o.json_path);
}

/// --design thesis restores the thesis' model settings (sec. 4.4) unless given explicitly:
/// world-frame (q - p, q, pdot), 5 bins, no tail, equal weights, plain least squares, 10 %
/// clamping margin, hard bin switch.
void apply_thesis_defaults(EvalForcesOptions& o, const CLI::App& cmd) {
  if (!cmd.count("--features")) o.features = "ue_q_v";
  if (!cmd.count("--bins")) o.params.bins = 5;
  if (!cmd.count("--tail")) o.params.linear_tail = false;
  if (!cmd.count("--feature-weights")) o.params.feature_weights = {1.0, 1.0, 1.0};
  if (!cmd.count("--ridge")) o.params.ridge = 0.0;
  if (!cmd.count("--box-margin")) o.params.box_margin = 0.1;
  if (!cmd.count("--bin-blend")) o.params.bin_blend = 0.0;
  if (!cmd.count("--tangent-mirror")) o.params.tangent_mirror = false;
  if (!cmd.count("--stiffness-prior")) o.params.stiffness_prior = false;
  if (!cmd.count("--shear-prior")) o.params.shear_prior = false;
  if (!cmd.count("--friction-cone")) o.params.friction_cone = false;
}

// The lab runs behind the evaluation: proxy source, physics and the coverage training operator.
void add_lab_run_flags(CLI::App& cmd, EvalForcesOptions& o) {
  cmd.add_option("--proxy", o.proxy,
                 "estimated (palpate the scene, run the proxy estimator) or truth (the lab's true "
                 "proxy and contact)")
      ->capture_default_str()
      ->check(CLI::IsMember({"estimated", "truth"}));
  cli::add_physics_option(cmd, o.physics,
                          "Lab contact physics: builtin | mujoco (docs/lab-mujoco.md)");
  cmd.add_option("--train-operator", o.train_operator,
                 "Training run: coverage (grid of spots, every depth, slides between) or random "
                 "(the ordinary exploration, as the test run)")
      ->capture_default_str()
      ->check(CLI::IsMember({"coverage", "random"}));
  cmd.add_option("--coverage-share", o.coverage_share,
                 "Coverage training run: share of the run spent on the grid of spots")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--spot-seconds", o.seconds_per_spot,
                 "Coverage training run: planned seconds per spot (sets the grid spacing)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 10.0));
  cmd.add_option("--coverage-force", o.coverage_force,
                 "Coverage training run: force range of the slides between spots and of the "
                 "strokes, N (min max)")
      ->capture_default_str()
      ->expected(2)
      ->check(CLI::Range(0.1, 6.0));
}

void register_eval_forces(CLI::App& app) {
  auto o = std::make_shared<EvalForcesOptions>();
  auto* cmd = eval_group(app)->add_subcommand(
      "forces",
      "Data-driven force model on the virtual lab (thesis 4.5, fig. 4.10-4.14): train on a free-\n"
      "exploration recording, test on a held-out one (another seed; deep pushes, then sliding "
      "only),\n"
      "with and without the proxy; q from the proxy estimator (or the lab's truth).\n"
      "Units: forces N, times s, step latency us.");
  cmd->add_option("--json", o->json_path, "Report file")->required();
  cmd->add_option("--scenes", o->scenes, "Lab scenes to evaluate")
      ->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--train-seed", o->train_seed, "Seed of the training recording")
      ->capture_default_str();
  cmd->add_option("--test-seed", o->test_seed, "Seed of the test recording")->capture_default_str();
  cmd->add_option(
         "--design", o->design,
         "thesis (A~ M x N_bin, and the thesis' settings: features ue_q_v, 5 bins, no "
         "tail, weights 1 1 1, ridge 0, margin 0.1, no bin blend, unless given) or regression "
         "(A~ N_bin x M)")
      ->capture_default_str()
      ->check(CLI::IsMember({"thesis", "regression"}));
  cmd->add_option("--features", o->features,
                  "ue_q_v (q - p, q, pdot), p_v_q (eq. 4.1) or local (q - p, pdot and the force "
                  "in the surface frame at q)")
      ->capture_default_str()
      ->check(CLI::IsMember({"ue_q_v", "p_v_q", "local"}));
  cmd->add_option("--bins", o->params.bins, "Bins by ||q - p||")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--centers", o->params.centers, "M per bin")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--lambda-ratio", o->params.lambda_ratio, "lambda / ||A~^T f~||_inf")
      ->capture_default_str();
  cmd->add_option("--seed", o->params.seed, "k-means++ seed")->capture_default_str();
  cli::add_switch(*cmd, "tail", o->params.linear_tail, "Linear tail on every expansion");
  cmd->add_option(
      "--feature-weights", o->params.feature_weights,
      "Weights of the feature groups (q - p, q, pdot) after standardisation (default 1 5 0.5)");
  cmd->add_option("--bin-blend", o->params.bin_blend,
                  "Half-width of the blend band around bin edges, mm of ||q - p|| (0: hard switch)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  add_local_training_flags(*cmd, o->params, "default on");
  cmd->add_option("--ridge", o->params.ridge, "Relative Tikhonov term of the CG debiasing")
      ->capture_default_str();
  cmd->add_option("--box-margin", o->params.box_margin,
                  "Clamping box margin (fraction of the range)")
      ->capture_default_str();
  cmd->add_option("--threads", o->params.threads, "Training threads (0 = all cores)")
      ->capture_default_str();
  cmd->add_option("--keep", o->keep, "Folder to keep the recordings, truth and models in");
  add_lab_run_flags(*cmd, *o);
  cli::add_switch(*cmd, "baselines", o->baselines,
                  "Also train the no-proxy and onset-proxy models (off: their fields are null)");
  cmd->add_flag("--quick", o->quick, "Recordings 2x shorter (a smoke test, not the evaluation)");
  cmd->callback([o, cmd] {
    if (o->design == "thesis") apply_thesis_defaults(*o, *cmd);
    run_eval_forces(*o);
  });
}

}  // namespace

INHAP_COMMAND(91, "eval forces", register_eval_forces);

}  // namespace inhap::cli
