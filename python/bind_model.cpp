// The data-driven force model (thesis 4.4-4.5) as `inhap model train | eval | render` run it:
// the same presets and parameters, the same files, the model's force on arrays.
// Units: positions mm, velocities mm/s, forces N, time s.
#include <pybind11/stl.h>

#include <string>

#include "common.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "inhap/eval/recordings.hpp"

namespace inhap::py {

namespace {

using datadriven::TrainedForceModel;

// Sets `field` from kwargs[name] when given (not None) and records "--flag" as given, so the
// preset fills in only what the caller left out (as `model train` does with its flags).
template <class T>
void take(const pyb::dict& kw, const char* name, const char* flag, T& field,
          eval::TrainRequest& q) {
  if (!kw.contains(name) || kw[name].is_none()) return;
  field = kw[name].cast<T>();
  q.given.insert(flag);
}

void take_switch(const pyb::dict& kw, const char* name, const char* flag, bool& field,
                 eval::TrainRequest& q) {
  take(kw, name, flag, field, q);
}

eval::TrainFileOptions train_options(const std::string& recording, const pyb::dict& kw) {
  static const char* const kKnown[] = {"preset",
                                       "mesh",
                                       "sys",
                                       "bins",
                                       "centers",
                                       "nonzeros",
                                       "lambda_ratio",
                                       "seed",
                                       "design",
                                       "features",
                                       "tail",
                                       "tangent_mirror",
                                       "stiffness_prior",
                                       "shear_prior",
                                       "friction_cone",
                                       "fallback",
                                       "fallback_near",
                                       "fallback_far",
                                       "solver",
                                       "feature_weights",
                                       "bin_blend",
                                       "threads",
                                       "modeling_range",
                                       "above_range",
                                       "foaw_window",
                                       "foaw_noise",
                                       "force_limit",
                                       "proxy_prefix",
                                       "contact_column",
                                       "contact_threshold",
                                       "velocity_window",
                                       "time_unit",
                                       "length_unit"};
  for (auto [k, v] : kw) {
    const std::string name = pyb::str(k);
    if (std::find(std::begin(kKnown), std::end(kKnown), name) == std::end(kKnown))
      throw pyb::type_error("train_force_model: unexpected keyword '" + name + "'");
  }
  eval::TrainFileOptions o;
  o.recording = recording;
  eval::TrainRequest& q = o.request;
  datadriven::TrainParams& p = q.params;
  if (kw.contains("preset") && !kw["preset"].is_none()) q.preset = kw["preset"].cast<std::string>();
  if (kw.contains("mesh") && !kw["mesh"].is_none()) o.mesh = kw["mesh"].cast<std::string>();
  if (kw.contains("sys") && !kw["sys"].is_none()) o.sys = kw["sys"].cast<std::string>();
  take(kw, "bins", "--bins", p.bins, q);
  take(kw, "centers", "--centers", p.centers, q);
  take(kw, "nonzeros", "--nonzeros", p.nonzeros, q);
  take(kw, "lambda_ratio", "--lambda-ratio", p.lambda_ratio, q);
  take(kw, "seed", "--seed", p.seed, q);
  take(kw, "design", "--design", q.design, q);
  take(kw, "features", "--features", q.features, q);
  take_switch(kw, "tail", "--tail", p.linear_tail, q);
  take_switch(kw, "tangent_mirror", "--tangent-mirror", p.tangent_mirror, q);
  take_switch(kw, "stiffness_prior", "--stiffness-prior", p.stiffness_prior, q);
  take_switch(kw, "shear_prior", "--shear-prior", p.shear_prior, q);
  take_switch(kw, "friction_cone", "--friction-cone", p.friction_cone, q);
  take_switch(kw, "fallback", "--fallback", p.fallback, q);
  take(kw, "fallback_near", "--fallback-near", p.fallback_near_mm, q);
  take(kw, "fallback_far", "--fallback-far", p.fallback_far_mm, q);
  if (kw.contains("solver") && !kw["solver"].is_none()) {
    p.solver = datadriven::l1_solver_from_string(kw["solver"].cast<std::string>());
    q.given.insert("--solver");
  }
  take(kw, "feature_weights", "--feature-weights", p.feature_weights, q);
  take(kw, "bin_blend", "--bin-blend", p.bin_blend, q);
  take(kw, "threads", "--threads", p.threads, q);
  take(kw, "modeling_range", "--modeling-range", p.modeling_range_n, q);
  take(kw, "above_range", "--above-range", q.above_range, q);
  take(kw, "foaw_window", "--foaw-window", o.foaw.max_window, q);
  take(kw, "foaw_noise", "--foaw-noise", o.foaw.noise_bound_mm, q);
  take(kw, "force_limit", "--force-limit", o.force_limit_n, q);
  take(kw, "proxy_prefix", "--proxy-prefix", o.proxy.prefix, q);
  take(kw, "contact_column", "--contact-column", o.proxy.contact_column, q);
  take(kw, "contact_threshold", "--contact-threshold", o.proxy.contact_threshold_n, q);
  take(kw, "velocity_window", "--velocity-window", o.velocity_window_s, q);
  take(kw, "time_unit", "--time-unit", o.units.time, q);
  take(kw, "length_unit", "--length-unit", o.units.length, q);
  return o;
}

/// A trained model and what training said (notes, coverage lines).
struct PyForceModel {
  TrainedForceModel m;
  std::vector<std::string> notes;
};

PyForceModel train(const std::string& recording, const std::string& out, pyb::object progress,
                   const pyb::kwargs& kw) {
  eval::TrainFileOptions o = train_options(recording, kw);
  PyForceModel r;
  eval::TrainFileResult res = with_progress(std::move(progress), [&](const Progress& cb) {
    o.progress = cb;
    return eval::train_from_file(o);
  });
  r.notes = res.notes;
  r.notes.push_back(eval::range_note(res.model.provenance, res.set, o.force_limit_n));
  if (!out.empty()) {
    if (res.estimate)  // no proxy columns: the estimated surface and yield surfaces beside it
      for (const std::string& f :
           eval::write_estimate_files(out, *res.estimate, res.model.provenance))
        r.notes.push_back("wrote " + f);
    datadriven::save_force_model(out, res.model);
    for (std::string& line :
         eval::write_training_coverage(res.set, datadriven::coverage_path_for(out)))
      r.notes.push_back(std::move(line));
  }
  r.m = std::move(res.model);
  return r;
}

pyb::array model_forces(const PyForceModel& self, const pyb::object& p_obj,
                        const pyb::object& v_obj, const pyb::object& q_obj,
                        const pyb::object& n_obj) {
  const pyb::array pa = checked(p_obj, "p", 3);
  const auto n = static_cast<std::size_t>(pa.shape(0));
  const pyb::array va = checked(v_obj, "v", 3, n), qa = checked(q_obj, "q", 3, n);
  pyb::array na;
  if (!n_obj.is_none()) na = checked(n_obj, "n", 3, n);
  pyb::array_t<double> out({static_cast<pyb::ssize_t>(n), pyb::ssize_t{3}});
  const Vec3 *p = as_vec3(pa), *v = as_vec3(va), *q = as_vec3(qa);
  const Vec3* nn = n_obj.is_none() ? nullptr : as_vec3(na);
  auto* f = reinterpret_cast<Vec3*>(out.mutable_data());
  const datadriven::ForceModel& m = self.m.model;
  {
    pyb::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i)
      f[i] = nn ? datadriven::model_force(m, p[i], v[i], q[i], nn[i])
                : datadriven::model_force(m, p[i], v[i], q[i]);
  }
  return out;
}

eval::ProxyColumnsSpec proxy_spec(const std::string& prefix, const std::string& contact_column,
                                  double contact_threshold) {
  eval::ProxyColumnsSpec s;
  s.prefix = prefix;
  s.contact_column = contact_column;
  s.contact_threshold_n = contact_threshold;
  return s;
}

eval::RecordingUnits units_of(const std::string& time_unit, const std::string& length_unit) {
  eval::RecordingUnits u;
  u.time = time_unit;
  u.length = length_unit;
  return u;
}

pyb::dict render(const std::string& model, const std::string& recording, const std::string& out,
                 const std::string& prefix, const std::string& contact_column,
                 double contact_threshold, const std::string& mesh, const std::string& time_unit,
                 const std::string& length_unit) {
  const auto spec = proxy_spec(prefix, contact_column, contact_threshold);
  eval::ReplayedFile r;
  {
    pyb::gil_scoped_release release;
    const TrainedForceModel m = datadriven::load_trained_force_model(model);
    r = eval::replay_file(model, m, recording, spec, mesh, units_of(time_unit, length_unit));
    if (!out.empty()) eval::write_rendered_csv(out, r, recording, model);
  }
  std::vector<double> contact(r.track.contact.begin(), r.track.contact.end());
  pyb::dict d;
  d["t"] = to_numpy(r.rec.t);
  d["p"] = to_numpy(r.rec.p);
  d["force"] = to_numpy(r.forces);
  d["measured"] = to_numpy(r.rec.f);
  d["q"] = to_numpy(r.track.q);
  d["contact"] = to_numpy(contact).attr("astype")("bool");
  d["support"] = eval::support_note(eval::support_share(model, r));
  return d;
}

pyb::object evaluate(const std::string& model, const std::string& recording,
                     const std::string& prefix, const std::string& contact_column,
                     double contact_threshold, const std::string& mesh,
                     const std::string& time_unit, const std::string& length_unit,
                     const std::string& train) {
  eval::ModelEvalResult r;
  {
    pyb::gil_scoped_release release;
    r = eval::evaluate_model_file(model, recording,
                                  proxy_spec(prefix, contact_column, contact_threshold), mesh,
                                  units_of(time_unit, length_unit), train);
  }
  pyb::object d = json_to_python(r.json.dump());
  d["text"] = eval::model_eval_text(r);
  d["support_note"] = eval::support_note(r.support);
  d["baselines_note"] = r.baselines_note;
  return d;
}

}  // namespace

