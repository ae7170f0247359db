// The report's step list, the context a step runs in and the helpers its figures share.
// Units: mm, N, s, N/mm.
#include "inhap/report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>

#include "inhap/core/error.hpp"

namespace inhap::report {

void Context::progress(double fraction, const std::string& what) const {
  if (!progress_to) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string label = what.empty() ? step : fmt::format("{}: {}", step, what);
  const double eta = fraction > 0 ? el * (1 - fraction) / fraction : 0;
  progress_to(label, fraction, eta);
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
    : c_(c), phases_(std::move(phases)), from_(from), to_(to), last_(from) {}

eval::Progress ForwardProgress::callback() {
  return [this](const std::string& what, double fraction, double) { on(what, fraction); };
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

std::string summary_text(const std::vector<StepRecord>& steps, double total, double cpu) {
  std::string out;
  std::size_t wq = 8, wm = 8;
  for (const auto& s : steps)
    for (const auto& r : s.result.rows) {
      wq = std::max(wq, r.quantity.size());
      wm = std::max(wm, r.measured.size());
    }
  out +=
      fmt::format("{:<12} {:<{}}  {:<{}}  {}\n", "step", "quantity", wq, "measured", wm, "thesis");
  out += fmt::format("{}\n", std::string(12 + wq + wm + 14 + 20, '-'));
  for (const auto& s : steps)
    for (const auto& r : s.result.rows)
      out += fmt::format("{:<12} {:<{}}  {:<{}}  {}\n", s.step.name, r.quantity, wq, r.measured, wm,
                         r.thesis);
  out += fmt::format("\n");
  for (const auto& s : steps)
    out += fmt::format("{:<12} {:>6.1f} s wall {:>6.1f} s CPU  {}\n", s.step.name, s.result.seconds,
                       s.result.cpu_seconds, s.result.note);
  out += fmt::format("total {:.1f} s wall, {:.1f} s CPU\n", total, cpu);
  return out;
}

std::vector<Step> select_steps(const std::vector<std::string>& only) {
  std::vector<Step> steps = all_steps();
  for (const auto& name : only)
    if (std::none_of(steps.begin(), steps.end(), [&](const Step& s) { return s.name == name; })) {
      std::string names;
      for (const auto& s : steps) names += " " + s.name;
      throw Error(fmt::format("--only: expected one of{}, got '{}'", names, name));
    }
  if (!only.empty())
    std::erase_if(steps, [&](const Step& s) {
      return std::find(only.begin(), only.end(), s.name) == only.end();
    });
  return steps;
}

std::vector<StepRecord> run_steps(const Options& o, const std::vector<Step>& steps,
                                  const eval::Progress& progress, const eval::Progress& done,
                                  const std::function<void(const std::string&)>& log) {
  std::vector<StepRecord> records;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    log(fmt::format("[demo] step {}/{}: {} (thesis {}): {}\n", i + 1, steps.size(), s.name,
                    s.chapter, s.title));
    Context c{o, s.name, progress};
    const std::clock_t step_c0 = std::clock();
    StepResult r = s.run(c);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    r.cpu_seconds = static_cast<double>(std::clock() - step_c0) / CLOCKS_PER_SEC;
    if (r.available && done) done(s.name, 1.0, 0);
    log(fmt::format("[demo] {} {} in {:.1f} s ({:.1f} s CPU)\n", s.name,
                    r.available ? "done" : "skipped (" + r.note + ")", r.seconds, r.cpu_seconds));
    records.push_back({s, std::move(r)});
  }
  return records;
}

eval::Progress step_progress_line(bool tty, const eval::Progress& line) {
  if (tty)
    return [line](const std::string& what, double fraction, double eta) {
      line(what, std::min(fraction, 0.999), eta);
    };
  auto last =
      std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  return [last](const std::string& what, double fraction, double eta) {
    const auto now = std::chrono::steady_clock::now();
    if (now - *last < std::chrono::seconds(5)) return;
    *last = now;
    fmt::print(stderr, "[{}] {:3.0f}% (eta {:.0f} s)\n", what, 100.0 * fraction, eta);
  };
}

}  // namespace inhap::report
