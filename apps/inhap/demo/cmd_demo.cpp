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

// The step's progress line: on a terminal the usual line, in logs (CI) one line every 5 s at
// most.
void step_progress(const std::string& label, double fraction, double eta) {
  static const bool tty = ::isatty(2);
  if (tty) {
    cli::progress(label, std::min(fraction, 0.999), eta);
    return;
  }
  static auto last = std::chrono::steady_clock::now();
  const auto now = std::chrono::steady_clock::now();
  if (now - last < std::chrono::seconds(5)) return;
  last = now;
  fmt::print(stderr, "[{}] {:3.0f}% (eta {:.0f} s)\n", label, 100.0 * fraction, eta);
}

void run_demo(const Options& o) {
  const std::string web = find_web_dir(o.web_dir);  // fail early when ./run setup is missing
  std::vector<Step> steps = all_steps();
  for (const auto& name : o.only)
    if (std::none_of(steps.begin(), steps.end(), [&](const Step& s) { return s.name == name; })) {
      std::string names;
      for (const auto& s : steps) names += " " + s.name;
      throw Error(fmt::format("--only: expected one of{}, got '{}'", names, name));
    }
  if (!o.only.empty())
    std::erase_if(steps, [&](const Step& s) {
      return std::find(o.only.begin(), o.only.end(), s.name) == o.only.end();
    });
  // All outputs or none: OUT is created (or checked) before the steps, which take minutes, and
  // every file is renamed into place after the report, the last one, is written.
  OutputFolder folder(o.out);
  check_output_path((std::filesystem::path(o.out) / "report.html").string());
  OutputTransaction tx;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  std::vector<StepRecord> done;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    fmt::print(stderr, "[demo] step {}/{}: {} (thesis {}): {}\n", i + 1, steps.size(), s.name,
               s.chapter, s.title);
    Context c{o, s.name, step_progress};
    const std::clock_t step_c0 = std::clock();
    StepResult r = s.run(c);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    r.cpu_seconds = static_cast<double>(std::clock() - step_c0) / CLOCKS_PER_SEC;
    if (r.available) cli::progress(s.name, 1.0, 0);
    fmt::print(stderr, "[demo] {} {} in {:.1f} s ({:.1f} s CPU)\n", s.name,
               r.available ? "done" : "skipped (" + r.note + ")", r.seconds, r.cpu_seconds);
    done.push_back({s, std::move(r)});
  }
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
