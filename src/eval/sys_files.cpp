// The sliding yield surfaces on files (`inhap sys ...`). Units: mm, N, s, rad.
#include "inhap/eval/sys_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "inhap/core/error.hpp"
#include "inhap/core/stats.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/mesh_rim.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/geometry/mesh_io.hpp"

namespace inhap::eval {

using namespace inhap::friction;

std::string sys_summary(const SysModel& m) {
  std::string s = fmt::format("{} reference points, f_N levels", m.points.size());
  for (double f : m.f_normal_levels) s += fmt::format(" {:g}", f);
  s += fmt::format(
      " N, {} directions; forces split at the {} normal\n", m.angles.size(),
      m.force_frame == ForceFrame::kAnchor ? "anchor (n_c)" : "probe (under the probe)");
  s += fmt::format("{:>5} {:>9}  {}\n", "point", "f_N (N)",
                   "f_T elastic limit per direction (N), e = extrapolated beyond the force range, "
                   "* = no sliding seen");
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j) {
      s += fmt::format("{:>5} {:>9g} ", m.points[i].id, m.f_normal_levels[j]);
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const BorderResult& r = m.border(i, j, k).result;
        s +=
            fmt::format(" {:6.3f}{}", r.f_limit, r.extrapolated ? "e" : (r.no_sliding ? "*" : " "));
      }
      s += "\n";
    }
  return s;
}

SysFitFileResult fit_sys_file(const SysFitFileOptions& o) {
  FitOptions opt;
  opt.border = o.border;
  opt.tangent_reference = o.tangent_reference;
  opt.load_damping = o.load_damping;
  opt.force_frame = force_frame_from_string(o.force_frame);
  std::unique_ptr<MeshSurface> shape;
  if (!o.mesh.empty()) {
    shape = std::make_unique<MeshSurface>(read_mesh(o.mesh), o.probe_radius_mm);
    opt.shape = shape.get();
  }
  const std::vector<CycleRecord> cycles =
      read_cycles_csv(o.cycles, CycleGeometry{opt.shape, opt.tangent_reference});
  return {fit_sys(cycles, opt), cycles.size()};
}

std::string table_4_1_text(const SysModel& m, int point, double fn, int dir) {
  const std::size_t i = m.point_index(point);
  const auto rows = table_4_1(m, point, fn, dir);
  std::size_t level = 0;
  for (std::size_t j = 1; j < m.f_normal_levels.size(); ++j)
    if (std::abs(m.f_normal_levels[j] - fn) < std::abs(m.f_normal_levels[level] - fn)) level = j;
  const BorderResult& r = m.border(i, level, static_cast<std::size_t>(dir)).result;
  std::string s = fmt::format(
      "Table 4.1: reference point {} at ({:.2f}, {:.2f}, {:.2f}) mm, f_N = {:g} N, "
      "direction {} ({:.1f} deg)\n",
      point, m.points[i].position.x(), m.points[i].position.y(), m.points[i].position.z(),
      m.f_normal_levels[level], dir, m.angles[dir] * 180.0 / 3.14159265358979);
  s += fmt::format("{:>8} {:>15} {:>15} {:>20}  {}\n", "f_T (N)", "||u^p_100|| mm",
                   "||u^p_600|| mm", "||Du^p_plateau|| mm", "class");
  for (const TableRow& row : rows)
    s += fmt::format("{:>8.3f} {:>15.3f} {:>15.3f} {:>20.3f}  {}\n", row.f_tangential, row.u_short,
                     row.u_long, row.growth, row.label ? "sliding" : "elastic");
  const char* note = r.extrapolated ? " (beyond the force range: extrapolated from a lower f_N)"
                     : r.no_sliding ? " (no sliding seen: lower bound)"
                                    : "";
  s += fmt::format("elastic limit: f_T = {:.3f} N{} (commanded load at the border {:.3f} N)\n",
                   r.f_limit, note, r.f_limit_load);
  s += fmt::format("u_elastic_limit: depth {:.3f} mm, tangential {:.3f} mm\n", r.depth, r.radius);
  return s;
}

void read_reference_points(const std::string& path, const MeshSurface& shape,
                           std::vector<Vec3>& points, std::vector<Vec3>& normals) {
  static constexpr std::string_view kXyz[] = {"x", "y", "z"};
  const CsvTable t = read_csv(path, kXyz);
  const bool has_n = t.find("nx") && t.find("ny") && t.find("nz");
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const Vec3 p(t.column("x")[i], t.column("y")[i], t.column("z")[i]);
    if (has_n) {
      const Vec3 n(t.column("nx")[i], t.column("ny")[i], t.column("nz")[i]);
      if (!(std::abs(n.norm() - 1.0) < 1e-6))
        throw IoError(path,
                      fmt::format("row {}: the normal (nx, ny, nz) must have length 1", i + 1));
      points.push_back(p);
      normals.push_back(n);
      continue;
    }
    Vec3 c, n;
    if (!shape.closest(p, c, n)) throw IoError(path, "the shape mesh has no closest point");
    points.push_back(c);
    normals.push_back(n);
  }
  if (points.empty()) throw IoError(path, "no reference points (expected rows x,y,z)");
}

void write_reference_points(const std::string& path, const std::vector<Vec3>& points,
                            const std::vector<Vec3>& normals) {
  CsvWriter w(path, {"x", "y", "z", "nx", "ny", "nz"},
              std::vector<std::string>{"reference points (probe centre, mm) and surface normals "
                                       "of a palpation: `sys palpate --device udp --refs`"});
  for (std::size_t i = 0; i < points.size(); ++i)
    w.row({points[i].x(), points[i].y(), points[i].z(), normals[i].x(), normals[i].y(),
           normals[i].z()});
  w.commit();
}

