// `inhap sys ...`: sliding yield surfaces (thesis 4.2-4.3): fit from palpation cycles, print
// Table 4.1, estimate the proxy of a recording. Units: mm, N, s, rad.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <numbers>
#include <optional>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/mesh_rim.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/lab/sim_device.hpp"

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
  std::string cycles, mesh, out, tangent_reference = "1,0,0", force_frame = "auto";
  BorderOptions border;
  double probe_radius = 0.0, load_damping = 0.004;
};

void print_summary(const SysModel& m) {
  fmt::print("{} reference points, f_N levels", m.points.size());
  for (double f : m.f_normal_levels) fmt::print(" {:g}", f);
  fmt::print(" N, {} directions; forces split at the {} normal\n", m.angles.size(),
             m.force_frame == ForceFrame::kAnchor ? "anchor (n_c)" : "probe (under the probe)");
  fmt::print("{:>5} {:>9}  {}\n", "point", "f_N (N)",
             "f_T elastic limit per direction (N), e = extrapolated beyond the force range, * = no "
             "sliding seen");
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j) {
      fmt::print("{:>5} {:>9g} ", m.points[i].id, m.f_normal_levels[j]);
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const BorderResult& r = m.border(i, j, k).result;
        fmt::print(" {:6.3f}{}", r.f_limit, r.extrapolated ? "e" : (r.no_sliding ? "*" : " "));
      }
      fmt::print("\n");
    }
}

void run_fit(const FitArgs& a) {
  FitOptions opt;
  opt.border = a.border;
  opt.tangent_reference = parse_vec3(a.tangent_reference, "--tangent-reference");
  opt.load_damping = a.load_damping;
  opt.force_frame = force_frame_from_string(a.force_frame);
  std::unique_ptr<MeshSurface> shape;
  if (!a.mesh.empty()) {
    shape = std::make_unique<MeshSurface>(read_mesh(a.mesh), a.probe_radius);
    opt.shape = shape.get();
  }
  // Rows without ncx,ncy,ncz / tx,ty,tz take them from the mesh and the angle column.
  const std::vector<CycleRecord> cycles =
      read_cycles_csv(a.cycles, CycleGeometry{opt.shape, opt.tangent_reference});
  SysModel m = fit_sys(cycles, opt);
  write_sys_json(a.out, m);
  print_summary(m);
  fmt::print(stderr, "fitted {} cycles -> {}\n", cycles.size(), a.out);
}

struct TableArgs {
  std::string sys;
  int point = 0, dir = 0;
  double fn = 1.0;
  std::string gs_mesh, fs_mesh;
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
  const char* note = r.extrapolated ? " (beyond the force range: extrapolated from a lower f_N)"
                     : r.no_sliding ? " (no sliding seen: lower bound)"
                                    : "";
  fmt::print("elastic limit: f_T = {:.3f} N{} (commanded load at the border {:.3f} N)\n", r.f_limit,
             note, r.f_limit_load);
  fmt::print("u_elastic_limit: depth {:.3f} mm, tangential {:.3f} mm\n", r.depth, r.radius);
  OutputTransaction tx;
  if (!a.gs_mesh.empty()) write_mesh(a.gs_mesh, m.points[i].gs.to_mesh(4));
  if (!a.fs_mesh.empty()) write_mesh(a.fs_mesh, m.points[i].fs.to_mesh(4));
  tx.commit();
}

std::string stem_of(const std::string& out) {
  return out.size() > 5 && out.substr(out.size() - 5) == ".json" ? out.substr(0, out.size() - 5)
                                                                 : out;
}

struct PalpateArgs {
  eval::ScenePalpationOptions opt;
  std::string out;
  // --device udp: a real (or `inhap lab device`) device over the bridge
  std::string device, shape, refs;
  double probe_radius = 0, tool_mass = 0, connect = 60;
};

