// `inhap sys ...`: sliding yield surfaces (thesis 4.2-4.3): fit from palpation cycles, print
// Table 4.1, estimate the proxy of a recording. Units: mm, N, s, rad.
#include <fmt/format.h>

#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/sys_bridge.hpp"
#include "inhap/eval/sys_files.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"

namespace {

using namespace inhap;
using namespace inhap::friction;

struct FitArgs {
  eval::SysFitFileOptions opt;
  std::string out, tangent_reference = "1,0,0";
};

void run_fit(FitArgs a) {
  a.opt.tangent_reference = eval::parse_vec3(a.tangent_reference, "--tangent-reference");
  const eval::SysFitFileResult r = eval::fit_sys_file(a.opt);
  write_sys_json(a.out, r.sys);
  fmt::print("{}", eval::sys_summary(r.sys));
  fmt::print(stderr, "fitted {} cycles -> {}\n", r.cycles, a.out);
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
  fmt::print("{}", eval::table_4_1_text(m, a.point, a.fn, a.dir));
  OutputTransaction tx;
  if (!a.gs_mesh.empty()) write_mesh(a.gs_mesh, m.points[i].gs.to_mesh(4));
  if (!a.fs_mesh.empty()) write_mesh(a.fs_mesh, m.points[i].fs.to_mesh(4));
  tx.commit();
}

struct PalpateArgs {
  eval::ScenePalpationOptions opt;
  std::string out;
  eval::BridgePalpationOptions dev;  ///< --device udp: a device over the bridge
};

// `sys palpate --device udp[:PORT]`: the protocol over the bridge, on a shape mesh the user gives.
void run_palpate_device(PalpateArgs a) {
  const std::string stem = eval::sys_output_stem(a.out);
  for (const std::string& path : {stem + ".cycles.csv", a.out}) check_output_path(path);
  eval::BridgePalpationOptions& o = a.dev;
  o.quick = a.opt.quick;
  o.progress = cli::progress;
  o.on_listening = [](std::uint16_t port) {
    fmt::print(stderr, "sys palpate: waiting for a device on udp 127.0.0.1:{}\n", port);
  };
  const eval::BridgePalpationResult r = eval::palpate_bridge(o);
  OutputTransaction tx;  // two outputs: both or neither
  write_cycles_csv(stem + ".cycles.csv", r.cycles);
  write_sys_json(a.out, r.sys);
  tx.commit();
  fmt::print("{}", eval::sys_summary(r.sys));
  fmt::print(stderr,
             "{} cycles, {} ticks, bridge: {} time-outs, {} lost; wrote {}, {}.cycles.csv\n",
             r.cycles.size(), r.ticks, r.bridge.timeouts, r.bridge.lost, a.out, stem);
}

void run_palpate(PalpateArgs a) {
  if (!a.dev.device.empty()) return run_palpate_device(a);
  a.opt.progress_label = "sys palpate";
  a.opt.progress = cli::progress;
  const std::string stem = eval::sys_output_stem(a.out);
  for (const std::string& path :
       {stem + ".cycles.csv", stem + ".shape.ply", stem + ".refs.csv", a.out})
    check_output_path(path);  // before the palpation, which takes minutes
  const eval::ScenePalpation r = eval::palpate_scene(a.opt);
  eval::write_scene_palpation(a.out, r);
  fmt::print("{}", eval::sys_summary(r.sys));
  fmt::print(stderr, "{}", eval::scene_palpation_text(a.out, r));
}

struct ProxyArgs {
  std::string sys, mesh, rec, out;
  double probe_radius = 0.0;
  bool no_creep = false;
};

void run_proxy(const ProxyArgs& a) {
  const auto [r, rows] = eval::proxy_file(a.sys, a.mesh, a.rec, a.out, a.probe_radius, !a.no_creep);
  fmt::print(stderr,
             "{} rows: {} in contact, {} with the proxy sliding, {} beyond the mesh rim -> {}\n",
             rows, r.contact, r.sliding, r.beyond, a.out);
  fmt::print(stderr, "{}", eval::beyond_rim_warning(r, a.mesh));
}

void register_fit(CLI::App* sys) {
  auto fa = std::make_shared<FitArgs>();
  auto* fit = sys->add_subcommand("fit",
                                  "Fit sliding yield surfaces from palpation cycles (CSV; one "
                                  "loading-unloading cycle per row,\n"
                                  "columns in docs/sliding-yield-surface.md) and write sys.json. "
                                  "Works on cycles recorded on a\n"
                                  "real device with your own code.");
  fit->add_option("cycles", fa->opt.cycles, "palpation cycles CSV")
      ->required()
      ->check(CLI::ExistingFile);
  fit->add_option("--mesh", fa->opt.mesh,
                  "shape mesh (PLY/OBJ), optional: depths of g_s are then measured from the "
                  "undeformed surface, forces decomposed at the surface under the probe, and "
                  "cycles without normal (ncx,ncy,ncz) or direction (tx,ty,tz) columns take "
                  "them from the mesh and the angle column")
      ->check(CLI::ExistingFile);
  fit->add_option("--probe-radius", fa->opt.probe_radius_mm,
                  "mm; 0 when the mesh is the probe-centre surface, else the probe radius")
      ->capture_default_str();
  fit->add_option("--load-damping", fa->opt.load_damping,
                  "damping the palpation commanded while loading, N s/mm (subtracted from the "
                  "measured slip viscosity)")
      ->capture_default_str();
  fit->add_option("--out,-o", fa->out, "sys.json to write")->required();
  fit->add_option("--tangent-reference", fa->tangent_reference,
                  "world direction whose projection onto the tangent plane is t_0 (x,y,z)")
      ->capture_default_str();
  fit->add_option("--weight-up", fa->opt.border.weight_up,
                  "k-means weight of the normalised ||u^p_100|| feature")
      ->capture_default_str();
  fit->add_option("--weight-growth", fa->opt.border.weight_growth,
                  "k-means weight of the normalised plateau growth ||u^p_600||-||u^p_100||")
      ->capture_default_str();
  fit->add_option("--noise-floor", fa->opt.border.min_sliding_growth,
                  "plateau growth (mm) below which a step is not sliding")
      ->capture_default_str();
  fit->add_option("--force-frame", fa->opt.force_frame,
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
  palpate->add_option("--device", pa->dev.device,
                      "udp or udp:PORT: palpate a device that joins over the bridge "
                      "(docs/bridge.md) instead of the lab; needs --shape and --refs");
  palpate->add_option("--shape", pa->dev.shape,
                      "--device: shape mesh (PLY/OBJ, mm; the probe-centre surface as sys palpate "
                      "writes it, or the object surface with --probe-radius)");
  palpate->add_option("--refs", pa->dev.refs,
                      "--device: reference points CSV x,y,z[,nx,ny,nz] (mm; as sys palpate writes "
                      "<out>.refs.csv)");
  palpate->add_option("--probe-radius", pa->dev.probe_radius_mm, "--device: probe radius, mm")
      ->capture_default_str();
  palpate
      ->add_option("--tool-mass", pa->dev.tool_mass_kg,
                   "--device: tool mass beyond the force sensor, kg")
      ->capture_default_str();
  palpate
      ->add_option("--connect-timeout", pa->dev.connect_s,
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
