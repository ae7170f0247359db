// The thesis on the virtual lab as a report (what `inhap demo` runs): a sequence of steps; each
// step measures something (through inhap::eval), writes its data to OUT/*.csv / OUT/*.json,
// returns rows of the summary table (measured figure beside the thesis figure it answers) and
// figures (plotly / three.js JSON) for the self-contained HTML report. Units: mm, N, s, N/mm.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/eval/progress.hpp"
#include "inhap/lab/physics.hpp"

namespace inhap::report {

struct Options {
  std::string out = "out";
  std::string data;               ///< folder with bunny/, headsq/, afm-topography/ (optional)
  std::string web_dir;            ///< folder holding node_modules/ and the report template
  std::vector<std::string> only;  ///< run only these steps (empty: all)
  bool quick = false;
  std::uint64_t seed = 1;
  /// Contact physics of the lab steps (tap, contacts, shape, palpation, explore, force-model);
  /// the stroke, study and data steps render with inhap's own renderers and do not use it.
  lab::Physics physics = lab::Physics::kBuiltin;
};

/// One line of the summary table.
struct Row {
  std::string quantity;  ///< what was measured, with unit
  std::string measured;  ///< this run's value ("skipped: ..." when the step could not run)
  std::string thesis;    ///< the thesis figure it answers ("-" when the thesis has none)
};

/// One figure of the report. kind "plotly": spec = {data, layout}; kind "three": spec =
/// {meshes: [{positions, indices, colors}], lines: [{points, color}], line_radius (mm), camera
/// ([x, y, z] view direction in scene sizes, optional)}.
struct Figure {
  std::string id, title, caption, kind;
  nlohmann::json spec;
};

struct StepResult {
  bool available = true;  ///< false: skipped (e.g. no --data), `note` says why
  std::string note;       ///< why skipped, or a remark
  std::vector<Row> rows;
  std::vector<Figure> figures;
  std::vector<std::string> files;  ///< data files written (relative to OUT)
  double seconds = 0;              ///< wall time of the step
  double cpu_seconds = 0;          ///< CPU time of the step (all threads)
};

/// What a step gets: the options, the step's name and where its progress goes.
struct Context {
  const Options& options;
  std::string step;
  /// Receives ("step: what", fraction done, eta s) of the step; empty: silent.
  eval::Progress progress_to;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  /// Reports `fraction` of the step done, labelled "step: what", with the eta from the start.
  void progress(double fraction, const std::string& what = {}) const;
  /// OUT/name, and records name as written by the step.
  std::string file(StepResult& r, const std::string& name) const;
};

struct Step {
  std::string name, chapter, title;
  std::function<StepResult(const Context&)> run;
};

/// Turns the progress of a shared experiment (an inhap::eval call with several phases, e.g.
/// forces_lab and sys_lab) into this step's progress: give `callback()` as the call's `progress`.
/// `phases` are substrings of the call's labels with their share of the time, in the order they
/// run; fraction f of phase i maps to from + (to - from) * (shares before i + share_i * f) / (all
/// shares). A label matching no phase keeps the last fraction and shows its own label. Must
/// outlive the call.
class ForwardProgress {
 public:
  ForwardProgress(const Context& c, std::vector<std::pair<std::string, double>> phases,
                  double from = 0.0, double to = 1.0);
  ForwardProgress(const ForwardProgress&) = delete;
  ForwardProgress& operator=(const ForwardProgress&) = delete;
  eval::Progress callback();
  void on(const std::string& what, double fraction);

 private:
  const Context& c_;
  std::vector<std::pair<std::string, double>> phases_;
  double from_, to_, last_;
};

/// Every step in the order of the thesis (tap, contacts, shape, palpation, explore, force-model,
/// strokes, study, data).
std::vector<Step> all_steps();
/// all_steps() kept to the names in `only` (all when empty), in thesis order. Throws
/// inhap::Error "--only: expected one of ..., got 'X'" for an unknown name.
std::vector<Step> select_steps(const std::vector<std::string>& only);

// Steps (src/report/steps_*.cpp).
StepResult step_tap(const Context& c);
/// Fig. 3.4.
StepResult step_contacts(const Context& c);
/// Fig. 3.6-3.7, Table 3.1 (inhap/eval/shape_lab.hpp).
StepResult step_shape(const Context& c);
/// Fig. 4.7-4.8 (inhap/eval/sys_lab.hpp).
StepResult step_palpation(const Context& c);
StepResult step_explore(const Context& c);
/// Fig. 4.11-4.14 (inhap/eval/forces_lab.hpp).
StepResult step_force_model(const Context& c);
StepResult step_study(const Context& c);
StepResult step_strokes(const Context& c);
StepResult step_data_strokes(const Context& c);

// Helpers shared by the steps.
/// Rounds to `digits` decimals (keeps the report's JSON small).
double rnd(double v, int digits = 3);
/// Every `stride`-th element of v, rounded.
nlohmann::json series(const std::vector<double>& v, std::size_t stride = 1, int digits = 3);
std::string fmt_num(double v, int digits = 2);
/// A plotly line trace (x, y already series()).
nlohmann::json line_trace(const nlohmann::json& x, const nlohmann::json& y, const std::string& name,
                          const std::string& colour, double width = 1.5,
                          const std::string& dash = "solid");

// The HTML report (html_report.cpp).
struct StepRecord {
  Step step;
  StepResult result;
};
/// The summary table printed after a run: every row (step, quantity, measured, thesis), then
/// each step's wall and CPU time and note, then the totals.
std::string summary_text(const std::vector<StepRecord>& steps, double total_s, double cpu_s);
/// The demo's step progress: on a terminal (`tty`) the program's progress line `line` (the
/// fraction capped below 1, the step's end is reported once by run_steps), in logs (CI) one line
/// "[what] NN% (eta S s)" on stderr every 5 s at most.
eval::Progress step_progress_line(bool tty, const eval::Progress& line);

/// Runs the steps in order; each reports to `progress` (its Context's progress_to), `done` gets
/// (name, 1, 0) when a step ran, and `log` a line before and after each ("[demo] step i/n: ...",
/// "[demo] NAME done in ..."). Wall and CPU seconds of each step go into its result.
std::vector<StepRecord> run_steps(const Options& o, const std::vector<Step>& steps,
                                  const eval::Progress& progress, const eval::Progress& done,
                                  const std::function<void(const std::string&)>& log);
/// Folder with node_modules/plotly.js-dist-min etc.: --web-dir, INHAP_WEB_DIR, or web/ found
/// beside or above the executable / the working directory. Throws Error telling to run
/// ./run setup when the libraries are missing.
std::string find_web_dir(const std::string& given);
/// Writes OUT/report.html (self-contained), OUT/figures.json and OUT/summary.{csv,json}.
void write_report(const Options& o, const std::string& web_dir,
                  const std::vector<StepRecord>& steps, double total_seconds, double cpu_seconds);

}  // namespace inhap::report
