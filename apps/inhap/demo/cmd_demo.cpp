// `inhap demo`: the whole thesis on the virtual lab in one run (the steps of inhap::report), with a
// summary table on stdout and a self-contained HTML report (OUT/report.html). This file parses
// the flags, selects the steps and commits their files. Units: mm, N, s, N/mm.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/report/report.hpp"

namespace inhap::demo {

using namespace inhap::report;

namespace {

void run_demo(const Options& o) {
  const std::string web = find_web_dir(o.web_dir);  // fail early when ./run setup is missing
  const std::vector<Step> steps = select_steps(o.only);
  // All outputs or none: OUT is created (or checked) before the steps, which take minutes, and
  // every file is renamed into place after the report, the last one, is written.
  OutputFolder folder(o.out);
  check_output_path((std::filesystem::path(o.out) / "report.html").string());
  OutputTransaction tx;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const std::vector<StepRecord> done =
      run_steps(o, steps, step_progress_line(::isatty(2), cli::progress), cli::progress,
                [](const std::string& line) { fmt::print(stderr, "{}", line); });
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  write_report(o, web, done, total, cpu);
  tx.commit();
  folder.keep();
  fmt::print("{}", summary_text(done, total, cpu));
  fmt::print("lab physics: {}\n", lab::to_string(o.physics));
  fmt::print("report: {}\n", (std::filesystem::path(o.out) / "report.html").string());
}

void register_demo(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "demo",
      "The whole thesis on the virtual lab: taps the dome and the Table 3.1 objects, estimates\n"
      "the contact points and reconstructs their shape (ch. 3); palpates the dome's sliding\n"
      "yield surfaces, records free exploration, trains the force model and validates it on a\n"
      "held-out recording (ch. 4); strokes the 25-model surface with TCA-MESH and CBA and runs\n"
      "a virtual user study, and strokes the AFM, bunny and CT head data of data/ (ch. 5).\n"
      "Prints a summary table (measured vs thesis) and writes OUT/report.html (self-contained,\n"
      "opens offline) plus each figure's data as OUT/*.csv / *.json (all files or none). About\n"
      "2-4 min on 2 cores; --quick about 20 s. Units: mm, N, s, N/mm.");
  cmd->add_option("--out,-o", o->out, "output folder")->capture_default_str();
  cmd->add_flag("--quick", o->quick,
                "shorter recordings, the dome only, fewer palpation points and a smaller study "
                "(the CI variant, about 20 s)");
  cmd->add_option("--data", o->data,
                  "folder with bunny/, headsq/, afm-topography/ (default: the project's data/)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--web-dir", o->web_dir,
                  "folder with the report template and node_modules (default: web/ of the "
                  "source tree, or INHAP_WEB_DIR)");
  cmd->add_option("--only", o->only,
                  "run only these steps (tap contacts shape palpation explore force-model "
                  "strokes study data)")
      ->delimiter(',');
  cmd->add_option("--seed", o->seed, "seed of every random choice")->capture_default_str();
  cmd->add_option_function<std::string>(
         "--physics", [o](const std::string& s) { o->physics = lab::physics_from_string(s); },
         "contact physics of the lab steps (tap contacts shape palpation explore force-model): "
         "builtin | mujoco (docs/lab-mujoco.md; objects MuJoCo cannot represent are skipped); "
         "strokes, study and data use inhap's renderers, not the lab")
      ->check(CLI::IsMember({"builtin", "mujoco"}))
      ->default_str("builtin");
  cmd->callback([o] { run_demo(*o); });
}

}  // namespace
}  // namespace inhap::demo

INHAP_COMMAND(90, "demo", inhap::demo::register_demo);
