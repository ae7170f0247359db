// inhap demo: palpation of the dome's sliding yield surfaces (thesis 4.3, fig. 4.7-4.8) with
// the simulated device, elastic limits against the lab's true mu * f_N, and the proxy of a free
// exploration estimated with them against the lab's true tangential anchor. Units: mm, N, s.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/stats.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/report/report.hpp"
#include "inhap/report/strokes.hpp"

namespace inhap::report {
namespace {

const char* kLevelColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"};

nlohmann::json vline(double x, const std::string& colour, const std::string& dash) {
  return {{"type", "line"},
          {"x0", rnd(x)},
          {"x1", rnd(x)},
          {"yref", "paper"},
          {"y0", 0},
          {"y1", 1},
          {"line", {{"color", colour}, {"dash", dash}, {"width", 1.5}}}};
}

// Fig. 4.7: u^p after the short and the long plateau over f_T at the first reference point,
// direction 0, one colour per f_N, with the border found and the true mu * f_N.
Figure border_figure(const eval::ScenePalpation& p, double mu, std::string& csv) {
  const friction::SysModel& m = p.sys;
  Figure f{"fig4_7",
           "Plastic displacement u^p vs f_T with the elastic border found (fig. 4.7)",
           fmt::format("Reference point at the top of the dome, tangential direction 0: "
                       "tangential plastic displacement ||u^p|| after the 100 ms (dotted) and "
                       "600 ms (solid) plateau for each f_T step, one colour per normal force "
                       "f_N. Dashed: the elastic border found (k-means on the two features, "
                       "refined; a border beyond the device's force range, where no step slid, is "
                       "extrapolated from "
                       "the lower levels); dotted grey: the lab's true limit mu f_N (mu = {:.2f}).",
                       mu),
           "plotly",
           {}};
  f.spec["data"] = nlohmann::json::array();
  f.spec["layout"] = {{"xaxis", {{"title", {{"text", "tangential load f_T (N)"}}}}},
                      {"yaxis", {{"title", {{"text", "||u^p|| (mm)"}}}}},
                      {"shapes", nlohmann::json::array()}};
  for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j) {
    const friction::SysBorder& b = m.border(0, j, 0);
    const std::string colour = kLevelColours[j % 5];
    std::vector<double> ft, us, ul;
    for (const auto& s : b.steps) {
      ft.push_back(s.f_tangential);
      us.push_back(s.u_short);
      ul.push_back(s.u_long);
      csv += fmt::format("{:.3f},{:.4f},{:.5f},{:.5f},{:.4f},{:.4f}\n", b.f_normal, s.f_tangential,
                         s.u_short, s.u_long, b.result.f_limit_load, mu * b.f_normal);
    }
    const std::string level = fmt::format("f_N = {:g} N", b.f_normal);
    f.spec["data"].push_back({{"type", "scatter"},
                              {"mode", "lines+markers"},
                              {"x", series(ft)},
                              {"y", series(ul, 1, 4)},
                              {"name", level + ", 600 ms"},
                              {"line", {{"color", colour}}}});
    f.spec["data"].push_back({{"type", "scatter"},
                              {"mode", "lines+markers"},
                              {"x", series(ft)},
                              {"y", series(us, 1, 4)},
                              {"name", level + ", 100 ms"},
                              {"line", {{"color", colour}, {"dash", "dot"}}},
                              {"marker", {{"symbol", "circle-open"}}}});
    f.spec["layout"]["shapes"].push_back(vline(b.result.f_limit_load, colour, "dash"));
    f.spec["layout"]["shapes"].push_back(vline(mu * b.f_normal, "#7f7f7f", "dot"));
  }
  return f;
}

// Fig. 4.8: the sliding yield surface f_s of the first reference point in force space (x, y
// tangential, z = f_N), with the lab's true Coulomb circles mu f_N at the measured levels.
Figure yield_figure(const eval::ScenePalpation& p, double mu) {
  const friction::SysModel& m = p.sys;
  const friction::YieldSurface& fs = m.points[0].fs;
  const TriMesh mesh = fs.to_mesh(4);
  std::vector<double> level;
  for (const Vec3& v : mesh.positions) level.push_back(v.z());
  const double top = *std::max_element(level.begin(), level.end());
  Figure f{"fig4_8",
           "A sliding yield surface in 3D (fig. 4.8)",
           fmt::format("Sliding yield surface f_s at the top of the dome in force space (N): "
                       "horizontal axes the tangential load, vertical the normal load f_N; "
                       "{} directions x {} levels measured by palpation, linear in between and a "
                       "cone through the apex beyond. Black rings: the lab's true limit "
                       "mu f_N (mu = {:.2f}) at the measured levels. Colour: f_N. Drag to "
                       "rotate.",
                       fs.directions(), fs.levels(), mu),
           "three",
           {}};
  f.spec["meshes"] = nlohmann::json::array({colored_mesh_json(mesh, level, 0, top)});
  f.spec["lines"] = nlohmann::json::array();
  for (double fn : m.f_normal_levels) {
    nlohmann::json pts = nlohmann::json::array();
    for (int k = 0; k <= 72; ++k) {
      const double a = 2 * std::numbers::pi * k / 72;
      for (double v : {mu * fn * std::cos(a), mu * fn * std::sin(a), fn}) pts.push_back(rnd(v));
    }
    f.spec["lines"].push_back({{"points", pts}, {"color", "#000000"}});
  }
  f.spec["line_radius"] = rnd(0.01 * top, 3);
  f.spec["camera"] = {0.35, -1.0, 0.3};  // from the side: the cone opening upwards
  return f;
}

// Every elastic limit against the lab's mu at its reference point: relative errors of all and of
// the measured (not extrapolated) limits; returns them as CSV.
std::string limit_errors_csv(const eval::ScenePalpation& p, std::vector<double>& rel,
                             std::vector<double>& rel_measured) {
  const friction::SysModel& m = p.sys;
  std::string limits =
      "# units: positions mm, forces N; f_limit = elastic limit found, truth = lab mu * f_N\n"
      "point,x,y,z,f_normal,direction_rad,f_limit,truth,rel_error,extrapolated\n";
  for (const eval::LimitError& e : eval::limit_errors(p)) {
    rel.push_back(e.rel);
    if (e.measured) rel_measured.push_back(e.rel);
    const Vec3& x = m.points[e.point].position;
    limits += fmt::format("{},{:.3f},{:.3f},{:.3f},{:g},{:.4f},{:.4f},{:.4f},{:.4f},{}\n", e.point,
                          x.x(), x.y(), x.z(), m.f_normal_levels[e.level], m.angles[e.direction],
                          e.f_limit, e.truth, e.rel, e.extrapolated ? 1 : 0);
  }
  return limits;
}

}  // namespace

