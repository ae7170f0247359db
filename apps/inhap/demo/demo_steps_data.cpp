// inhap demo: thesis sec. 5.3 on the real data sets (fig. 5.3, 5.7): the AFM protein-on-mica
// topography, the Stanford bunny and the CT head from the project's data/ folder (or --data
// DIR), loaded as the thesis did (real_data.hpp), stroked through the regions the thesis marks
// with TCA-MESH and CBA (eval/strokes.hpp). Units: mm, N, N/mm, s.
#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "demo.hpp"
#include "demo_strokes.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/strokes.hpp"
#include "inhap/rendering/real_data.hpp"

namespace inhap::demo {

namespace fs = std::filesystem;

namespace {

bool has_data(const fs::path& d) {
  return fs::exists(d / "afm-topography" / "sample_0.top") &&
         fs::exists(d / "bunny" / "bun_zipper.ply") && fs::exists(d / "headsq" / "quarter.nhdr");
}

}  // namespace

std::string find_data_dir(const std::string& given) {
  if (!given.empty()) {
    if (!has_data(given))
      throw Error(
          fmt::format("{}: expected afm-topography/sample_0.top, bunny/bun_zipper.ply and "
                      "headsq/quarter.nhdr in it",
                      given));
    return given;
  }
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("INHAP_DATA"); env && *env) candidates.push_back(env);
  std::array<char, 4096> buf{};
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n > 0) {
    fs::path d = fs::path(std::string(buf.data(), std::size_t(n))).parent_path();
    for (int up = 0; up < 5 && !d.empty(); ++up, d = d.parent_path()) {
      candidates.push_back(d / "data");
      candidates.push_back(d / "share/inhap/data");
    }
  }
  candidates.push_back(fs::current_path() / "data");
  for (const auto& c : candidates)
    if (has_data(c)) return c.string();
  return {};
}

