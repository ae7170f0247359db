// inhap eval tca: the virtual user study of thesis sec. 5.4 (16 participants, TCA-MESH and CBA,
// 5 trials each, shape and stiffness tasks) plus the servo-step timing on a 131,072-triangle
// height map (the experiment: eval/tca_study.hpp). Units: mm, N, N/mm, s; timings in
// microseconds.
#include <fmt/format.h>

#include <algorithm>
#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/tca_report.hpp"

namespace inhap::cli {
namespace {

struct EvalTcaOptions {
  eval::TcaStudyOptions study;  // seed, participants, trials, threads (flags)
  bool quick = false;
  std::string json, afm;
};

void run_eval_tca(EvalTcaOptions o) {
  eval::TcaStudyOptions& so = o.study;
  if (o.quick) so.participants = std::min(so.participants, 4), so.trials = std::min(so.trials, 2);
  so.progress = [](const std::string&, double f, double eta) { progress("eval tca", f, eta); };
  const eval::TcaEvalReport r = eval::run_tca_eval(so, o.afm);
  fmt::print("{}", eval::tca_eval_text(r));
  if (!o.json.empty()) write_file_atomic(o.json, eval::tca_eval_json(r).dump(2) + "\n");
}
void register_eval_tca(CLI::App& app) {
  auto opt = std::make_shared<EvalTcaOptions>();
  auto* cmd = eval_group(app)->add_subcommand(
      "tca",
      "Virtual user study of TCA-MESH vs CBA (thesis 5.4, fig. 5.10-5.11): simulated participants "
      "stroke\n"
      "and tap the 25 shape-stiffness models (5x5 on 140x140 mm, 39,200 triangles, layout "
      "reshuffled per trial)\n"
      "and label shape (bump/hole/flat) and stiffness (harder/softer/same). Also times the servo "
      "step on a\n"
      "131,072-triangle height map. Units: mm, N, N/mm, s; step times in microseconds.");
  cmd->add_option("--seed", opt->study.seed, "Seed of participants and layouts")
      ->capture_default_str();
  cmd->add_option("--participants", opt->study.participants, "Number of virtual participants")
      ->capture_default_str();
  cmd->add_option("--trials", opt->study.trials,
                  "Trials per session (one session per algorithm and task)")
      ->capture_default_str();
  cmd->add_option("--threads", opt->study.threads, "Worker threads (participants run in parallel)")
      ->capture_default_str();
  cmd->add_flag("--quick", opt->quick, "At most 4 participants x 2 trials");
  cmd->add_option("--json", opt->json, "Write the results as JSON to this file");
  cmd->add_option("--afm", opt->afm,
                  "Time the servo step on this WSxM .top topography instead of the synthetic map")
      ->check(CLI::ExistingFile);
  cmd->callback([opt] { run_eval_tca(*opt); });
}

}  // namespace

INHAP_COMMAND(60, "eval tca", register_eval_tca);

}  // namespace inhap::cli
