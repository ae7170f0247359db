// The data-driven force model (thesis 4.4-4.5) as `inhap model train | eval | render` run it:
// the same presets and parameters, the same files, the model's force on arrays.
// Units: positions mm, velocities mm/s, forces N, time s.
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "inhap/eval/recordings.hpp"
#include "inhap/eval/recordings_eval.hpp"
#include "inhap/geometry/trimesh.hpp"

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
                                       "sliding_floor",
                                       "fallback",
                                       "fallback_near",
                                       "fallback_far",
                                       "fallback_normal_near",
                                       "fallback_normal_far",
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
  take_switch(kw, "sliding_floor", "--sliding-floor", p.sliding_floor, q);
  take_switch(kw, "fallback", "--fallback", p.fallback, q);
  take(kw, "fallback_near", "--fallback-near", p.fallback_near_mm, q);
  take(kw, "fallback_far", "--fallback-far", p.fallback_far_mm, q);
  take(kw, "fallback_normal_near", "--fallback-normal-near", p.fallback_normal_near_mm, q);
  take(kw, "fallback_normal_far", "--fallback-normal-far", p.fallback_normal_far_mm, q);
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

/// A trained model and what training said (notes, coverage lines); a model trained here also
/// keeps its estimated surface and yield surfaces and its training samples (for eval, render and
/// save); a model read from or written to a file knows its path (the references beside it).
struct PyForceModel {
  TrainedForceModel m;
  std::vector<std::string> notes;
  std::string path;
  std::optional<datadriven::RecordingEstimate> estimate;
  std::optional<datadriven::TrainingSet> set, baseline_set;

  eval::ModelSource source(const std::string& mesh_flag, const TriMesh* mesh) const {
    eval::ModelSource s;
    s.model = &m;
    s.path = path;
    s.estimate = estimate ? &*estimate : nullptr;
    s.set = set ? &*set : nullptr;
    s.baseline_set = baseline_set ? &*baseline_set : nullptr;
    s.mesh_flag = mesh_flag;
    s.mesh = mesh;
    return s;
  }
};

constexpr const char* kInMemory = "recording (in memory)";

/// What `model train --out` writes: the estimated surface and yield surfaces beside the model
/// (referenced by it), the model, its coverage file. Returns the lines the program prints.
std::vector<std::string> save_model(PyForceModel& s, const std::string& out) {
  std::vector<std::string> notes;
  if (s.estimate)  // no proxy columns: the estimated surface and yield surfaces beside it
    for (const std::string& f : eval::write_estimate_files(out, *s.estimate, s.m.provenance))
      notes.push_back("wrote " + f);
  datadriven::save_force_model(out, s.m);
  if (s.set)
    for (std::string& line :
         eval::write_training_coverage(*s.set, datadriven::coverage_path_for(out)))
      notes.push_back(std::move(line));
  s.path = out;
  return notes;
}

/// A recording argument: a file path (read in `units`) or an inhap.Recording (copied, converted
/// from `units`). `name` receives the path or kInMemory.
Recording recording_arg(const pyb::object& obj, const eval::RecordingUnits& units,
                        std::string& name, const char* what) {
  if (pyb::isinstance<pyb::str>(obj)) {
    name = obj.cast<std::string>();
    return eval::read_recording_in(name, units);
  }
  if (!pyb::isinstance<Recording>(obj))
    throw pyb::type_error(std::string(what) + ": expected a file path (str) or an inhap.Recording");
  name = kInMemory;
  Recording r = obj.cast<const Recording&>();
  eval::convert_units(r, units);
  return r;
}