StepResult step_palpation(const Context& c) {
  StepResult r;
  const bool quick = c.options.quick;
  eval::ScenePalpationOptions po;
  po.scene = "dome";
  po.seed = c.options.seed;
  po.physics = lab::to_string(c.options.physics);
  po.quick = quick;
  if (quick) po.points = "rings:1,3:20";  // 4 reference points, f_N 1 and 3 N, 4 directions
  po.progress_label = "palpate";
  const eval::ScenePalpation p = [&] {
    ForwardProgress fw(c, {{"palpate", 1.0}}, 0.0, 0.8);
    po.progress = fw.callback();
    return eval::palpate_scene(po);
  }();
  const friction::SysModel& m = p.sys;
  friction::write_sys_json(c.file(r, "dome_sys.json"), m);

  std::vector<double> rel, rel_measured;
  write_file_atomic(c.file(r, "dome_elastic_limits.csv"), limit_errors_csv(p, rel, rel_measured));
  const double mu0 = p.scene.object.mu_at(m.points[0].position);
  std::string steps =
      "# units: f N, u^p mm; first reference point, direction 0 (fig. 4.7)\n"
      "f_normal,f_tangential,u_short,u_long,border_found,truth\n";
  r.figures.push_back(border_figure(p, mu0, steps));
  write_file_atomic(c.file(r, "fig4_7_border.csv"), steps);
  r.figures.push_back(yield_figure(p, mu0));

  // Proxy of a free exploration estimated with the fitted surfaces.
  lab::RecordSpec spec;
  spec.operator_name = "explore";
  spec.seconds = quick ? 10.0 : 30.0;
  spec.seed = c.options.seed + 3;
  spec.physics = c.options.physics;
  const lab::LabRecording lab =
      lab::record_scene(p.scene, spec, [&](const std::string&, double f, double) {
        c.progress(0.8 + 0.18 * f, fmt::format("explore {:.0f} s for the proxy", spec.seconds));
      });
  const std::vector<double> pe = eval::proxy_errors(p, lab, true).err;

  r.rows.push_back(
      {"palpation time per sliding yield surface (simulated min)",
       fmt::format("{:.1f} ({} points x {} f_N x {} dir.)",
                   static_cast<double>(p.ticks) / 6e4 / static_cast<double>(m.points.size()),
                   m.points.size(), m.f_normal_levels.size(), m.angles.size()),
       "about 60 (sec. 4.3.2)"});
  r.rows.push_back({"elastic limit vs true mu f_N: relative error median / max",
                    fmt::format("{:.3f} / {:.3f} ({} limits)", quantile(rel, 0.5),
                                quantile(rel, 1.0), rel.size()),
                    "- (target median <= 0.10)"});
  r.rows.push_back({"same, measured limits only (not extrapolated): median / max",
                    fmt::format("{:.3f} / {:.3f} ({} limits)", quantile(rel_measured, 0.5),
                                quantile(rel_measured, 1.0), rel_measured.size()),
                    "-"});
  r.rows.push_back(
      {"proxy q vs true anchor, free exploration: median / p95 (mm)",
       fmt::format("{:.3f} / {:.3f} ({} ticks)", quantile(pe, 0.5), quantile(pe, 0.95), pe.size()),
       "- (target <= 0.3 / <= 1.0)"});
  r.note = fmt::format("palpation {:.1f} s wall, {:.1f} s CPU", p.wall_s, p.cpu_s);
  return r;
}

}  // namespace inhap::report
