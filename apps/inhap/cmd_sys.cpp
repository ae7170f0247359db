// `inhap sys ...`: sliding yield surfaces (thesis 4.2-4.3): fit from palpation cycles, print
// Table 4.1, estimate the proxy of a recording. Units: mm, N, s, rad.
#include <fmt/format.h>

#include <memory>

#include "command.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/sys_model.hpp"

namespace {

using namespace inhap;
using namespace inhap::friction;

Vec3 parse_vec3(const std::string& s, const char* flag) {
  Vec3 v;
  if (std::sscanf(s.c_str(), "%lf,%lf,%lf", &v.x(), &v.y(), &v.z()) != 3 || !v.allFinite())
    throw Error(fmt::format("{}: expected x,y,z, got '{}'", flag, s));
  return v;
}

struct FitArgs {
  std::string cycles, mesh, out, tangent_reference = "1,0,0";
  BorderOptions border;
};

void print_summary(const SysModel& m) {
  fmt::print("{} reference points, f_N levels", m.points.size());
  for (double f : m.f_normal_levels) fmt::print(" {:g}", f);
  fmt::print(" N, {} directions\n", m.angles.size());
  fmt::print("{:>5} {:>9}  {}\n", "point", "f_N (N)",
             "f_T elastic limit per direction (N), * = no sliding seen");
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j) {
      fmt::print("{:>5} {:>9g} ", m.points[i].id, m.f_normal_levels[j]);
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const BorderResult& r = m.border(i, j, k).result;
        fmt::print(" {:6.3f}{}", r.f_limit, r.no_sliding ? "*" : " ");
      }
      fmt::print("\n");
    }
}

void run_fit(const FitArgs& a) {
  const std::vector<CycleRecord> cycles = read_cycles_csv(a.cycles);
  FitOptions opt;
  opt.border = a.border;
  opt.tangent_reference = parse_vec3(a.tangent_reference, "--tangent-reference");
  SysModel m = fit_sys(cycles, opt);
  write_sys_json(a.out, m);
  print_summary(m);
  fmt::print(stderr, "fitted {} cycles -> {}\n", cycles.size(), a.out);
}

struct TableArgs {
  std::string sys;
  int point = 0, dir = 0;
  double fn = 1.0;
};

void run_table(const TableArgs& a) {
  const SysModel m = read_sys_json(a.sys);
  const std::size_t i = m.point_index(a.point);
  const auto rows = table_4_1(m, a.point, a.fn, a.dir);
  std::size_t level = 0;
  for (std::size_t j = 1; j < m.f_normal_levels.size(); ++j)
    if (std::abs(m.f_normal_levels[j] - a.fn) < std::abs(m.f_normal_levels[level] - a.fn))
      level = j;
  const BorderResult& r = m.border(i, level, static_cast<std::size_t>(a.dir)).result;
  fmt::print(
      "Table 4.1: reference point {} at ({:.2f}, {:.2f}, {:.2f}) mm, f_N = {:g} N, "
      "direction {} ({:.1f} deg)\n",
      a.point, m.points[i].position.x(), m.points[i].position.y(), m.points[i].position.z(),
      m.f_normal_levels[level], a.dir, m.angles[a.dir] * 180.0 / 3.14159265358979);
  fmt::print("{:>8} {:>15} {:>15} {:>20}  {}\n", "f_T (N)", "||u^p_100|| mm", "||u^p_600|| mm",
             "||Du^p_plateau|| mm", "class");
  for (const TableRow& row : rows)
    fmt::print("{:>8.3f} {:>15.3f} {:>15.3f} {:>20.3f}  {}\n", row.f_tangential, row.u_short,
               row.u_long, row.growth, row.label ? "sliding" : "elastic");
  fmt::print(
      "elastic limit: f_T = {:.3f} N{}; u_elastic_limit: depth {:.3f} mm, tangential {:.3f} mm\n",
      r.f_limit, r.no_sliding ? " (no sliding seen: lower bound)" : "", r.depth, r.radius);
}

void register_sys(CLI::App& app) {
  auto* sys = app.add_subcommand(
      "sys",
      "Sliding yield surfaces (thesis 4.2-4.3): automatic palpation, elastic limits, proxy.\n"
      "Units: positions/displacements mm, forces N, times s, angles rad.");
  sys->require_subcommand(1);

  auto fa = std::make_shared<FitArgs>();
  auto* fit = sys->add_subcommand("fit",
                                  "Fit sliding yield surfaces from palpation cycles (CSV; one "
                                  "loading-unloading cycle per row,\n"
                                  "columns in docs/sliding-yield-surface.md) and write sys.json. "
                                  "Works on cycles recorded on a\n"
                                  "real device with your own code.");
  fit->add_option("cycles", fa->cycles, "palpation cycles CSV")
      ->required()
      ->check(CLI::ExistingFile);
  fit->add_option("--mesh", fa->mesh,
                  "shape mesh (PLY/OBJ) of the probe-centre surface (optional)");
  fit->add_option("--out,-o", fa->out, "sys.json to write")->required();
  fit->add_option("--tangent-reference", fa->tangent_reference,
                  "world direction whose projection onto the tangent plane is t_0 (x,y,z)")
      ->capture_default_str();
  fit->add_option("--weight-up", fa->border.weight_up,
                  "k-means weight of the normalised ||u^p_100|| feature")
      ->capture_default_str();
  fit->add_option("--weight-growth", fa->border.weight_growth,
                  "k-means weight of the normalised plateau growth ||u^p_600||-||u^p_100||")
      ->capture_default_str();
  fit->add_option("--noise-floor", fa->border.min_sliding_growth,
                  "plateau growth (mm) below which a step is not sliding")
      ->capture_default_str();
  fit->callback([fa] { run_fit(*fa); });

  auto ta = std::make_shared<TableArgs>();
  auto* table = sys->add_subcommand(
      "table",
      "Print Table 4.1 of a reference point: f_T, ||u^p_100||, ||u^p_600||, plateau growth (mm).");
  table->add_option("sys", ta->sys, "sys.json")->required()->check(CLI::ExistingFile);
  table->add_option("--point,-p", ta->point, "reference point id")->capture_default_str();
  table->add_option("--fn", ta->fn, "normal force level f_N (N; nearest level)")
      ->capture_default_str();
  table->add_option("--dir", ta->dir, "tangential direction index")->capture_default_str();
  table->callback([ta] { run_table(*ta); });
}

}  // namespace

INHAP_COMMAND(60, "sys", register_sys);
