// Sliding yield surfaces (thesis 4.2-4.3) as `inhap sys palpate | fit | proxy` run them: the
// automatic palpation of a lab scene, the fit from palpation cycles, and the proxy track of a
// recording (return mapping on g_s) added to it as columns. Units: mm, N, s.
#include <pybind11/stl.h>

#include <string>

#include "common.hpp"
#include "inhap/eval/sys_bridge.hpp"
#include "inhap/eval/sys_files.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/sys_model.hpp"

namespace inhap::py {

namespace {

pyb::dict palpate(const std::string& scene, const std::string& points, std::uint64_t seed,
                  bool quick, const std::string& physics, const std::string& scene_file,
                  const std::string& out, pyb::object progress) {
  eval::ScenePalpationOptions o;
  o.scene = scene_file.empty() ? scene : "";
  o.scene_file = scene_file;
  o.points = points;
  o.seed = seed;
  o.quick = quick;
  o.physics = physics;
  o.progress_label = "sys palpate";
  const std::string stem = eval::sys_output_stem(out);
  const std::string summary = with_progress(std::move(progress), [&](const Progress& cb) {
    o.progress = cb;
    const eval::ScenePalpation r = eval::palpate_scene(o);
    eval::write_scene_palpation(out, r);
    return eval::sys_summary(r.sys);
  });
  pyb::dict d;
  d["sys"] = out;
  d["cycles"] = stem + ".cycles.csv";
  d["shape"] = stem + ".shape.ply";
  d["refs"] = stem + ".refs.csv";
  d["summary"] = summary;
  return d;
}

pyb::dict add_proxy(Recording& rec, const std::string& sys, const TriMesh& mesh,
                    double probe_radius, bool creep) {
  const friction::SysModel model = friction::read_sys_json(sys);
  eval::ProxyFileResult r;
  {
    pyb::gil_scoped_release release;
    r = eval::add_proxy_columns(rec, model, mesh, probe_radius, creep);
  }
  pyb::dict d;
  d["contact"] = r.contact;
  d["sliding"] = r.sliding;
  d["beyond"] = r.beyond;
  d["beyond_max_mm"] = r.beyond_max_mm;
  return d;
}

}  // namespace

void register_sys(pyb::module_& m) {
  m.def("sys_palpate", &palpate, pyb::arg("scene") = "planar", pyb::arg("points") = "",
        pyb::arg("seed") = 1, pyb::arg("quick") = false, pyb::arg("physics") = "builtin",
        pyb::arg("scene_file") = "", pyb::kw_only(), pyb::arg("out"), pyb::arg("progress") = true,
        "`inhap sys palpate` on a lab scene: loading-unloading cycles at f_N 1/3/5 N in 8 "
        "directions (quick: 1 and 3 N, 4) at the reference points (points: grid:RxC[:H], "
        "rings:..., file:xy.csv; '' the scene's default), elastic borders, sliding yield "
        "surfaces. Writes out (sys.json) and its .cycles.csv, .shape.ply, .refs.csv like the "
        "program; returns their paths and the summary it prints.");
  m.def(
      "sys_fit",
      [](const std::string& cycles, const std::string& out, const std::string& mesh,
         double probe_radius) {
        eval::SysFitFileOptions o;
        o.cycles = cycles;
        o.mesh = mesh;
        o.probe_radius_mm = probe_radius;
        eval::SysFitFileResult r;
        {
          pyb::gil_scoped_release release;
          r = eval::fit_sys_file(o);
          friction::write_sys_json(out, r.sys);
        }
        return eval::sys_summary(r.sys);
      },
      pyb::arg("cycles"), pyb::arg("out"), pyb::arg("mesh") = "", pyb::arg("probe_radius") = 0.0,
      "`inhap sys fit`: sliding yield surfaces from palpation cycles (CSV, mm, N, s) with the "
      "program's defaults; writes out (sys.json) and returns the summary.");
  m.def("add_proxy_columns", &add_proxy, pyb::arg("recording"), pyb::arg("sys"), pyb::arg("mesh"),
        pyb::arg("probe_radius") = 0.0, pyb::arg("creep") = true,
        "`inhap sys proxy` on a Recording, in place: runs the proxy estimator (return mapping on "
        "the sliding yield surfaces of sys.json over the shape Mesh, probe_radius mm) and adds "
        "qx,qy,qz (mm; q = p out of contact), contact (0/1), nx,ny,nz and beyond_mesh. Returns "
        "the counts (contact, sliding, beyond samples, beyond_max_mm).");
}

}  // namespace inhap::py