void register_model(pyb::module_& m) {
  pyb::class_<PyForceModel>(m, "ForceModel", R"doc(
A trained data-driven force model f = g(p, pdot, q) (thesis 4.4): r^3 RBFs per ||q - p|| bin,
with its provenance (training parameters and statistics). Positions mm, velocities mm/s,
forces N.)doc")
      .def(
          "save",
          [](const PyForceModel& s, const std::string& path) {
            datadriven::save_force_model(path, s.m);
          },
          pyb::arg("path"), "Writes the model JSON (forces bit-identical after load)")
      .def(
          "summary",
          [](const PyForceModel& s, bool verbose) { return eval::train_summary(s.m, verbose); },
          pyb::arg("verbose") = false, "The report `model train` prints")
      .def("force", &model_forces, pyb::arg("p"), pyb::arg("v"), pyb::arg("q"),
           pyb::arg("n") = pyb::none(),
           "Model force (N, (N, 3)) for probe positions p (mm), velocities v (mm/s), proxies q "
           "(mm) and, for local-frame models, outward normals n at q; float64 (N, 3) C-order "
           "arrays used in place. Non-finite input gives zero force.")
      .def_readonly("notes", &PyForceModel::notes, "What training said (as the CLI's stderr)")
      .def_property_readonly("bins", [](const PyForceModel& s) { return s.m.model.bins.size(); })
      .def_property_readonly(
          "features",
          [](const PyForceModel& s) { return std::string(to_string(s.m.model.features)); })
      .def_property_readonly(
          "json",
          [](const PyForceModel& s) {
            return json_to_python(datadriven::force_model_to_json(s.m));
          },
          "The model file's content as a dict");
  m.def(
      "load_force_model",
      [](const std::string& path) {
        PyForceModel r;
        r.m = datadriven::load_trained_force_model(path);
        return r;
      },
      pyb::arg("path"), "Reads and validates a model JSON (inhap.Error naming the file)");
  m.def("train_force_model", &train, pyb::arg("recording"), pyb::kw_only(), pyb::arg("out") = "",
        pyb::arg("progress") = true, R"doc(
Trains a model from a recording CSV with proxy columns qx,qy,qz (mm) and a contact column, as
`inhap model train` does: preset 'best' by default ('world', 'thesis'); every keyword given
overrides the preset like the flag of the same name (bins, centers, nonzeros, lambda_ratio,
seed, design, features, tail, tangent_mirror, stiffness_prior, shear_prior, friction_cone,
fallback, fallback_near mm, fallback_far mm, solver 'cd'|'sparsa', feature_weights (3),
bin_blend mm, threads, modeling_range N, above_range 'keep'|'exclude', foaw_window samples,
foaw_noise mm, velocity_window s, force_limit N, proxy_prefix, contact_column, contact_threshold
N, time_unit 's'|'ms', length_unit 'mm'|'m', mesh, sys). Without proxy columns the surface,
normals, proxy and friction are estimated from the recording (written beside out).
With out=PATH the model and its coverage file are written there. progress: True (a tqdm bar
when installed), False, or a callable(what, fraction, eta_s).)doc");
  m.def("evaluate_force_model", &evaluate, pyb::arg("model"), pyb::arg("recording"),
        pyb::arg("proxy_prefix") = "q", pyb::arg("contact_column") = "contact",
        pyb::arg("contact_threshold") = 0.05, pyb::arg("mesh") = "", pyb::arg("time_unit") = "s",
        pyb::arg("length_unit") = "mm", pyb::arg("train") = "",
        "`inhap model eval`: replays a test recording through the servo renderer; returns the "
        "--json report as a dict (errors in N, eq. 4.27-4.31, the mean and k-NN baselines fitted "
        "on `train` or the model's training recording) plus 'text' (what it prints). time_unit "
        "s|ms and length_unit mm|m: the recording's t and p columns.");
  m.def("render_force_model", &render, pyb::arg("model"), pyb::arg("recording"),
        pyb::arg("out") = "", pyb::arg("proxy_prefix") = "q",
        pyb::arg("contact_column") = "contact", pyb::arg("contact_threshold") = 0.05,
        pyb::arg("mesh") = "", pyb::arg("time_unit") = "s", pyb::arg("length_unit") = "mm",
        "`inhap model render`: rendered forces of a recording at servo rate. Returns t (s), p "
        "(mm), force (rendered, N), measured (N), q (mm), contact; out=PATH also writes the CSV.");
}

}  // namespace inhap::py
