// The virtual lab (record with truth), shape modeling by tapping (contacts with the knee
// estimate, reconstruction, comparison) and the `inhap eval` experiments with their results as
// dicts (the same JSON as the program's --json). Units: mm, N, s, N/mm.
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/contact/detector.hpp"
#include "inhap/contact/knee.hpp"
#include "inhap/contact/tapping.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/contacts_lab.hpp"
#include "inhap/eval/forces_lab.hpp"
#include "inhap/eval/forces_report.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/eval/lab_objects.hpp"
#include "inhap/eval/shape_files.hpp"
#include "inhap/eval/shape_study.hpp"
#include "inhap/eval/sys_files.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/eval/tca_report.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/physics.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::py {

namespace {

pyb::dict truth_dict(pyb::object self) {
  lab::TruthTable& t = self.cast<lab::LabRecording&>().truth;
  pyb::dict d;
  d["t"] = view(t.t, self);
  d["contact"] = pyb::array_t<int>(static_cast<pyb::ssize_t>(t.contact.size()), t.contact.data());
  d["tap"] = pyb::array_t<long>(static_cast<pyb::ssize_t>(t.tap.size()), t.tap.data());
  d["tc"] = view(t.tc, self);
  d["c"] = view(t.c, self);
  d["anchor"] = view(t.anchor, self);
  d["force"] = view(t.force, self);
  d["k"] = view(t.k, self);
  d["mu"] = view(t.mu, self);
  return d;
}

lab::LabRecording record(const std::string& scene, const std::string& scene_file,
                         const eval::LabRecordRequest& req, const std::string& out,
                         pyb::object progress) {
  const lab::Scene s = eval::pick_scene(scene_file.empty() ? scene : "", scene_file);
  const lab::RecordSpec spec = eval::lab_record_spec(req);
  return with_progress(std::move(progress), [&](const Progress& cb) {
    lab::LabRecording r =
        eval::downsample_recording(lab::record_scene(s, spec, cb), req.rate_hz, req.seed);
    if (!out.empty()) {
      eval::require_finite_recording(r.rec, out);
      lab::write_lab_recording(out, r);
    }
    return r;
  });
}

void bind_lab(pyb::module_& m) {
  pyb::class_<lab::LabRecording>(m, "LabRecording", R"doc(
A simulated recording and its ground truth. `recording` is what a real rig logs (t s, p mm,
compensated f N, raw rfx,rfy,rfz N); `truth` per tick: t, contact (0/1), tap (episode, -1 out of
contact), tc (true first-contact instant, s), c (contact point p(tc), mm, (N, 3)), anchor (true
proxy q, mm), force (noise-free, N), k (N/mm), mu. Float arrays are views (no copy).)doc")
      .def_property_readonly(
          "recording", [](lab::LabRecording& r) -> Recording& { return r.rec; },
          pyb::return_value_policy::reference_internal)
      .def_property_readonly("truth", &truth_dict)
      .def_readonly("comments", &lab::LabRecording::comments)
      .def(
          "write",
          [](const lab::LabRecording& r, const std::string& path) {
            lab::write_lab_recording(path, r);
          },
          pyb::arg("path"), "Writes PATH and PATH's .truth.csv sidecar atomically");
  m.def(
      "lab_record",
      [](const std::string& scene, const std::string& op, double seconds, std::uint64_t seed,
         const std::string& probe, const std::string& physics, bool noise, bool gravity,
         bool inertia, bool whole_object, const std::string& region, bool coverage, double rate,
         const std::string& scene_file, const std::string& out, pyb::object progress) {
        eval::LabRecordRequest q;
        q.rate_hz = rate;
        q.op = op;
        q.seconds = seconds;
        q.seed = seed;
        q.probe = probe;
        q.physics = physics;
        q.no_noise = !noise;
        q.no_gravity = !gravity;
        q.no_inertia = !inertia;
        q.whole_object = whole_object;
        q.region = region;
        q.coverage = coverage;
        return record(scene, scene_file, q, out, std::move(progress));
      },
      pyb::arg("scene") = "planar", pyb::arg("operator") = "explore", pyb::arg("seconds") = 60.0,
      pyb::arg("seed") = 1, pyb::arg("probe") = "sphere", pyb::arg("physics") = "builtin",
      pyb::arg("noise") = true, pyb::arg("gravity") = true, pyb::arg("inertia") = true,
      pyb::arg("whole_object") = false, pyb::arg("region") = "reachable",
      pyb::arg("coverage") = false, pyb::arg("rate") = 1000.0, pyb::arg("scene_file") = "",
      pyb::arg("out") = "", pyb::arg("progress") = true,
      "`inhap lab record`: simulates an operator (tap | explore | air) on a built-in scene (or "
      "scene_file JSON) for `seconds` s at 1 kHz with the sphere (8 mm) or tip probe. The same "
      "seed gives the same bytes as the program. The tap operator taps the reachable surface "
      "(region='reachable', the default; whole_object=True means the same) or the region seen "
      "from above (region='top'); rate < 1000 Hz keeps the tick nearest each "
      "jittered "
      "instant of a logger at that rate. out=PATH also writes PATH and its truth.");
  m.def("lab_scenes", &lab::builtin_scene_names, "Names of the built-in lab scenes");
  m.def(
      "lab_scene",
      [](const std::string& name, const std::string& out) {
        lab::save_scene(out, lab::builtin_scene(name));
      },
      pyb::arg("name"), pyb::arg("out"),
      "`inhap lab scene NAME --out OUT`: writes a built-in scene as an editable JSON file (use "
      "it with lab_record(scene_file=OUT)).");
  m.def("lab_scenes_table", &eval::scenes_table,
        "The table `inhap lab scenes` prints (stiffness at 5 N, N/mm)");
}

/// Contacts of a tapping recording with the options they were found with.
struct PyContacts {
  std::vector<Contact> c;
  std::vector<std::string> notes;
};

template <class T, class F>
pyb::array field(const PyContacts& s, F get) {
  pyb::array_t<T> a(static_cast<pyb::ssize_t>(s.c.size()));
  for (std::size_t i = 0; i < s.c.size(); ++i) a.mutable_data()[i] = static_cast<T>(get(s.c[i]));
  return a;
}

template <class F>
pyb::array points(const PyContacts& s, F get) {
  std::vector<Vec3> v(s.c.size());
  for (std::size_t i = 0; i < s.c.size(); ++i) v[i] = get(s.c[i]);
  return to_numpy(v);
}

ContactOptions contact_options(const std::string& method, double eps, std::size_t window,
                               std::size_t post, std::size_t min_contact, bool refine) {
  eval::ContactsRequest q;
  q.method = method;
  q.eps = eps;
  q.window = window;
  q.post = post;
  q.min_contact = min_contact;
  q.no_refine = !refine;
  return eval::contact_options(q);
}

void bind_contacts_class(pyb::module_& m) {
  pyb::class_<PyContacts>(m, "Contacts", R"doc(
Taps found in a recording (thesis 3.2): per tap the detection (t_detect s, p_detect mm), the
estimated true contact instant t_contact (s) and point (mm, (N, 3)), the force direction at the
peak (outward normal), peak_force (N) and whether the knee estimate was used.)doc")
      .def("__len__", [](const PyContacts& s) { return s.c.size(); })
      .def_readonly("notes", &PyContacts::notes)
      .def_property_readonly(
          "point",
          [](const PyContacts& s) { return points(s, [](const Contact& c) { return c.point; }); })
      .def_property_readonly("p_detect",
                             [](const PyContacts& s) {
                               return points(s, [](const Contact& c) { return c.p_detect; });
                             })
      .def_property_readonly("direction",
                             [](const PyContacts& s) {
                               return points(s, [](const Contact& c) { return c.direction; });
                             })
      .def_property_readonly("t_contact",
                             [](const PyContacts& s) {
                               return field<double>(s,
                                                    [](const Contact& c) { return c.t_contact; });
                             })
      .def_property_readonly("t_detect",
                             [](const PyContacts& s) {
                               return field<double>(s, [](const Contact& c) { return c.t_detect; });
                             })
      .def_property_readonly("peak_force",
                             [](const PyContacts& s) {
                               return field<double>(s,
                                                    [](const Contact& c) { return c.peak_force; });
                             })
      .def_property_readonly("estimated",
                             [](const PyContacts& s) {
                               return field<bool>(s, [](const Contact& c) { return c.estimated; });
                             })
      .def(
          "write",
          [](const PyContacts& s, const std::string& path, bool ascii) {
            write_contact_points(path, s.c, ascii);
          },
          pyb::arg("path"), pyb::arg("ascii") = false,
          "The point PLY of `inhap shape contacts` (x,y,z mm, nx,ny,nz, tap, t_contact, ...)");
}

void bind_contact_functions(pyb::module_& m) {
  m.def(
      "detect_contacts",
      [](const pyb::object& t, const pyb::object& p, const pyb::object& f,
         const std::string& method, double eps, std::size_t window, std::size_t post,
         std::size_t min_contact, bool refine) {
        const pyb::array ta = checked(t, "t", 0);
        const auto n = static_cast<std::size_t>(ta.shape(0));
        const pyb::array pa = checked(p, "p", 3, n), fa = checked(f, "f", 3, n);
        const ContactOptions o = contact_options(method, eps, window, post, min_contact, refine);
        PyContacts r;
        pyb::gil_scoped_release release;
        r.c = detect_contacts(double_span(ta), vec3_span(pa), vec3_span(fa), o, &r.notes);
        return r;
      },
      pyb::arg("t"), pyb::arg("p"), pyb::arg("f"), pyb::arg("method") = "estimate",
      pyb::arg("eps") = 0.2, pyb::arg("window") = 100, pyb::arg("post") = 0,
      pyb::arg("min_contact") = 5, pyb::arg("refine") = true,
      "Taps in arrays t (s, (N,)), p (mm, (N, 3)), f (compensated contact force N, (N, 3)), "
      "used in place: contact when |f| > eps N; method 'estimate' fits the two-segment knee "
      "over `window` samples before detection, 'threshold' takes p(t_d).");
  m.def(
      "fit_knee",
      [](const pyb::object& t, const pyb::object& f, bool refine) {
        const pyb::array ta = checked(t, "t", 0);
        const auto n = static_cast<std::size_t>(ta.shape(0));
        const pyb::array fa = checked(f, "f", 0, n);
        const KneeFit k = fit_knee(double_span(ta), double_span(fa), KneeOptions{refine});
        pyb::dict d;
        d["valid"] = k.valid;
        d["tc"] = k.tc;
        d["index"] = k.index;
        d["g"] = pyb::make_tuple(k.g0, k.gc, k.gd);
        d["sse"] = k.sse;
        return d;
      },
      pyb::arg("t"), pyb::arg("f"), pyb::arg("refine") = true,
      "The knee (true contact instant) of a force-magnitude profile (thesis 3.2.2): two "
      "connected segments fitted to f (N, (N,)) over t (s, (N,), increasing, N >= 4), exact over "
      "every sample then refined between samples. Returns valid, tc (s), index, g = (g0, gc, "
      "gd) (N) and sse (N^2).");
  m.def(
      "contacts_from_recording",
      [](const Recording& rec, const std::string& method, double eps, std::size_t window,
         std::size_t post, std::size_t min_contact, bool refine, const std::string& force) {
        eval::ContactsRequest q;
        q.force = force;
        const ContactOptions o = contact_options(method, eps, window, post, min_contact, refine);
        PyContacts r;
        pyb::gil_scoped_release release;
        TappingResult res = contacts_from_recording(rec, o, eval::force_source(q));
        r.c = std::move(res.contacts);
        r.notes = std::move(res.notes);
        return r;
      },
      pyb::arg("recording"), pyb::arg("method") = "estimate", pyb::arg("eps") = 0.2,
      pyb::arg("window") = 100, pyb::arg("post") = 0, pyb::arg("min_contact") = 5,
      pyb::arg("refine") = true, pyb::arg("force") = "auto",
      "`inhap shape contacts` on a Recording: force 'auto' compensates the raw rfx,rfy,rfz "
      "columns offline when present, 'recorded' uses fx,fy,fz, 'raw' requires rf*.");
}

pyb::tuple reconstruct(const pyb::object& pts, const pyb::object& dirs, const std::string& alpha,
                       const std::string& mode, std::size_t taubin, std::size_t subdivide,
                       std::size_t jet_k, std::size_t outlier_k) {
  eval::ReconstructRequest q;
  q.alpha = alpha;
  q.mode = mode;
  q.taubin = taubin;
  q.subdivide = subdivide;
  q.jet_k = jet_k;
  q.outlier_k = outlier_k;
  const ReconstructOptions o = eval::reconstruct_options(q);
  const pyb::array pa = checked(pts, "points", 3);
  const auto n = static_cast<std::size_t>(pa.shape(0));
  pyb::array da;
  if (!dirs.is_none()) da = checked(dirs, "directions", 3, n);
  ReconstructReport rep;
  TriMesh mesh;
  {
    pyb::gil_scoped_release release;
    mesh = reconstruct_surface(vec3_span(pa),
                               dirs.is_none() ? std::span<const Vec3>() : vec3_span(da), o, &rep);
  }
  const std::string text = eval::reconstruct_summary(rep, o, mode, !dirs.is_none());
  return pyb::make_tuple(std::move(mesh), text);
}

void bind_shape(pyb::module_& m) {
  m.def("reconstruct_surface", &reconstruct, pyb::arg("points"),
        pyb::arg("directions") = pyb::none(), pyb::arg("alpha") = "auto",
        pyb::arg("mode") = "shell", pyb::arg("taubin") = eval::ReconstructRequest{}.taubin,
        pyb::arg("subdivide") = eval::ReconstructRequest{}.subdivide,
        pyb::arg("jet_k") = eval::ReconstructRequest{}.jet_k,
        pyb::arg("outlier_k") = eval::ReconstructRequest{}.outlier_k,
        "`inhap shape reconstruct`: mesh from contact points (mm, float64 (N, 3), used in "
        "place) and optional outward directions: outliers, jet projection, alpha shape ('auto' "
        "or a radius in mm), Taubin smoothing, sqrt(3) subdivision. Returns (Mesh, summary).");
  m.def(
      "compare_meshes",
      [](const TriMesh& a, const TriMesh& b, bool icp, double density, double crop_distance,
         bool overlap_only, const std::string& a_name, const std::string& b_name) {
        eval::CompareRequest q;
        q.icp = icp;
        q.density = density;
        q.crop_distance = crop_distance;
        q.overlap_only = overlap_only;
        std::string text;
        {
          pyb::gil_scoped_release release;
          text = eval::compare_json(eval::compare_meshes(a_name, a, b_name, b, q));
        }
        return json_to_python(text);
      },
      pyb::arg("a"), pyb::arg("b"), pyb::arg("icp") = false, pyb::arg("density") = 4.0,
      pyb::arg("crop_distance") = 0.0, pyb::arg("overlap_only") = false, pyb::arg("a_name") = "a",
      pyb::arg("b_name") = "b",
      "`inhap shape compare`: symmetric Hausdorff, mean and RMS distances (mm) between two "
      "meshes (a moved by ICP onto b when icp), the --json report as a dict.");
}

pyb::object eval_contacts(std::size_t taps, std::uint64_t seed, double eps, std::size_t window,
                          const std::string& physics, pyb::object progress) {
  eval::ContactObjectOptions o;
  o.taps = taps;
  o.seed = seed;
  o.eps = eps;
  o.window = window;
  o.physics = lab::physics_from_string(physics);
  const std::string text = with_progress(std::move(progress), [&](const Progress& cb) {
    nlohmann::json objects = nlohmann::json::array();
    for (const std::string& name : lab::tapping_scene_names()) {
      o.progress = [&](const std::string&, double f, double eta) {
        if (cb) cb("eval contacts " + name, f, eta);
      };
      const eval::ContactObjectResult r = eval::run_contact_object(name, o);
      if (!r.skipped) objects.push_back(eval::contact_object_json(r));
    }
    return eval::contacts_run_json(objects, o.eps, o.window, o.seed).dump();
  });
  return json_to_python(text);
}

pyb::object eval_forces(const std::vector<std::string>& scenes, std::uint64_t train_seed,
                        std::uint64_t test_seed, bool quick, bool baselines,
                        const std::string& proxy, const std::string& physics,
                        const std::string& keep, int threads, double rate, pyb::object progress) {
  eval::ForceLabOptions fo;
  fo.rate_hz = rate;
  fo.train_seed = train_seed;
  fo.test_seed = test_seed;
  fo.quick = quick;
  fo.baselines = baselines;
  fo.proxy = proxy;
  fo.keep = keep;
  fo.params.threads = threads;
  fo.physics = lab::physics_from_string(physics);
  const std::string text = with_progress(std::move(progress), [&](const Progress& cb) {
    nlohmann::ordered_json out = eval::forces_report_head(physics, proxy);
    out["objects"] = nlohmann::ordered_json::array();
    for (const std::string& s : scenes) {
      fo.scene = s;
      fo.progress = cb;
      out["objects"].push_back(
          nlohmann::ordered_json::parse(eval::force_lab_json(eval::evaluate_forces_on_lab(fo))));
    }
    return out.dump();
  });
  return json_to_python(text);
}

pyb::object eval_shape(const std::vector<std::string>& objects, std::size_t taps,
                       const eval::ShapeEvalSettings& st, const std::string& bunny,
                       pyb::object progress) {
  const std::string text = with_progress(std::move(progress), [&](const Progress& cb) {
    nlohmann::json out = nlohmann::json::array();
    for (const eval::ShapeTarget& t : eval::shape_targets(st.top_only, objects, taps, st.quick)) {
      if (t.name == "bunny" && bunny.empty())
        throw Error("eval_shape: the bunny needs bunny=PATH to bun_zipper.ply");
      const lab::Scene scene = eval::shape_target_scene(t.name, t.name == "bunny" ? bunny : "");
      if (st.physics == lab::Physics::kMujoco && !lab::mujoco_represents(scene.object.shape()))
        continue;  // as the program: skipped
      eval::ShapeObjectOptions o = eval::shape_object_options(t.taps, st);
      o.progress = [&](const std::string&, double f, double eta) {
        if (cb) cb("eval shape " + t.name, f, eta);
      };
      out.push_back(eval::shape_object_json(t.name, eval::run_shape_object(scene, o)));
    }
    return eval::shape_run_json(out, st).dump();
  });
  return json_to_python(text);
}

void bind_eval_shape(pyb::module_& m) {
  m.def(
      "eval_shape",
      [](const std::vector<std::string>& objects, std::size_t taps, std::uint64_t seed, bool quick,
         bool top_only, bool icp, double region, double rim_margin, bool normal_overlap,
         const std::string& physics, const std::string& bunny, pyb::object progress) {
        eval::ShapeEvalSettings st;
        st.seed = seed;
        st.quick = quick;
        st.top_only = top_only;
        st.icp = icp;
        st.region_mm = region;
        st.rim_margin_mm = rim_margin;
        st.no_normal_overlap = !normal_overlap;
        st.physics = lab::physics_from_string(physics);
        return eval_shape(objects, taps, st, bunny, std::move(progress));
      },
      pyb::arg("objects") =
          std::vector<std::string>{"foam-ball", "ridged-silicone", "silicone-hemisphere"},
      pyb::arg("taps") = 0, pyb::arg("seed") = 1, pyb::arg("quick") = false,
      pyb::arg("top_only") = false, pyb::arg("icp") = false,
      pyb::arg("region") = eval::ShapeEvalSettings{}.region_mm,
      pyb::arg("rim_margin") = eval::ShapeEvalSettings{}.rim_margin_mm,
      pyb::arg("normal_overlap") = true, pyb::arg("physics") = "builtin", pyb::arg("bunny") = "",
      pyb::arg("progress") = true,
      "`inhap eval shape` (thesis Table 3.1): tap whole lab objects (taps 0: the thesis' "
      "counts), reconstruct from estimated and thresholded contact points, Hausdorff and mean "
      "distance (mm) to the reference, coverage; 'bunny' in objects needs bunny=PATH to "
      "bun_zipper.ply. The --json report as a dict.");
}

void bind_eval(pyb::module_& m) {
  m.def("eval_contacts", &eval_contacts, pyb::arg("taps") = 100, pyb::arg("seed") = 1,
        pyb::arg("eps") = 0.2, pyb::arg("window") = 100, pyb::arg("physics") = "builtin",
        pyb::arg("progress") = true,
        "`inhap eval contacts` (thesis fig. 3.4): contact-point error (mm) of the knee estimate "
        "and of thresholding on the lab's tapping objects; the --json report as a dict.");
  m.def("eval_forces", &eval_forces,
        pyb::arg("scenes") = std::vector<std::string>{"planar", "dome"}, pyb::arg("train_seed") = 1,
        pyb::arg("test_seed") = 2, pyb::arg("quick") = false, pyb::arg("baselines") = true,
        pyb::arg("proxy") = "estimated", pyb::arg("physics") = "builtin", pyb::arg("keep") = "",
        pyb::arg("threads") = 0, pyb::arg("rate") = 1000.0, pyb::arg("progress") = true,
        "`inhap eval forces` (thesis 4.5) with the program's defaults (preset 'best'): "
        "palpate, record training and held-out test runs, train, replay, score (N); the --json "
        "report as a dict. quick: recordings 2x shorter.");
  m.def(
      "eval_sys",
      [](const std::vector<std::string>& scenes, double seconds, std::uint64_t seed, bool quick,
         const std::string& physics, pyb::object progress) {
        eval::SysLabOptions so;
        so.seconds = seconds;
        so.seed = seed;
        so.quick = quick;
        so.physics = physics;
        const std::string text = with_progress(std::move(progress), [&](const Progress& cb) {
          nlohmann::json objects = nlohmann::json::array();
          for (const std::string& s : scenes) {
            so.scene = s;
            so.progress = cb;
            objects.push_back(eval::sys_lab_json(s, eval::evaluate_sys_on_lab(so)));
          }
          return nlohmann::json{{"objects", objects}}.dump();
        });
        return json_to_python(text);
      },
      pyb::arg("scenes") = std::vector<std::string>{"planar", "dome"},
      pyb::arg("seconds") = eval::SysLabOptions{}.seconds, pyb::arg("seed") = 1,
      pyb::arg("quick") = false, pyb::arg("physics") = "builtin", pyb::arg("progress") = true,
      "`inhap eval sys` (thesis 4.3): palpation, elastic limits vs the lab's mu f_N, proxy vs "
      "the true anchor (mm); the --json report as a dict.");
  m.def(
      "eval_tca",
      [](std::uint64_t seed, int participants, int trials, int threads, bool quick,
         const std::string& afm, pyb::object progress) {
        eval::TcaStudyOptions so;
        so.seed = seed;
        so.participants = quick ? std::min(participants, 4) : participants;
        so.trials = quick ? std::min(trials, 2) : trials;
        so.threads = threads;
        const std::string text = with_progress(std::move(progress), [&](const Progress& cb) {
          so.progress = cb;
          return eval::tca_eval_json(eval::run_tca_eval(so, afm)).dump();
        });
        return json_to_python(text);
      },
      pyb::arg("seed") = 1, pyb::arg("participants") = eval::TcaStudyOptions{}.participants,
      pyb::arg("trials") = eval::TcaStudyOptions{}.trials,
      pyb::arg("threads") = eval::TcaStudyOptions{}.threads, pyb::arg("quick") = false,
      pyb::arg("afm") = "", pyb::arg("progress") = true,
      "`inhap eval tca` (thesis 5.4): the virtual user study of TCA-MESH vs CBA; the --json "
      "report as a dict.");
}

}  // namespace

void register_lab(pyb::module_& m) {
  bind_lab(m);
  bind_contacts_class(m);
  bind_contact_functions(m);
  bind_shape(m);
  bind_eval(m);
  bind_eval_shape(m);
}

}  // namespace inhap::py