PyForceModel train(const pyb::object& recording, const std::string& out, pyb::object progress,
                   const pyb::kwargs& kw) {
  const bool file = pyb::isinstance<pyb::str>(recording);
  if (!file && !pyb::isinstance<Recording>(recording))
    throw pyb::type_error("recording: expected a file path (str) or an inhap.Recording");
  eval::TrainFileOptions o = train_options(file ? recording.cast<std::string>() : kInMemory, kw);
  // A recording in memory is used in place unless its units need converting.
  const Recording* rec = file ? nullptr : &recording.cast<const Recording&>();
  std::optional<Recording> converted;
  if (rec && (o.units.time != "s" || o.units.length != "mm")) {
    converted = *rec;
    eval::convert_units(*converted, o.units);
    rec = &*converted;
  }
  eval::TrainFileResult res = with_progress(std::move(progress), [&](const Progress& cb) {
    o.progress = cb;
    return file ? eval::train_from_file(o) : eval::train_from_recording(*rec, o);
  });
  PyForceModel r;
  r.notes = res.notes;
  r.notes.push_back(eval::range_note(res.model.provenance, res.set, o.force_limit_n));
  r.m = std::move(res.model);
  r.estimate = std::move(res.estimate);
  r.set = std::move(res.set);
  r.baseline_set = std::move(res.baseline_set);
  if (!out.empty())
    for (std::string& line : save_model(r, out)) r.notes.push_back(std::move(line));
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

/// A model argument (a model file path or an inhap.ForceModel) and a mesh argument (a file path,
/// an inhap.Mesh or None) as the library's model source; `loaded` keeps a model read here.
struct ModelArg {
  std::optional<PyForceModel> loaded;
  const PyForceModel* model = nullptr;
  std::string name;  ///< the model file, or "" in memory
  eval::ModelSource source;
};

void model_arg(ModelArg& a, const pyb::object& model, const pyb::object& mesh) {
  if (pyb::isinstance<pyb::str>(model)) {
    a.loaded.emplace();
    a.loaded->path = model.cast<std::string>();
    a.loaded->m = datadriven::load_trained_force_model(a.loaded->path);
    a.model = &*a.loaded;
  } else if (pyb::isinstance<PyForceModel>(model)) {
    a.model = &model.cast<const PyForceModel&>();
  } else {
    throw pyb::type_error("model: expected a model file path (str) or an inhap.ForceModel");
  }
  a.name = a.model->path;
  std::string mesh_flag;
  const TriMesh* shape = nullptr;
  if (pyb::isinstance<pyb::str>(mesh))
    mesh_flag = mesh.cast<std::string>();
  else if (pyb::isinstance<TriMesh>(mesh))
    shape = &mesh.cast<const TriMesh&>();
  else if (!mesh.is_none())
    throw pyb::type_error("mesh: expected a mesh file path (str), an inhap.Mesh or None");
  a.source = a.model->source(mesh_flag, shape);
}

pyb::dict render(const pyb::object& model, const pyb::object& recording, const std::string& out,
                 const std::string& prefix, const std::string& contact_column,
                 double contact_threshold, const pyb::object& mesh, const std::string& time_unit,
                 const std::string& length_unit) {
  const auto spec = proxy_spec(prefix, contact_column, contact_threshold);
  ModelArg ma;
  model_arg(ma, model, mesh);
  std::string name;
  Recording rec = recording_arg(recording, units_of(time_unit, length_unit), name, "recording");
  eval::ReplayedFile r;
  eval::SupportShare support;
  with_progress(pyb::none(), [&](const Progress&) {
    r = eval::replay_recording(ma.source, std::move(rec), name, spec);
    if (!out.empty()) eval::write_rendered_csv(out, r, name, ma.name);
    support = eval::support_share(ma.source, r);
  });
  std::vector<double> contact(r.track.contact.begin(), r.track.contact.end());
  pyb::dict d;
  d["t"] = to_numpy(r.rec.t);
  d["p"] = to_numpy(r.rec.p);
  d["force"] = to_numpy(r.forces);
  d["measured"] = to_numpy(r.rec.f);
  d["q"] = to_numpy(r.track.q);
  d["contact"] = to_numpy(contact).attr("astype")("bool");
  d["support"] = eval::support_note(support);
  return d;
}

pyb::object evaluate(const pyb::object& model, const pyb::object& recording,
                     const std::string& prefix, const std::string& contact_column,
                     double contact_threshold, const pyb::object& mesh,
                     const std::string& time_unit, const std::string& length_unit,
                     const pyb::object& train) {
  const auto spec = proxy_spec(prefix, contact_column, contact_threshold);
  const auto units = units_of(time_unit, length_unit);
  ModelArg ma;
  model_arg(ma, model, mesh);
  std::string name, train_name;
  Recording rec = recording_arg(recording, units, name, "recording");
  std::optional<Recording> train_rec;
  if (!train.is_none() &&
      !(pyb::isinstance<pyb::str>(train) && train.cast<std::string>().empty())) {
    const datadriven::ForceModelProvenance& pv = ma.model->m.provenance;
    // A training file in the model's units (as `model eval --train`); in memory like `recording`.
    train_rec = recording_arg(
        train, pyb::isinstance<pyb::str>(train) ? units_of(pv.time_unit, pv.length_unit) : units,
        train_name, "train");
  }
  const eval::ModelEvalResult r = with_progress(pyb::none(), [&](const Progress&) {
    const eval::ReplayedFile rf = eval::replay_recording(ma.source, std::move(rec), name, spec);
    return eval::evaluate_model(ma.source, rf, name, spec, train_rec ? &*train_rec : nullptr,
                                train_name);
  });
  pyb::object d = json_to_python(r.json.dump());
  d["text"] = eval::model_eval_text(r);
  d["support_note"] = eval::support_note(r.support);
  d["baselines_note"] = r.baselines_note;
  return d;
}

pyb::dict evaluate_recordings(const pyb::object& train, const pyb::object& test,
                              const pyb::object& preset, const pyb::object& time_unit,
                              const pyb::object& length_unit, const pyb::object& contact_threshold,
                              const pyb::object& threads, pyb::object progress) {
  eval::TrainFileOptions o;
  eval::TrainRequest& q = o.request;
  // As the program: every option given counts as given (the preset fills in the rest).
  const auto given = [&](const pyb::object& v, const char* flag) {
    if (!v.is_none()) q.given.insert(flag);
    return !v.is_none();
  };
  if (given(preset, "--preset")) q.preset = preset.cast<std::string>();
  if (given(time_unit, "--time-unit")) o.units.time = time_unit.cast<std::string>();
  if (given(length_unit, "--length-unit")) o.units.length = length_unit.cast<std::string>();
  if (given(contact_threshold, "--contact-threshold"))
    o.proxy.contact_threshold_n = contact_threshold.cast<double>();
  if (given(threads, "--threads")) q.params.threads = threads.cast<int>();
  std::string train_name, test_name;
  const bool files = pyb::isinstance<pyb::str>(train) && pyb::isinstance<pyb::str>(test);
  std::optional<Recording> train_rec, test_rec;
  if (files) {
    o.recording = train.cast<std::string>();
    test_name = test.cast<std::string>();
  } else {
    train_rec = recording_arg(train, o.units, train_name, "train");
    test_rec = recording_arg(test, o.units, test_name, "test");
    o.recording = train_name;
  }
  eval::RecordingsEval e = with_progress(std::move(progress), [&](const Progress& cb) {
    o.progress = cb;
    return files ? eval::evaluate_recordings(o, test_name)
                 : eval::evaluate_recordings(*train_rec, std::move(*test_rec), o, test_name);
  });
  pyb::dict d(json_to_python(eval::recordings_json(e, test_name, files ? "" : train_name).dump()));
  d["text"] = eval::baseline_text(e.report);
  d["notes"] = e.train.notes;
  std::vector<double> scored(e.scored.begin(), e.scored.end());
  d["t"] = to_numpy(e.test.t);
  d["measured"] = to_numpy(e.test.f);
  d["rendered"] = to_numpy(e.rendered);
  d["scored"] = to_numpy(scored).attr("astype")("bool");
  return d;
}

}  // namespace