namespace {

// Marks the in-contact samples whose probe lies beyond the rim of the mesh.
std::vector<double> beyond_rim(const TriMesh& mesh, const Recording& rec, const ProxyColumns& c,
                               ProxyFileResult& r) {
  constexpr double kToleranceMm = 0.01;  // encoder quantisation and round-off
  const MeshRim rim(mesh);
  std::vector<double> flag(rec.size(), 0.0);
  if (!rim.has_rim()) return flag;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    if (!c.contact[i]) continue;
    const double d = rim.beyond_mm(rec.p[i]);
    if (d <= kToleranceMm) continue;
    flag[i] = 1.0;
    ++r.beyond;
    r.beyond_max_mm = std::max(r.beyond_max_mm, d);
  }
  return flag;
}

}  // namespace

ProxyFileResult add_proxy_columns(Recording& rec, const SysModel& sys, const TriMesh& mesh,
                                  double probe_radius_mm, bool creep) {
  const MeshSurface shape(mesh, probe_radius_mm);
  ProxyModel model{&sys, &shape};
  model.creep = creep;
  const ProxyColumns c = proxy_track(model, rec);
  ProxyFileResult r;
  std::vector<double> beyond = beyond_rim(mesh, rec, c, r);
  std::vector<double> qx(rec.size()), qy(rec.size()), qz(rec.size());
  // The estimator's contact flag and surface normal at q, so that `model train` needs no flags.
  std::vector<double> cf(rec.size()), nx(rec.size()), ny(rec.size()), nz(rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    qx[i] = c.q[i].x();
    qy[i] = c.q[i].y();
    qz[i] = c.q[i].z();
    cf[i] = c.contact[i] ? 1.0 : 0.0;
    const Vec3 n = c.contact[i] ? c.n[i] : Vec3::UnitZ();
    nx[i] = n.x(), ny[i] = n.y(), nz[i] = n.z();
  }
  r.contact = c.contact_count;
  r.sliding = c.sliding_count;
  rec.set_extra("qx", std::move(qx));
  rec.set_extra("qy", std::move(qy));
  rec.set_extra("qz", std::move(qz));
  if (!rec.find_extra("contact")) rec.set_extra("contact", std::move(cf));
  if (!rec.find_extra("nx")) {
    rec.set_extra("nx", std::move(nx));
    rec.set_extra("ny", std::move(ny));
    rec.set_extra("nz", std::move(nz));
  }
  rec.set_extra("beyond_mesh", std::move(beyond));
  return r;
}

nlohmann::json sys_lab_json(const std::string& name, const SysLabResult& res) {
  const ScenePalpation& r = res.palpation;
  const std::vector<double>&rel = res.limit_rel, &rel_measured = res.limit_rel_measured;
  const ProxyErrors &pe = res.proxy, &pr = res.proxy_rate_independent;
  nlohmann::json j;
  j["name"] = name;
  j["reference_points"] = r.sys.points.size();
  j["limit_rel_error"] = {{"median", quantile(rel, 0.5)}, {"max", quantile(rel, 1.0)}};
  j["proxy_error_mm"] = {{"median", quantile(pe.err, 0.5)}, {"p95", quantile(pe.err, 0.95)}};
  j["palpation_sim_hours"] = static_cast<double>(r.ticks) / 3.6e6;
  j["palpation_wall_s"] = r.wall_s;
  // Extras (documented in docs/sliding-yield-surface.md).
  j["palpation_wall_s_per_point"] = r.wall_s / static_cast<double>(r.sys.points.size());
  j["palpation_cpu_s"] = r.cpu_s;
  j["palpation_cpu_s_per_point"] = r.cpu_s / static_cast<double>(r.sys.points.size());
  j["force_frame"] = friction::to_string(r.sys.force_frame);
  j["cycles"] = r.cycles.size();
  j["limits"] = rel.size();
  j["limit_rel_error_measured"] = {{"median", quantile(rel_measured, 0.5)},
                                   {"max", quantile(rel_measured, 1.0)},
                                   {"count", rel_measured.size()}};
  j["proxy_error_mm_rate_independent"] = {{"median", quantile(pr.err, 0.5)},
                                          {"p95", quantile(pr.err, 0.95)}};
  j["proxy_contact_samples"] = pe.err.size();
  j["proxy_missed_contact_samples"] = pe.missed;
  j["exploration_s"] = res.exploration_s;
  return j;
}

std::string sys_lab_table(const nlohmann::json& objects) {
  std::string s;
  s += fmt::format("{:<8} {:>6} {:>14} {:>14} {:>16} {:>16} {:>10} {:>10}\n", "object", "points",
                   "limit err med", "limit err max", "proxy mm median", "proxy mm p95", "sim h",
                   "wall s/pt");
  for (const nlohmann::json& j : objects)
    s += fmt::format(
        "{:<8} {:>6} {:>14.3f} {:>14.3f} {:>16.3f} {:>16.3f} {:>10.2f} {:>10.2f}\n",
        j["name"].get<std::string>(), j["reference_points"].get<int>(),
        j["limit_rel_error"]["median"].get<double>(), j["limit_rel_error"]["max"].get<double>(),
        j["proxy_error_mm"]["median"].get<double>(), j["proxy_error_mm"]["p95"].get<double>(),
        j["palpation_sim_hours"].get<double>(), j["palpation_wall_s_per_point"].get<double>());
  s += fmt::format(
      "targets: limit error median <= 0.10; proxy median <= 0.3 mm, p95 <= 1.0 mm; "
      "<= 10 s wall per reference point\n");
  return s;
}

}  // namespace inhap::eval
