// inhap eval strokes: thesis sec. 5.3 on the real data sets (fig. 5.7): constant-force strokes
// through the regions the thesis marks on the AFM topography, the Stanford bunny and the CT
// head, TCA-MESH vs CBA, with the shape distortion against the original surface, the largest
// height jump at a stiffness boundary and the servo step time. Units: mm, N, N/mm, s; step
// times in microseconds.
#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/strokes.hpp"
#include "inhap/rendering/real_data.hpp"
#include "inhap/report/strokes.hpp"

namespace inhap::cli {
namespace {

struct EvalStrokesOptions {
  std::string data, json;
  std::vector<double> speeds = {10.0, 20.0, 40.0};
  double force = 1.0;
  std::uint64_t seed = 1;
  bool quick = false;
};

void run_eval_strokes(EvalStrokesOptions o) {
  const std::string dir = report::find_data_dir(o.data);
  if (dir.empty())
    throw Error(
        "eval strokes: no data/ folder found; give --data DIR (with afm-topography/, "
        "bunny/, headsq/)");
  const eval::StrokesConfig cfg = eval::strokes_config(o.speeds, o.force, o.seed, o.quick);
  const std::vector<rendering::RealDataset> sets = rendering::load_real_datasets(dir);
  std::vector<eval::DatasetResult> results;
  fmt::print("{}", eval::strokes_table_header());
  for (const auto& ds : sets) {
    progress("eval strokes: " + ds.name, double(results.size()) / double(sets.size()), 0);
    const rendering::Model model(ds.mesh, cfg.params);
    results.push_back(eval::run_dataset(model, ds, cfg));
    fmt::print("{}", eval::strokes_table_row(results.back()));
  }
  fmt::print("(mm, mm, microseconds; data from {})\n", dir);
  if (!o.json.empty()) write_file_atomic(o.json, eval::to_json(results).dump(2) + "\n");
}

void register_eval_strokes(CLI::App& app) {
  auto opt = std::make_shared<EvalStrokesOptions>();
  auto* cmd = eval_group(app)->add_subcommand(
      "strokes",
      "Strokes on the real data sets (thesis 5.3, fig. 5.7): the AFM topography (131,072\n"
      "triangles, halo stiffness map), the Stanford bunny (confidence -> stiffness) and the CT\n"
      "head (57,608 triangles, stiffness from the skin-bone distance), each scaled into a 100 mm\n"
      "cube with stiffness up to 1.0 N/mm, stroked at 1 N through the regions the thesis marks\n"
      "with TCA-MESH and CBA. Prints per data set the shape distortion against the original\n"
      "surface (RMS, mm), the largest height jump at a stiffness boundary (mm) and the servo\n"
      "step p50/p99 (microseconds). Units: mm, N, N/mm, s.");
  cmd->add_option("--data", opt->data,
                  "folder with afm-topography/, bunny/, headsq/ (default: the project's data/)");
  cmd->add_option("--json", opt->json, "write the results as JSON to this file");
  cmd->add_option("--speeds", opt->speeds, "stroke speeds, mm/s")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--force", opt->force, "force the hand holds, N")->capture_default_str();
  cmd->add_option("--seed", opt->seed, "seed of the hand's tremor")->capture_default_str();
  cmd->add_flag("--quick", opt->quick, "one speed (20 mm/s)");
  cmd->callback([opt] { run_eval_strokes(*opt); });
}

}  // namespace

INHAP_COMMAND(62, "eval strokes", register_eval_strokes);

}  // namespace inhap::cli