// Reference points for a device palpation: CSV columns x,y,z (probe centre, mm) and optionally
// nx,ny,nz; without normals the closest point of the shape mesh gives point and normal.
void read_refs(const std::string& path, const MeshSurface& shape, std::vector<Vec3>& points,
               std::vector<Vec3>& normals) {
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

void write_refs(const std::string& path, const std::vector<Vec3>& points,
                const std::vector<Vec3>& normals) {
  CsvWriter w(path, {"x", "y", "z", "nx", "ny", "nz"},
              std::vector<std::string>{"reference points (probe centre, mm) and surface normals "
                                       "of a palpation: `sys palpate --device udp --refs`"});
  for (std::size_t i = 0; i < points.size(); ++i)
    w.row({points[i].x(), points[i].y(), points[i].z(), normals[i].x(), normals[i].y(),
           normals[i].z()});
  w.commit();
}

// `sys palpate --device udp[:PORT]`: the protocol over the bridge, on a shape mesh the user gives.
void run_palpate_device(const PalpateArgs& a) {
  if (a.shape.empty() || a.refs.empty())
    throw Error("--device needs --shape MESH (probe-centre surface) and --refs REFS.csv");
  const std::string stem = stem_of(a.out);
  for (const std::string& path : {stem + ".cycles.csv", a.out}) check_output_path(path);
  const MeshSurface shape(read_mesh(a.shape), a.probe_radius);
  std::vector<Vec3> points, normals;
  read_refs(a.refs, shape, points, normals);
  haptics::BridgeOptions bo;
  const std::string& d = a.device;
  const std::optional<std::uint16_t> port = haptics::parse_udp_device(d);
  if (!port)
    throw Error(
        fmt::format("--device: expected udp or udp:PORT (PORT 1-65535), got {}", quote_token(d)));
  bo.port = *port;
  bo.info.tool_mass_kg = a.tool_mass;
  bo.info.probe_radius_mm = a.probe_radius;
  haptics::BridgeDevice dev(bo);
  fmt::print(stderr, "sys palpate: waiting for a device on udp 127.0.0.1:{}\n", dev.port());
  if (!dev.connect(a.connect))
    throw Error(fmt::format("no device joined within {:g} s", a.connect));
  const friction::PalpationConfig cfg = eval::palpation_config(a.opt.quick);
  const eval::DevicePalpation r =
      eval::palpate_points(dev, shape, points, normals, cfg, cli::progress, "sys palpate");
  dev.stop();
  const SysModel sys = eval::fit_palpation(r.cycles, shape, cfg);
  OutputTransaction tx;  // two outputs: both or neither
  write_cycles_csv(stem + ".cycles.csv", r.cycles);
  write_sys_json(a.out, sys);
  tx.commit();
  print_summary(sys);
  fmt::print(stderr,
             "{} cycles, {} ticks, bridge: {} time-outs, {} lost; wrote {}, {}.cycles.csv\n",
             r.cycles.size(), r.ticks, dev.stats().timeouts, dev.stats().lost, a.out, stem);
}

void run_palpate(PalpateArgs a) {
  if (!a.device.empty()) return run_palpate_device(a);
  a.opt.progress_label = "sys palpate";
  a.opt.progress = cli::progress;
  const std::string stem = stem_of(a.out);
  for (const std::string& path :
       {stem + ".cycles.csv", stem + ".shape.ply", stem + ".refs.csv", a.out})
    check_output_path(path);  // before the palpation, which takes minutes
  const eval::ScenePalpation r = eval::palpate_scene(a.opt);
  OutputTransaction tx;  // four outputs: all or none
  write_cycles_csv(stem + ".cycles.csv", r.cycles);
  write_mesh(stem + ".shape.ply", r.shape_mesh);
  write_refs(stem + ".refs.csv", r.points, r.normals);
  write_sys_json(a.out, r.sys);
  tx.commit();
  print_summary(r.sys);
  fmt::print(
      stderr,
      "{} cycles, {:.2f} simulated hours, {:.1f} s wall ({:.1f} s per point, {:.1f} s CPU)\n",
      r.cycles.size(), r.ticks / 3.6e6, r.wall_s, r.wall_s / r.points.size(), r.cpu_s);
  fmt::print(stderr, "wrote {}, {}.cycles.csv, {}.shape.ply, {}.refs.csv\n", a.out, stem, stem,
             stem);
}

struct ProxyArgs {
  std::string sys, mesh, rec, out;
  double probe_radius = 0.0;
  bool no_creep = false;
};

/// In-contact samples whose probe lies beyond the rim of the shape mesh (column beyond_mesh).
struct BeyondRim {
  std::vector<double> flag;
  std::size_t count = 0;
  double max_mm = 0;
};

BeyondRim beyond_rim(const TriMesh& mesh, const Recording& rec, const ProxyColumns& c) {
  constexpr double kToleranceMm = 0.01;  // encoder quantisation and round-off
  const MeshRim rim(mesh);
  BeyondRim b;
  b.flag.assign(rec.size(), 0.0);
  if (!rim.has_rim()) return b;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    if (!c.contact[i]) continue;
    const double d = rim.beyond_mm(rec.p[i]);
    if (d <= kToleranceMm) continue;
    b.flag[i] = 1.0;
    ++b.count;
    b.max_mm = std::max(b.max_mm, d);
  }
  return b;
}