namespace {

// The thesis' marked points (A-D) as labelled markers just above the original surface.
nlohmann::json marks_trace(const rendering::DataStroke& line, const std::vector<double>& u,
                           const std::vector<double>& h) {
  nlohmann::json mx = nlohmann::json::array(), my = nlohmann::json::array(),
                 mt = nlohmann::json::array();
  for (const auto& mk : line.marks) {
    double best = std::numeric_limits<double>::infinity(), hz = 0;
    for (std::size_t i = 0; i < u.size(); ++i)
      if (std::abs(u[i] - mk.along_mm) < best) {
        best = std::abs(u[i] - mk.along_mm);
        hz = h[i];
      }
    mx.push_back(rnd(mk.along_mm));
    my.push_back(rnd(hz + 0.5));
    mt.push_back(mk.label);
  }
  return {{"type", "scatter"},
          {"mode", "markers+text"},
          {"x", mx},
          {"y", my},
          {"text", mt},
          {"textposition", "top center"},
          {"name", "thesis' marked points"},
          {"marker", {{"color", "#d62728"}, {"size", 9}, {"symbol", "triangle-down"}}}};
}

// Fig. 5.7: heights along the stroke of the original surface and of HIP, IHIP, CIHIP for both
// algorithms, the stiffness under the stroke (right axis) and the thesis' marked points.
Figure profile_figure(const rendering::Model& model, const rendering::RealDataset& ds,
                      const eval::StrokeRun& run, const std::string& id) {
  const rendering::DataStroke& line = run.line;
  const double len = (line.to - line.from).norm();
  const Vec2 dir = (line.to - line.from) / len;
  const Box3 b = model.index().bounds();
  std::vector<double> u, h, k;
  for (double a = 0; a <= len + 1e-9; a += len / 400) {
    const Vec2 q = line.from + a * dir;
    const auto hit = model.index().first_hit(Vec3(q.x(), q.y(), b.max.z() + 1),
                                             Vec3(q.x(), q.y(), b.min.z() - 1));
    if (!hit) continue;
    u.push_back(a);
    h.push_back(hit->point.z());
    k.push_back(model.stiffness(*hit));
  }
  nlohmann::json data = nlohmann::json::array();
  data.push_back(line_trace(series(u), series(h), "original surface", "#000000", 2.5));
  auto add = [&](const std::vector<rendering::StrokeSample>& s, int which, const std::string& name,
                 const std::string& colour, const std::string& dash) {
    std::vector<double> x, z;
    std::size_t m = 0;
    for (const auto& e : s) m += e.contact;
    const std::size_t stride = std::max<std::size_t>(1, m / 600);
    std::size_t i = 0;
    for (const auto& e : s) {
      if (!e.contact || i++ % stride) continue;
      const double a = (Vec2(e.hip.x(), e.hip.y()) - line.from).dot(dir);
      if (a < 0.2 || a > len - 0.2) continue;
      const Vec3& p = which == 0 ? e.hip : which == 1 ? e.ihip : e.cihip;
      x.push_back(a);
      z.push_back(p.z());
    }
    data.push_back(line_trace(series(x), series(z), name, colour, 1.8, dash));
  };
  add(run.samples_tca, 0, "TCA-MESH HIP p", "#1f77b4", "solid");
  add(run.samples_tca, 1, "TCA-MESH IHIP q", "#d62728", "dot");
  add(run.samples_tca, 2, "TCA-MESH CIHIP q'", "#2ca02c", "dash");
  add(run.samples_cba, 0, "CBA HIP p", "#ff7f0e", "solid");
  add(run.samples_cba, 1, "CBA IHIP q", "#9467bd", "dot");
  nlohmann::json kt = line_trace(series(u), series(k), "stiffness under the stroke (N/mm)",
                                 "#7f7f7f", 1.2, "dashdot");
  kt["yaxis"] = "y2";
  data.push_back(kt);
  data.push_back(marks_trace(line, u, h));
  std::string marks;
  for (const auto& mk : line.marks) marks += fmt::format(" {}: {}.", mk.label, mk.what);
  Figure f{
      id,
      fmt::format("Fig. 5.7 on the {}: {} at {:.0f} mm/s", ds.name, line.name, run.speed_mm_s),
      fmt::format("Constant 1 N stroke; heights of the HIP p (what the hand feels), IHIP q and "
                  "CIHIP q' over the original surface; stiffness under the stroke on the right "
                  "axis.{} Shape distortion against the original surface (RMS, mean removed): "
                  "TCA-MESH {:.3f} mm, CBA {:.3f} mm; largest jump at a stiffness boundary: "
                  "TCA-MESH {:.3f} mm, CBA {:.3f} mm.",
                  marks, run.tca.distortion_rms_mm, run.cba.distortion_rms_mm, run.tca.max_jump_mm,
                  run.cba.max_jump_mm),
      "plotly",
      {}};
  f.spec["data"] = data;
  f.spec["layout"] = {{"xaxis", {{"title", {{"text", "distance along the stroke (mm)"}}}}},
                      {"yaxis", {{"title", {{"text", "height z (mm)"}}}}},
                      {"yaxis2",
                       {{"title", {{"text", "stiffness (N/mm)"}}},
                        {"overlaying", "y"},
                        {"side", "right"},
                        {"range", {0, 1.1}}}},
                      {"legend", {{"orientation", "h"}}}};
  return f;
}

void write_run_csv(const std::string& path, const eval::StrokeRun& run) {
  const std::vector<std::string> units = {
      "units: algorithm 0 = TCA-MESH, 1 = CBA; t s; p HIP, q IHIP, c CIHIP in mm; f N; k N/mm"};
  CsvWriter csv(path,
                {"algorithm", "t", "px", "py", "pz", "qx", "qy", "qz", "cx", "cy", "cz", "fz", "k",
                 "contact"},
                units);
  for (int a = 0; a < 2; ++a)
    for (const auto& e : a == 0 ? run.samples_tca : run.samples_cba)
      csv.row({double(a), e.time, e.hip.x(), e.hip.y(), e.hip.z(), e.ihip.x(), e.ihip.y(),
               e.ihip.z(), e.cihip.x(), e.cihip.y(), e.cihip.z(), e.force.z(), e.k,
               e.contact ? 1.0 : 0.0});
  csv.commit();
}

void dataset_rows(StepResult& r, const eval::DatasetResult& d) {
  r.rows.push_back(
      {fmt::format("{}: shape distortion RMS vs original surface, TCA-MESH / CBA (mm)", d.name),
       fmt::format("{:.3f} / {:.3f}", d.distortion_tca, d.distortion_cba),
       "fig. 5.7: TCA-MESH follows, CBA dips"});
  r.rows.push_back(
      {fmt::format("{}: largest jump at a stiffness boundary, TCA-MESH / CBA (mm)", d.name),
       fmt::format("{:.3f} / {:.3f}", d.jump_tca, d.jump_cba), "-"});
  r.rows.push_back({fmt::format("{}: servo step p50 / p99 ({} triangles, us)", d.name, d.triangles),
                    fmt::format("{:.1f} / {:.1f}", d.step_p50_us, d.step_p99_us), "1 kHz"});
}

}  // namespace

