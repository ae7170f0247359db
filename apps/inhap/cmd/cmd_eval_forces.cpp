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

#include <memory>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/forces_lab.hpp"
#include "inhap/eval/forces_report.hpp"
#include "inhap/lab/operators.hpp"
#include "model_flags.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::datadriven;
using namespace inhap::eval;
using ojson = nlohmann::ordered_json;

struct EvalForcesOptions {
  ForceLabOptions lab;  // seeds, params, keep, proxy, training run, baselines, quick (flags)
  std::string json_path;
  std::vector<std::string> scenes{"planar", "dome"};
  std::string design = to_string(TrainParams{}.design);
  std::string features = to_string(lab_train_params().features);
  std::vector<double> coverage_force{lab::ExploreOptions{}.coverage_force_min,
                                     lab::ExploreOptions{}.coverage_force_max};
  std::string physics = "builtin";
};

ojson evaluate_object(const EvalForcesOptions& o, const std::string& name) {
  ForceLabOptions fo = o.lab;
  fo.scene = name;
  fo.params.design = design_from_string(o.design);
  fo.params.features = feature_set_from_string(o.features);
  fo.coverage_force_min = o.coverage_force[0];
  fo.coverage_force_max = o.coverage_force[1];
  fo.progress = cli::progress;
  fo.physics = lab::physics_from_string(o.physics);
  const ForceLabResult d = evaluate_forces_on_lab(fo);
  fmt::print("{}\n", force_lab_summary(d));
  return ojson::parse(force_lab_json(d));
}

void run_eval_forces(const EvalForcesOptions& o) {
  ojson out = forces_report_head(o.physics, o.lab.proxy);
  out["objects"] = ojson::array();
  for (const auto& s : o.scenes) out["objects"].push_back(evaluate_object(o, s));
  write_file_atomic(o.json_path, out.dump(1) + "\n");
  fmt::print("report -> {}\n", o.json_path);
}

// The lab runs behind the evaluation: proxy source, physics and the coverage training operator.
void add_lab_run_flags(CLI::App& cmd, EvalForcesOptions& o) {
  cmd.add_option("--proxy", o.lab.proxy,
                 "estimated (palpate the scene, run the proxy estimator), recording (surface, "
                 "normals, friction\nand proxy estimated from the training recording alone, as "
                 "model train does without proxy\ncolumns) or truth (the lab's true proxy and "
                 "contact)")
      ->capture_default_str()
      ->check(CLI::IsMember({"estimated", "recording", "truth"}));
  cmd.add_option("--rate", o.lab.rate_hz,
                 "Logging rate of both recordings, Hz (servo and physics stay at 1 kHz; e.g. 66 "
                 "for a rig that logs\nlike the dVRK)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  cli::add_physics_option(cmd, o.physics,
                          "Lab contact physics: builtin | mujoco (docs/lab-mujoco.md)");
  cmd.add_option("--train-operator", o.lab.train_operator,
                 "Training run: coverage (grid of spots, every depth, slides between) or random "
                 "(the ordinary exploration, as the test run)")
      ->capture_default_str()
      ->check(CLI::IsMember({"coverage", "random"}));
  cmd.add_option("--coverage-share", o.lab.coverage_share,
                 "Coverage training run: share of the run spent on the grid of spots")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--spot-seconds", o.lab.seconds_per_spot,
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
  cmd->add_option("--train-seed", o->lab.train_seed, "Seed of the training recording")
      ->capture_default_str();
  cmd->add_option("--test-seed", o->lab.test_seed, "Seed of the test recording")
      ->capture_default_str();
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
  cmd->add_option("--bins", o->lab.params.bins, "Bins by ||q - p||")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--centers", o->lab.params.centers, "M per bin")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--lambda-ratio", o->lab.params.lambda_ratio, "lambda / ||A~^T f~||_inf")
      ->capture_default_str();
  cmd->add_option("--seed", o->lab.params.seed, "k-means++ seed")->capture_default_str();
  cli::add_switch(*cmd, "tail", o->lab.params.linear_tail, "Linear tail on every expansion");
  cmd->add_option(
      "--feature-weights", o->lab.params.feature_weights,
      "Weights of the feature groups (q - p, q, pdot) after standardisation (default 1 5 0.5)");
  cmd->add_option("--bin-blend", o->lab.params.bin_blend,
                  "Half-width of the blend band around bin edges, mm of ||q - p|| (0: hard switch)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  add_local_training_flags(*cmd, o->lab.params, "default on");
  cmd->add_option("--ridge", o->lab.params.ridge, "Relative Tikhonov term of the CG debiasing")
      ->capture_default_str();
  cmd->add_option("--box-margin", o->lab.params.box_margin,
                  "Clamping box margin (fraction of the range)")
      ->capture_default_str();
  cmd->add_option("--threads", o->lab.params.threads, "Training threads (0 = all cores)")
      ->capture_default_str();
  cmd->add_option("--keep", o->lab.keep, "Folder to keep the recordings, truth and models in");
  add_lab_run_flags(*cmd, *o);
  cli::add_switch(*cmd, "baselines", o->lab.baselines,
                  "Also train the no-proxy and onset-proxy models (off: their fields are null)");
  cmd->add_flag("--quick", o->lab.quick,
                "Recordings 2x shorter (a smoke test, not the evaluation)");
  cmd->callback([o, cmd] {
    auto given = [cmd](const std::string& flag) { return cmd->count(flag) > 0; };
    if (o->design == "thesis") {  // the thesis' settings unless given
      if (!given("--features")) o->features = "ue_q_v";
      apply_thesis_settings(o->lab.params, given);
    }
    // An estimated proxy trains as `model train` does without proxy columns: no tangent mirror
    // unless asked for (docs/real-recordings.md).
    if (o->lab.proxy == "recording" && !given("--tangent-mirror"))
      o->lab.params.tangent_mirror = false;
    run_eval_forces(*o);
  });
}

}  // namespace

INHAP_COMMAND(91, "eval forces", register_eval_forces);

}  // namespace inhap::cli