void run_proxy(const ProxyArgs& a) {
  const SysModel sys = read_sys_json(a.sys);
  const TriMesh mesh = read_mesh(a.mesh);
  const MeshSurface shape(mesh, a.probe_radius);
  Recording rec = read_recording(a.rec);
  ProxyModel model{&sys, &shape};
  model.creep = !a.no_creep;
  const ProxyColumns c = proxy_track(model, rec);
  BeyondRim beyond = beyond_rim(mesh, rec, c);
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
  const std::size_t contact = c.contact_count, sliding = c.sliding_count;
  rec.set_extra("qx", std::move(qx));
  rec.set_extra("qy", std::move(qy));
  rec.set_extra("qz", std::move(qz));
  if (!rec.find_extra("contact")) rec.set_extra("contact", std::move(cf));
  if (!rec.find_extra("nx")) {
    rec.set_extra("nx", std::move(nx));
    rec.set_extra("ny", std::move(ny));
    rec.set_extra("nz", std::move(nz));
  }
  rec.set_extra("beyond_mesh", std::move(beyond.flag));
  write_recording(a.out, rec);
  fmt::print(stderr,
             "{} rows: {} in contact, {} with the proxy sliding, {} beyond the mesh rim -> {}\n",
             rec.size(), contact, sliding, beyond.count, a.out);
  if (beyond.count > 0)
    fmt::print(stderr,
               "inhap: warning: {} of {} in-contact samples ({:.1f} %) lie beyond the rim of the "
               "shape mesh {} (up to {:.2f} mm; column beyond_mesh): the proxy there follows the "
               "rim, not the object; model a wider area of the object\n",
               beyond.count, contact,
               100.0 * double(beyond.count) / double(std::max<std::size_t>(contact, 1)), a.mesh,
               beyond.max_mm);
}

void register_fit(CLI::App* sys) {
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
                  "shape mesh (PLY/OBJ), optional: depths of g_s are then measured from the "
                  "undeformed surface, forces decomposed at the surface under the probe, and "
                  "cycles without normal (ncx,ncy,ncz) or direction (tx,ty,tz) columns take "
                  "them from the mesh and the angle column")
      ->check(CLI::ExistingFile);
  fit->add_option("--probe-radius", fa->probe_radius,
                  "mm; 0 when the mesh is the probe-centre surface, else the probe radius")
      ->capture_default_str();
  fit->add_option("--load-damping", fa->load_damping,
                  "damping the palpation commanded while loading, N s/mm (subtracted from the "
                  "measured slip viscosity)")
      ->capture_default_str();
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
  fit->add_option("--force-frame", fa->force_frame,
                  "normal the measured forces are split at for the limits (needs --mesh): anchor "
                  "(n_c, where the stuck contact began), probe (the surface under the displaced "
                  "probe) or auto (the one whose f_T/f_N depends least on f_N)")
      ->check(CLI::IsMember({"auto", "anchor", "probe"}))
      ->capture_default_str();
  fit->callback([fa] { run_fit(*fa); });
}

void register_table(CLI::App* sys) {
  auto ta = std::make_shared<TableArgs>();
  auto* table = sys->add_subcommand(
      "table",
      "Print Table 4.1 of a reference point: f_T, ||u^p_100||, ||u^p_600||, plateau growth (mm).");
  table->add_option("sys", ta->sys, "sys.json")->required()->check(CLI::ExistingFile);
  table->add_option("--point,-p", ta->point, "reference point id")->capture_default_str();
  table->add_option("--fn", ta->fn, "normal force level f_N (N; nearest level)")
      ->capture_default_str();
  table->add_option("--dir", ta->dir, "tangential direction index")->capture_default_str();
  table->add_option("--gs-mesh", ta->gs_mesh,
                    "also write the point's elastic displacement limit surface g_s (fig. 4.8) as a "
                    "mesh: local mm, x along t_0, y along t_1, z = depth");
  table->add_option("--fs-mesh", ta->fs_mesh,
                    "also write the point's sliding yield surface f_s as a mesh: local N, z = f_N");
  table->callback([ta] { run_table(*ta); });
}

