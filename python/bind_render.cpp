// Renderers behind the common servo interface (haptics::Renderer): TCA-MESH and CBA on a mesh
// with a stiffness map, the data-driven renderer; `step` one tick, `replay` the servo loop over
// whole arrays in C++ without the GIL; and the constant-force stroke of thesis ch. 5.3.
// Units: t s, positions mm, forces N, stiffness N/mm.
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "inhap/eval/serve.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/rendering/renderer.hpp"
#include "inhap/rendering/stroke.hpp"

namespace inhap::py {

namespace {

using rendering::Algorithm;

/// A renderer and what it refers to (the model is shared with Python; the files' setup owned).
struct PyRenderer {
  std::shared_ptr<const rendering::Model> mesh_model;
  eval::RenderSetup setup;
  std::unique_ptr<haptics::Renderer> own;
  haptics::Renderer& r() { return own ? *own : *setup.renderer; }
};

std::unique_ptr<PyRenderer> mesh_renderer(std::shared_ptr<const rendering::Model> m, Algorithm a) {
  auto r = std::make_unique<PyRenderer>();
  r->mesh_model = std::move(m);
  r->own = std::make_unique<haptics::MeshRenderer>(*r->mesh_model, a);
  return r;
}

Vec3 to_point(const pyb::handle& obj) {
  if (pyb::isinstance<pyb::array>(obj)) {
    const pyb::array a = checked(obj, "p", 0, 3);
    return *as_vec3(a);
  }
  const auto s = pyb::reinterpret_borrow<pyb::sequence>(obj);
  if (pyb::len(s) != 3) throw pyb::type_error("p: expected 3 numbers (mm)");
  return {s[0].cast<double>(), s[1].cast<double>(), s[2].cast<double>()};
}

pyb::array vec3_array(const Vec3& v) {
  pyb::array_t<double> a(3);
  std::copy(v.data(), v.data() + 3, a.mutable_data());
  return a;
}

// The servo loop over whole arrays: ticks run in C++ with the GIL released; Ctrl-C is checked
// every 65,536 ticks.
pyb::dict replay(PyRenderer& self, const pyb::object& t_obj, const pyb::object& p_obj, bool reset) {
  const pyb::array ta = checked(t_obj, "t", 0);
  const auto n = static_cast<std::size_t>(ta.shape(0));
  const pyb::array pa = checked(p_obj, "p", 3, n);
  pyb::array_t<double> force({static_cast<pyb::ssize_t>(n), pyb::ssize_t{3}});
  pyb::array_t<double> ihip({static_cast<pyb::ssize_t>(n), pyb::ssize_t{3}});
  pyb::array_t<double> cihip({static_cast<pyb::ssize_t>(n), pyb::ssize_t{3}});
  pyb::array_t<bool> contact(static_cast<pyb::ssize_t>(n));
  const double* t = as_doubles(ta);
  const Vec3* p = as_vec3(pa);
  auto* f = reinterpret_cast<Vec3*>(force.mutable_data());
  auto* q = reinterpret_cast<Vec3*>(ihip.mutable_data());
  auto* qc = reinterpret_cast<Vec3*>(cihip.mutable_data());
  bool* c = contact.mutable_data();
  haptics::Renderer& r = self.r();
  {
    pyb::gil_scoped_release release;
    if (reset) r.reset();
    haptics::ServoInput in;
    for (std::size_t i = 0; i < n; ++i) {
      if ((i & 0xFFFF) == 0xFFFF) check_signals();
      in.t_s = t[i];
      in.p_mm = p[i];
      const haptics::ServoOutput o = r.step(in);
      f[i] = o.force_n;
      q[i] = o.ihip_mm;
      qc[i] = o.cihip_mm;
      c[i] = o.contact;
    }
  }
  pyb::dict d;
  d["force"] = force;
  d["contact"] = contact;
  d["ihip"] = ihip;
  d["cihip"] = cihip;
  return d;
}

void bind_output(pyb::module_& m) {
  pyb::class_<haptics::ServoOutput>(m, "ServoOutput",
                                    "One tick's output: force (N), contact, HIP/IHIP/CIHIP (mm)")
      .def_property_readonly(
          "force", [](const haptics::ServoOutput& o) { return vec3_array(o.force_n); },
          "Force to command, N, (3,)")
      .def_readonly("contact", &haptics::ServoOutput::contact, "In contact this tick")
      .def_property_readonly(
          "hip", [](const haptics::ServoOutput& o) { return vec3_array(o.hip_mm); }, "HIP, mm")
      .def_property_readonly(
          "ihip", [](const haptics::ServoOutput& o) { return vec3_array(o.ihip_mm); },
          "IHIP / proxy q on the surface, mm (the HIP out of contact)")
      .def_property_readonly(
          "cihip", [](const haptics::ServoOutput& o) { return vec3_array(o.cihip_mm); },
          "CIHIP q' = q + s n of TCA-MESH (the IHIP for the others), mm");
}

std::shared_ptr<const rendering::Model> make_model(const TriMesh& mesh, double a_s, double a_t,
                                                   double force_limit, double default_stiffness,
                                                   bool force_shading, bool spatial_order) {
  rendering::Params p;
  p.a_s = a_s;
  p.a_t = a_t;
  p.force_limit_n = force_limit;
  p.default_stiffness = default_stiffness;
  p.force_shading = force_shading;
  p.spatial_order = spatial_order;
  return std::make_shared<const rendering::Model>(mesh, p);
}

void bind_renderer(pyb::module_& m) {
  pyb::class_<rendering::Model, std::shared_ptr<rendering::Model>>(
      m, "MeshModel",
      "Immutable rendering model of CBA / TCA-MESH: a mesh (mm) with its 'stiffness' property "
      "(N/mm), normals, adjacency and spatial index. Many renderers can share one model.")
      .def(pyb::init([](const TriMesh& mesh, double a_s, double a_t, double force_limit,
                        double default_stiffness, bool force_shading, bool spatial_order) {
             return std::const_pointer_cast<rendering::Model>(make_model(
                 mesh, a_s, a_t, force_limit, default_stiffness, force_shading, spatial_order));
           }),
           pyb::arg("mesh"), pyb::arg("a_s") = rendering::Params{}.a_s,
           pyb::arg("a_t") = rendering::Params{}.a_t,
           pyb::arg("force_limit") = rendering::Params{}.force_limit_n,
           pyb::arg("default_stiffness") = rendering::Params{}.default_stiffness,
           pyb::arg("force_shading") = true, pyb::arg("spatial_order") = true,
           "a_s: height restoration slope (eq. 5.11); a_t: mesh restoration ratio (eq. 5.15); "
           "force_limit N; default_stiffness N/mm when the mesh has no 'stiffness'. The mesh "
           "is copied (and reordered along a Morton curve when spatial_order).")
      .def_property_readonly("mesh", &rendering::Model::mesh, pyb::return_value_policy::copy,
                             "The model's mesh (a copy; reordered when spatial_order)");
  pyb::class_<PyRenderer>(m, "Renderer", R"doc(
A renderer behind the common servo interface: step(t, p) one 1 kHz tick (t s, p mm -> force N),
replay(t, p) the whole servo loop over arrays in C++. Make one with Renderer.tca(model),
Renderer.cba(model) or Renderer.data_driven(model, sys, shape). A NaN position gives zero force.)doc")
      .def_static(
          "tca",
          [](std::shared_ptr<rendering::Model> mdl) { return mesh_renderer(mdl, Algorithm::kTCA); },
          pyb::arg("model"), "TCA-MESH on a MeshModel (thesis Algorithm 1)")
      .def_static(
          "cba",
          [](std::shared_ptr<rendering::Model> mdl) { return mesh_renderer(mdl, Algorithm::kCBA); },
          pyb::arg("model"), "The constraint-based god-object (CBA) with force shading")
      .def_static(
          "data_driven",
          [](const std::string& model, const std::string& sys, const std::string& shape,
             double probe_radius) {
            auto r = std::make_unique<PyRenderer>();
            eval::RendererOptions o;
            o.render = "model";
            o.model = model;
            o.sys = sys;
            o.shape = shape;
            o.probe_radius_mm = probe_radius;
            r->setup = eval::make_renderer(o);
            return r;
          },
          pyb::arg("model"), pyb::arg("sys"), pyb::arg("shape"), pyb::arg("probe_radius") = 0.0,
          "The data-driven renderer (FOAW -> sliding-yield-surface proxy -> RBF force) from a "
          "force-model JSON, a sys.json and the shape mesh (probe_radius mm), as `inhap serve "
          "--render model`.")
      .def(
          "step",
          [](PyRenderer& self, double t, const pyb::object& p) {
            haptics::ServoInput in;
            in.t_s = t;
            in.p_mm = to_point(p);
            return self.r().step(in);
          },
          pyb::arg("t"), pyb::arg("p"),
          "One servo tick: t (s), probe position p (mm, 3 numbers) -> ServoOutput (force N)")
      .def("replay", &replay, pyb::arg("t"), pyb::arg("p"), pyb::arg("reset") = true,
           "Runs the servo loop over t (float64 (N,), s) and p (float64 (N, 3), C order, mm) "
           "in C++ without the GIL (arrays used in place); returns {'force': (N, 3) N, "
           "'contact': (N,) bool, 'ihip': (N, 3) mm, 'cihip': (N, 3) mm}. reset: start from a "
           "fresh state (else continue after the last step).")
      .def(
          "reset", [](PyRenderer& self) { self.r().reset(); }, "Back to a fresh state")
      .def_property_readonly(
          "name", [](PyRenderer& self) { return std::string(self.r().name()); },
          "tca-mesh, cba or data-driven");
}

pyb::dict stroke(const rendering::Model& model, const std::string& algorithm,
                 std::pair<double, double> from, std::pair<double, double> to, double force,
                 double speed, double tremor, std::uint64_t seed) {
  const auto a = rendering::parse_algorithm(algorithm);
  if (!a) throw pyb::value_error("algorithm: expected tca or cba, got " + algorithm);
  rendering::StrokeOptions o;
  o.from = Vec2(from.first, from.second);
  o.to = Vec2(to.first, to.second);
  o.force_n = force;
  o.speed_mm_s = speed;
  o.tremor_n = tremor;
  o.seed = seed;
  std::vector<rendering::StrokeSample> s;
  {
    pyb::gil_scoped_release release;
    s = rendering::simulate_stroke(model, *a, o);
  }
  std::vector<double> t(s.size()), k(s.size()), sc(s.size()), contact(s.size());
  std::vector<Vec3> hip(s.size()), ihip(s.size()), cihip(s.size()), f(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    t[i] = s[i].time;
    k[i] = s[i].k;
    sc[i] = s[i].s;
    contact[i] = s[i].contact;
    hip[i] = s[i].hip;
    ihip[i] = s[i].ihip;
    cihip[i] = s[i].cihip;
    f[i] = s[i].force;
  }
  pyb::dict d;
  d["t"] = to_numpy(t);
  d["hip"] = to_numpy(hip);
  d["ihip"] = to_numpy(ihip);
  d["cihip"] = to_numpy(cihip);
  d["force"] = to_numpy(f);
  d["k"] = to_numpy(k);
  d["s"] = to_numpy(sc);
  d["contact"] = to_numpy(contact).attr("astype")("bool");
  return d;
}

}  // namespace

void register_render(pyb::module_& m) {
  bind_output(m);
  bind_renderer(m);
  m.def("simulate_stroke", &stroke, pyb::arg("model"), pyb::arg("algorithm") = "tca",
        pyb::arg("start") = std::pair<double, double>{0, 0},
        pyb::arg("end") = std::pair<double, double>{0, 0}, pyb::arg("force") = 1.0,
        pyb::arg("speed") = 20.0, pyb::arg("tremor") = 0.0, pyb::arg("seed") = 1,
        "A constant-force stroke across a MeshModel (thesis 5.3, `inhap tca stroke`): from "
        "start (x, y mm) to end at `force` N and `speed` mm/s with tremor N RMS. Returns arrays "
        "t (s), hip/ihip/cihip (mm), force (N), k (N/mm), s (mm), contact per servo tick.");
}

}  // namespace inhap::py
