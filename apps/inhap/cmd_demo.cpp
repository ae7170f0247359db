// `inhap demo`: the whole thesis on the virtual lab in one run, with a summary table on stdout
// and a self-contained HTML report (OUT/report.html). Units: mm, N, s, N/mm.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "command.hpp"
#include "demo.hpp"
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

std::string fmt_num(double v, int digits) {
  return fmt::format("{:.{}f}", v, digits);
}

StepResult pending_step(const std::string& module, const std::vector<Row>& rows,
                        const std::vector<std::pair<std::string, std::string>>& figures) {
  StepResult r;
  r.available = false;
  r.note = fmt::format("not available in this build: needs {}", module);
  for (Row row : rows) {
    row.measured = "not available in this build";
    r.rows.push_back(row);
  }
  for (const auto& [id, title] : figures) r.figures.push_back({id, title, r.note, "pending", {}});
  return r;
}

namespace {

std::vector<Step> all_steps() {
  return {
      {"tap", "3.2", "Tap the dome (ground-truth contact)", step_tap},
      {"contacts", "3.2.2", "Contact points of five objects, threshold vs estimate", step_contacts},
      {"shape", "3.3", "Shape reconstruction",
       [](const Context&) {
         return pending_step(
             "its demo step (inhap/surface has landed; `inhap eval shape` computes Table 3.1 "
             "meanwhile)",
             {{"Hausdorff distance to truth, foam ball / ridged / hemisphere (mm)", "",
               "2.16 / 4.92 / 3.30 (Table 3.1)"},
              {"same with simple thresholding (mm)", "", "2.82 / 4.67 / 6.69 (Table 3.1)"}},
             {{"fig3_6", "Reconstructed meshes coloured by error (fig. 3.6-3.7)"},
              {"table3_1", "Table 3.1"}});
       }},
      {"palpation", "4.3", "Palpate the sliding yield surfaces",
       [](const Context&) {
         return pending_step("the chapter-4.3 friction module (inhap/friction)",
                             {{"sliding yield surface: stick/slip border found", "", "fig. 4.7"}},
                             {{"fig4_7", "u^p vs f_T with the found border (fig. 4.7)"},
                              {"fig4_8", "A sliding yield surface in 3D (fig. 4.8)"}});
       }},
      {"explore", "4.4.1", "Record free exploration of the dome", step_explore},
      {"force-model", "4.4", "Train the force model, validate on a held-out recording",
       [](const Context&) {
         return pending_step("the chapter-4.4 data-driven module (inhap/datadriven)",
                             {{"force RMSE x / y / z, dome (N)", "", "0.51 / 0.33 / 0.50"},
                              {"relative force error mean / median, dome", "", "0.260 / 0.211"}},
                             {{"fig4_12", "Measured vs rendered force per axis (fig. 4.11-4.12)"},
                              {"fig4_13", "Relative error vs force magnitude (fig. 4.13)"},
                              {"fig4_14", "Relative error box plots (fig. 4.14)"}});
       }},
      {"strokes", "5.3", "Strokes on the 25-model surface, TCA-MESH vs CBA", step_strokes},
      {"study", "5.4", "Virtual user study, TCA-MESH vs CBA", step_study},
      {"data", "5.3", "Strokes on the real data sets (--data)", step_data_strokes},
  };
}

void print_summary(const std::vector<StepRecord>& steps, double total) {
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
    fmt::print("{:<12} {:>6.1f} s  {}\n", s.step.name, s.result.seconds,
               s.result.available ? s.result.note : s.result.note);
  fmt::print("total {:.1f} s\n", total);
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
  std::filesystem::create_directories(o.out);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<StepRecord> done;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    fmt::print(stderr, "[demo] step {}/{}: {} (thesis {}): {}\n", i + 1, steps.size(), s.name,
               s.chapter, s.title);
    Context c{o, s.name};
    StepResult r = s.run(c);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    if (r.available) cli::progress(s.name, 1.0, 0);
    fmt::print(stderr, "[demo] {} {} in {:.1f} s\n", s.name,
               r.available ? "done" : "skipped (" + r.note + ")", r.seconds);
    done.push_back({s, std::move(r)});
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_report(o, web, done, total);
  print_summary(done, total);
  fmt::print("report: {}\n", (std::filesystem::path(o.out) / "report.html").string());
}

void register_demo(CLI::App& app) {
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "demo",
      "The whole thesis on the virtual lab: taps the dome (ch. 3), records free exploration\n"
      "(ch. 4), strokes the 25-model surface with TCA-MESH and CBA and runs a reduced virtual\n"
      "user study (ch. 5); with --data also strokes the bunny, CT head and AFM data. Prints a\n"
      "summary table (measured vs thesis) and writes OUT/report.html (self-contained, opens\n"
      "offline) plus each figure's data as OUT/*.csv / *.json. Steps whose module is not in\n"
      "this build are marked 'not available in this build'. Units: mm, N, s, N/mm.");
  cmd->add_option("--out,-o", o->out, "output folder")->capture_default_str();
  cmd->add_flag("--quick", o->quick, "shorter recordings and a smaller study (CI, < 2 min)");
  cmd->add_option("--data", o->data, "folder with bunny/, headsq/, afm-topography/")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--web-dir", o->web_dir,
                  "folder with the report template and node_modules (default: web/ of the "
                  "source tree, or INHAP_WEB_DIR)");
  cmd->add_option("--only", o->only,
                  "run only these steps (tap shape palpation explore "
                  "force-model strokes study data)")
      ->delimiter(',');
  cmd->add_option("--seed", o->seed, "seed of every random choice")->capture_default_str();
  cmd->callback([o] { run_demo(*o); });
}

}  // namespace
}  // namespace inhap::demo

INHAP_COMMAND(90, "demo", inhap::demo::register_demo);
