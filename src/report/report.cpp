// The report's step list, the context a step runs in and the helpers its figures share.
// Units: mm, N, s, N/mm.
#include "inhap/report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

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

}  // namespace inhap::report