void register_palpate(CLI::App* sys) {
  auto pa = std::make_shared<PalpateArgs>();
  auto* palpate = sys->add_subcommand(
      "palpate",
      "Automatic palpation (thesis 4.3.2) of a virtual-lab scene: at each reference point the\n"
      "device (hand detached) runs loading-unloading cycles at f_N 1, 3, 5 N, 8 tangential\n"
      "directions, rising f_T and plateaus 100/600 ms; the sliding yield surfaces are fitted and\n"
      "written to sys.json, with the cycles (<out>.cycles.csv), the probe-centre shape mesh\n"
      "(<out>.shape.ply) and the reference points (<out>.refs.csv) beside it. With --device udp\n"
      "the same protocol runs on a device over the bridge (a real one, or `inhap lab device\n"
      "--operator none`). Units: mm, N, s.");
  palpate->add_option("--scene", pa->opt.scene, "built-in scene (see `inhap lab scenes`)");
  palpate->add_option("--scene-file", pa->opt.scene_file, "scene JSON file")
      ->check(CLI::ExistingFile);
  palpate->add_option("--points", pa->opt.points,
                      "reference points: grid:RxC[:half_extent_mm], rings:1,6,11[:radius_mm] or "
                      "file:xy.csv (columns x,y; mm); default grid:3x3 (dome: rings:1,6,11) over "
                      "the scene's region");
  palpate->add_option("--seed", pa->opt.seed, "device noise seed")->capture_default_str();
  palpate->add_flag("--quick", pa->opt.quick, "f_N 1 and 3 N, 4 directions (for tests)");
  cli::add_physics_option(*palpate, pa->opt.physics, "lab contact physics: builtin | mujoco");
  palpate->add_option("--out,-o", pa->out, "sys.json to write")->required();
  palpate->add_option("--device", pa->device,
                      "udp or udp:PORT: palpate a device that joins over the bridge "
                      "(docs/bridge.md) instead of the lab; needs --shape and --refs");
  palpate->add_option("--shape", pa->shape,
                      "--device: shape mesh (PLY/OBJ, mm; the probe-centre surface as sys palpate "
                      "writes it, or the object surface with --probe-radius)");
  palpate->add_option("--refs", pa->refs,
                      "--device: reference points CSV x,y,z[,nx,ny,nz] (mm; as sys palpate writes "
                      "<out>.refs.csv)");
  palpate->add_option("--probe-radius", pa->probe_radius, "--device: probe radius, mm")
      ->capture_default_str();
  palpate
      ->add_option("--tool-mass", pa->tool_mass, "--device: tool mass beyond the force sensor, kg")
      ->capture_default_str();
  palpate
      ->add_option("--connect-timeout", pa->connect,
                   "--device: give up if no device joins within this, s")
      ->capture_default_str();
  palpate->callback([pa] { run_palpate(*pa); });
}

void register_proxy(CLI::App* sys) {
  auto xa = std::make_shared<ProxyArgs>();
  auto* proxy = sys->add_subcommand(
      "proxy",
      "Estimate the proxy q of a recording (thesis 4.3.1) with the sliding yield surfaces and the\n"
      "shape mesh; writes the recording with columns qx,qy,qz (mm; q = p out of contact), contact "
      "(0/1),\nnx,ny,nz (outward normal at q) and beyond_mesh (1: in contact with the probe "
      "beyond the rim of the\nshape mesh, where the proxy follows the rim; counted, with a "
      "warning) added.");
  proxy->add_option("recording", xa->rec, "recording CSV (t,px,py,pz,fx,fy,fz,...)")
      ->required()
      ->check(CLI::ExistingFile);
  proxy->add_option("--sys", xa->sys, "sys.json")->required()->check(CLI::ExistingFile);
  proxy->add_option("--mesh", xa->mesh, "shape mesh (PLY/OBJ)")
      ->required()
      ->check(CLI::ExistingFile);
  proxy
      ->add_option("--probe-radius", xa->probe_radius,
                   "mm; 0 when the mesh is the probe-centre surface (as written by sys palpate), "
                   "else the probe radius to offset the object's surface by")
      ->capture_default_str();
  proxy->add_flag("--no-creep", xa->no_creep,
                  "rate-independent return mapping (ignore the slip viscosity)");
  proxy->add_option("--out,-o", xa->out, "recording CSV to write")->required();
  proxy->callback([xa] { run_proxy(*xa); });
}

void register_sys(CLI::App& app) {
  auto* sys = app.add_subcommand(
      "sys",
      "Sliding yield surfaces (thesis 4.2-4.3): automatic palpation, elastic limits, proxy.\n"
      "Units: positions/displacements mm, forces N, times s, angles rad.");
  sys->require_subcommand(1);

  register_fit(sys);
  register_table(sys);
  register_palpate(sys);
  register_proxy(sys);
}

}  // namespace

INHAP_COMMAND(60, "sys", register_sys);