void register_model(pyb::module_& m) {
  pyb::class_<PyForceModel>(m, "ForceModel", R"doc(
A trained data-driven force model f = g(p, pdot, q) (thesis 4.4): r^3 RBFs per ||q - p|| bin,
with its provenance (training parameters and statistics). Positions mm, velocities mm/s,
forces N. A model trained from Python keeps its training samples and, when its proxy was
estimated, the estimated surface and yield surfaces: evaluate_force_model and
render_force_model use them without files.)doc")
      .def("save", &save_model, pyb::arg("path"),
           "Writes the model JSON (forces bit-identical after load) and, as `model train --out`, "
           "the estimated surface (<stem>.surface.ply) and yield surfaces (<stem>.sys.json) "
           "beside it and its coverage file; returns the lines the program prints about them.")
      .def(
          "summary",
          [](const PyForceModel& s, bool verbose) { return eval::train_summary(s.m, verbose); },
          pyb::arg("verbose") = false, "The report `model train` prints")
      .def("force", &model_forces, pyb::arg("p"), pyb::arg("v"), pyb::arg("q"),
           pyb::arg("n") = pyb::none(),
           "Model force (N, (N, 3)) for probe positions p (mm), velocities v (mm/s), proxies q "
           "(mm) and, for local-frame models, outward normals n at q; float64 (N, 3) C-order "
           "arrays used in place. Non-finite input gives zero force. Each row is evaluated on "
           "its own, so the sliding floor (which needs the proxy's previous tick) is not "
           "applied; the model's render/eval and inhap.Renderer.replay run the servo step, "
           "which applies it.")
      .def_readonly("notes", &PyForceModel::notes, "What training said (as the CLI's stderr)")
      .def_readonly("path", &PyForceModel::path,
                    "The model file it was read from or saved to ('' in memory)")
      .def_property_readonly(
          "estimated", [](const PyForceModel& s) { return s.estimate.has_value(); },
          "True when the proxy was estimated from the recording here (its "
          "surface and yield surfaces are kept)")
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
        r.path = path;
        return r;
      },
      pyb::arg("path"), "Reads and validates a model JSON (inhap.Error naming the file)");
  m.def("train_force_model", &train, pyb::arg("recording"), pyb::kw_only(), pyb::arg("out") = "",
        pyb::arg("progress") = true, R"doc(
Trains a model as `inhap model train` does, from a recording CSV (path) or an inhap.Recording
in memory (used in place; t s, p mm, f N unless time_unit/length_unit say otherwise): preset
'best' by default ('world', 'thesis'); every keyword given overrides the preset like the flag
of the same name (bins, centers, nonzeros, lambda_ratio, seed, design, features, tail,
tangent_mirror, stiffness_prior, shear_prior, friction_cone, sliding_floor, fallback,
fallback_near mm, fallback_far mm, fallback_normal_near mm, fallback_normal_far mm, solver 'cd'|'sparsa', feature_weights (3), bin_blend mm, threads,
modeling_range N, above_range 'keep'|'exclude', foaw_window samples, foaw_noise mm,
velocity_window s, force_limit N, proxy_prefix, contact_column, contact_threshold N, time_unit
's'|'ms', length_unit 'mm'|'m', mesh, sys). With proxy columns qx,qy,qz (mm) and a contact
column they are the proxy; without, the surface, normals, proxy and friction are estimated from
the recording (datadriven/estimate.hpp) and kept in the model. With out=PATH the model (and the
estimated surface and yield surfaces, and the coverage file) are written there. progress: True
(a tqdm bar when installed), False, or a callable(what, fraction, eta_s); Ctrl-C or an
exception of the callable stops the training within a fraction of a second.)doc");
  m.def("evaluate_force_model", &evaluate, pyb::arg("model"), pyb::arg("recording"),
        pyb::arg("proxy_prefix") = "q", pyb::arg("contact_column") = "contact",
        pyb::arg("contact_threshold") = 0.05, pyb::arg("mesh") = pyb::none(),
        pyb::arg("time_unit") = "s", pyb::arg("length_unit") = "mm",
        pyb::arg("train") = pyb::none(),
        "`inhap model eval`: replays a test recording (path or inhap.Recording) through the "
        "servo renderer of a model (path or inhap.ForceModel); returns the --json report as a "
        "dict (errors in N, eq. 4.27-4.31, the mean and k-NN baselines fitted on `train` (path "
        "or inhap.Recording), else on a model's training samples in memory, else on the "
        "training recording its file names) plus 'text' (what it prints). mesh: the shape mesh "
        "(path or inhap.Mesh) of a local-frame model. time_unit s|ms and length_unit mm|m: the "
        "recording's t and p columns.");
  m.def("render_force_model", &render, pyb::arg("model"), pyb::arg("recording"),
        pyb::arg("out") = "", pyb::arg("proxy_prefix") = "q",
        pyb::arg("contact_column") = "contact", pyb::arg("contact_threshold") = 0.05,
        pyb::arg("mesh") = pyb::none(), pyb::arg("time_unit") = "s", pyb::arg("length_unit") = "mm",
        "`inhap model render`: rendered forces of a recording (path or inhap.Recording) at "
        "servo rate by a model (path or inhap.ForceModel). Returns t (s), p (mm), force "
        "(rendered, N), measured (N), q (mm), contact, support (the training-support line); "
        "out=PATH also writes the CSV.");
  m.def("evaluate_recordings", &evaluate_recordings, pyb::arg("train"), pyb::arg("test"),
        pyb::kw_only(), pyb::arg("preset") = pyb::none(), pyb::arg("time_unit") = pyb::none(),
        pyb::arg("length_unit") = pyb::none(), pyb::arg("contact_threshold") = pyb::none(),
        pyb::arg("threads") = pyb::none(), pyb::arg("progress") = true,
        "`inhap eval recordings`: trains on `train` as `model train` with no flags (the proxy "
        "estimated when it has no proxy columns), renders `test` (paths or inhap.Recording, "
        "t s, p mm unless time_unit 's'|'ms' / length_unit 'mm'|'m') and scores both beside "
        "the baselines (mean force, k-NN on p and on (p, pdot)). Returns its --json dict plus "
        "'text' (what it prints), 'notes' (training's), and per test sample t (s), measured "
        "and rendered force (N, (N, 3)) and scored (bool).");
}

}  // namespace inhap::py
