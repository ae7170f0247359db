// `inhap demo`: the whole thesis on the virtual lab in one run, with a summary table on stdout
// and a self-contained HTML report (OUT/report.html). Units: mm, N, s, N/mm.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>

#include "command.hpp"
#include "demo.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"

namespace inhap::demo {

void Context::progress(double fraction, const std::string& what) const {
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string label = what.empty() ? step : fmt::format("{}: {}", step, what);
  const double eta = fraction > 0 ? el * (1 - fraction) / fraction : 0;
  static const bool tty = ::isatty(2);
  if (tty) {
    cli::progress(label, std::min(fraction, 0.999), eta);
    return;
  }
  // Logs (CI): one line every 5 s at most.
  static auto last = std::chrono::steady_clock::now();
  const auto now = std::chrono::steady_clock::now();
  if (now - last < std::chrono::seconds(5)) return;
  last = now;
  fmt::print(stderr, "[{}] {:3.0f}% (eta {:.0f} s)\n", label, 100.0 * fraction, eta);
}

std::string Context::file(StepResult& r, const std::string& name) const {
  r.files.push_back(name);
  return (std::filesystem::path(options.out) / name).string();
}

double rnd(double v, int digits) {
  if (!std::isfinite(v)) return 0.0;
  const double s = std::pow(10.0, digits);
  return std::round(v * s) / s;
}

nlohmann::json series(const std::vector<double>& v, std::size_t stride, int digits) {
  nlohmann::json j = nlohmann::json::array();
  for (std::size_t i = 0; i < v.size(); i += std::max<std::size_t>(1, stride))
    j.push_back(rnd(v[i], digits));
  return j;
}

nlohmann::json line_trace(const nlohmann::json& x, const nlohmann::json& y, const std::string& name,
                          const std::string& colour, double width, const std::string& dash) {
  return {{"type", "scatter"},
          {"mode", "lines"},
          {"x", x},
          {"y", y},
          {"name", name},
          {"line", {{"color", colour}, {"width", width}, {"dash", dash}}}};
}

std::string fmt_num(double v, int digits) {
  return fmt::format("{:.{}f}", v, digits);
}

ForwardProgress::ForwardProgress(const Context& c,
                                 std::vector<std::pair<std::string, double>> phases, double from,
                                 double to)
    : c_(c), phases_(std::move(phases)), from_(from), to_(to), last_(from) {
  cli::set_progress_hook(
      [this](const std::string& what, double fraction, double) { on(what, fraction); });
}

ForwardProgress::~ForwardProgress() {
  cli::set_progress_hook({});
}

void ForwardProgress::on(const std::string& what, double fraction) {
  double total = 0, before = 0;
  int found = -1;
  for (std::size_t i = 0; i < phases_.size(); ++i) {
    if (found < 0 && what.find(phases_[i].first) != std::string::npos) {
      found = static_cast<int>(i);
      before = total;
    }
    total += phases_[i].second;
  }
  if (found >= 0 && total > 0) {
    const double f = std::clamp(fraction, 0.0, 1.0);
    last_ = from_ + (to_ - from_) * (before + phases_[std::size_t(found)].second * f) / total;
  }
  c_.progress(last_, what);
}

namespace {

std::vector<Step> all_steps() {
  return {
      {"tap", "3.2", "Tap the dome (ground-truth contact)", step_tap},
      {"contacts", "3.2.2", "Contact points of five objects, threshold vs estimate", step_contacts},
      {"shape", "3.3", "Shape reconstruction from tapped contact points", step_shape},
      {"palpation", "4.3", "Palpate the sliding yield surfaces of the dome", step_palpation},
      {"explore", "4.4.1", "Record free exploration of the dome", step_explore},
      {"force-model", "4.4-4.5", "Train the force model, validate on a held-out recording",
       step_force_model},
      {"strokes", "5.3", "Strokes on the 25-model surface, TCA-MESH vs CBA", step_strokes},
      {"study", "5.4", "Virtual user study, TCA-MESH vs CBA", step_study},
      {"data", "5.3", "Strokes on the real data sets: AFM, bunny, CT head (fig. 5.3, 5.7)",
       step_data_strokes},
  };
}

void print_summary(const std::vector<StepRecord>& steps, double total, double cpu) {
  std::size_t wq = 8, wm = 8;
  for (const auto& s : steps)
    for (const auto& r : s.result.rows) {
      wq = std::max(wq, r.quantity.size());
      wm = std::max(wm, r.measured.size());
    }
  fmt::print("{:<12} {:<{}}  {:<{}}  {}\n", "step", "quantity", wq, "measured", wm, "thesis");
  fmt::print("{}\n", std::string(12 + wq + wm + 14 + 20, '-'));
  for (const auto& s : steps)
    for (const auto& r : s.result.rows)
      fmt::print("{:<12} {:<{}}  {:<{}}  {}\n", s.step.name, r.quantity, wq, r.measured, wm,
                 r.thesis);
  fmt::print("\n");
  for (const auto& s : steps)
    fmt::print("{:<12} {:>6.1f} s wall {:>6.1f} s CPU  {}\n", s.step.name, s.result.seconds,
               s.result.cpu_seconds, s.result.note);
  fmt::print("total {:.1f} s wall, {:.1f} s CPU\n", total, cpu);
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
    Context c{o, s.name};
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
  print_summary(done, total, cpu);
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