StepResult step_data_strokes(const Context& c) {
  StepResult r;
  const std::string dir = find_data_dir(c.options.data);
  if (dir.empty()) {
    r.available = false;
    r.note = "no data/ folder found (give --data DIR with bunny/, headsq/, afm-topography/)";
    r.rows.push_back({"strokes on AFM / bunny / CT head", "skipped: no data", "fig. 5.7"});
    return r;
  }
  eval::StrokesConfig cfg;
  cfg.seed = c.options.seed;
  cfg.keep_samples = true;
  if (c.options.quick) cfg.speeds_mm_s = {20.0};
  // Quick mode: the AFM and the bunny only (the CT head's isosurfaces, skin-bone distances and
  // CGAL simplification take most of the step's time).
  const std::array<std::string, 3> names = {"afm", "bunny", "ct-head"};
  const std::size_t count = c.options.quick ? 2 : 3;
  std::vector<eval::DatasetResult> results;
  for (std::size_t i = 0; i < count; ++i) {
    c.progress(double(i) / double(count), "loading " + names[i]);
    const fs::path d(dir);
    rendering::RealDataset ds =
        i == 0   ? rendering::load_afm((d / "afm-topography" / "sample_0.top").string())
        : i == 1 ? rendering::load_bunny((d / "bunny" / "bun_zipper.ply").string())
                 : rendering::load_head((d / "headsq" / "quarter.nhdr").string());
    if (c.options.quick) ds.strokes.resize(1);
    const rendering::Model model(ds.mesh, cfg.params);
    c.progress((double(i) + 0.3) / double(count), "strokes on " + names[i]);
    eval::DatasetResult res = eval::run_dataset(model, ds, cfg);
    // Fig. 5.7 profile: the first stroke at 20 mm/s (or the first speed).
    const eval::StrokeRun* shown = &res.runs.front();
    for (const auto& run : res.runs)
      if (run.stroke == ds.strokes.front().name && std::abs(run.speed_mm_s - 20.0) < 1e-9) {
        shown = &run;
        break;
      }
    r.figures.push_back(profile_figure(model, ds, *shown, "fig5_7_" + ds.name));
    write_run_csv(c.file(r, fmt::format("stroke_{}.csv", ds.name)), *shown);
    if (!c.options.quick)
      r.figures.push_back(mesh_figure(
          model.mesh(), "stiffness",
          {{shown->samples_tca, "#1f77b4"}, {shown->samples_cba, "#ff7f0e"}}, "fig5_3_" + ds.name,
          fmt::format("Fig. 5.3: the {} coloured by stiffness", ds.name),
          fmt::format("{} triangles, scaled into a 100 mm cube; stiffness {} (blue soft to red "
                      "hard). Lines: IHIP paths of the fig. 5.7 stroke (TCA-MESH blue, CBA "
                      "orange).",
                      model.mesh().num_triangles(), ds.stiffness_from)));
    dataset_rows(r, res);
    for (auto& run : res.runs) {  // the JSON keeps the metrics only
      run.samples_tca.clear();
      run.samples_cba.clear();
    }
    results.push_back(std::move(res));
  }
  if (count < names.size())
    r.rows.push_back({"ct-head: strokes", "skipped in --quick (the full run has it)", "fig. 5.7c"});
  write_file_atomic(c.file(r, "strokes_data.json"), eval::to_json(results).dump(2) + "\n");
  r.note = fmt::format("data from {}", dir);
  return r;
}

}  // namespace inhap::demo
