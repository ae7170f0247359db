// `inhap eval contacts` and `inhap eval shape`: thesis fig. 3.4 and Table 3.1 on the virtual
// lab's tapping objects (simulated operator, tip probe, ground truth per tap).
// Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "command.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/contact/tapping.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace {

using namespace inhap;
using namespace inhap::cli;
using namespace inhap::eval;
using json = nlohmann::json;

// --- recordings with ground truth ------------------------------------------------------------

struct Summary {
  double median = 0, p95 = 0, max = 0;
};
Summary summarize(std::vector<double> v) {
  Summary s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {  // linear interpolation between order statistics
    const double x = q * static_cast<double>(v.size() - 1);
    const auto i = static_cast<std::size_t>(x);
    const double w = x - static_cast<double>(i);
    return i + 1 < v.size() ? (1 - w) * v[i] + w * v[i + 1] : v[i];
  };
  s.median = at(0.5);
  s.p95 = at(0.95);
  s.max = v.back();
  return s;
}
json to_json(const Summary& s) {
  return {{"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

// --- eval contacts ----------------------------------------------------------------------------

struct EvalContactsArgs {
  std::string json_out;
  std::size_t taps = 100;
  std::uint64_t seed = 1;
  double eps = 0.2;
  std::size_t window = 100;
  std::string physics = "builtin";
};

void run_eval_contacts(const EvalContactsArgs& a) {
  json objects = json::array();
  fmt::print("{:<21} {:>8} {:>5} | {:>25} | {:>25} | {:>5}\n", "object", "k N/mm", "taps",
             "estimate mm (med/p95/max)", "threshold mm (med/p95/max)", "ratio");
  for (const std::string& name : lab::tapping_scene_names()) {
    const lab::Scene scene = lab::builtin_scene(name);
    const lab::Physics physics = lab::physics_from_string(a.physics);
    if (physics == lab::Physics::mujoco && !lab::mujoco_represents(scene.object.shape())) {
      fmt::print("{:<21} skipped: MuJoCo cannot represent a {} shape\n", name,
                 scene.object.shape().type_name());
      continue;
    }
    const lab::LabRecording rec = record_taps(
        scene, a.taps, a.seed, [&](double f) { cli::progress("eval contacts " + name, f, 0); },
        physics);
    ContactOptions est, thr;
    est.eps_f = thr.eps_f = a.eps;
    est.window = thr.window = a.window;
    thr.method = ContactMethod::Threshold;
    const MatchedContacts me = match_contacts(rec, est, a.taps),
                          mt = match_contacts(rec, thr, a.taps);
    const Summary se = summarize(me.error), st = summarize(mt.error);
    const double k = summarize(me.stiffness).median;
    fmt::print(
        "{:<21} {:>8.2f} {:>5} | {:>7.3f} {:>7.3f} {:>9.3f} | {:>7.3f} {:>7.3f} {:>9.3f} | "
        "{:>5.1f}\n",
        name, k, me.contacts.size(), se.median, se.p95, se.max, st.median, st.p95, st.max,
        se.median > 0 ? st.median / se.median : 0.0);
    objects.push_back({{"name", name},
                       {"stiffness_n_per_mm", k},
                       {"taps", me.contacts.size()},
                       {"false_detections", me.false_detections},
                       {"estimate_mm", to_json(se)},
                       {"threshold_mm", to_json(st)}});
  }
  const json out = {{"objects", objects},
                    {"units", "mm; stiffness N/mm (effective, at 5 N)"},
                    {"eps_f_n", a.eps},
                    {"window_samples", a.window},
                    {"seed", a.seed}};
  if (!a.json_out.empty()) {
    write_file_atomic(a.json_out, out.dump(2) + "\n");
    fmt::print("wrote {}\n", a.json_out);
  }
}

// --- eval shape -------------------------------------------------------------------------------

struct EvalShapeArgs {
  std::string json_out, out_dir;
  std::vector<std::string> objects;
  std::size_t taps = 0;  ///< 0: the thesis' counts
  std::uint64_t seed = 1;
  double region_mm = 5.0, rim_margin_mm = 1.0;
  bool icp = false, no_normal_overlap = false;
  std::string physics = "builtin";
};

ShapeVariant run_variant(const lab::LabRecording& rec, ContactMethod method, std::size_t taps,
                         const TriMesh& reference, const EvalShapeArgs& a, const std::string& tag) {
  ShapeCompareOptions co;
  co.icp = a.icp;
  co.region_mm = a.region_mm;
  co.rim_margin_mm = a.rim_margin_mm;
  co.normal_overlap = !a.no_normal_overlap;
  ShapeVariant v = reconstruct_and_compare(rec, method, taps, reference, co);
  if (!a.out_dir.empty()) {  // temporaries of the command's OutputTransaction
    write_contact_points(a.out_dir + "/" + tag + ".points.ply", v.matched.contacts);
    TriMesh colored = v.mesh;
    colored.set_property("error", v.cmp.a_vertex_error);
    write_mesh(a.out_dir + "/" + tag + ".mesh.ply", colored);
  }
  return v;
}

void run_eval_shape(const EvalShapeArgs& a) {
  // All outputs or none: the folder and the JSON path are checked before the taps (minutes), and
  // every file is renamed into place after the last one is written.
  std::optional<OutputFolder> folder;
  if (!a.out_dir.empty()) folder.emplace(a.out_dir);
  if (!a.json_out.empty()) check_output_path(a.json_out);
  OutputTransaction tx;
  struct Target {
    const char* name;
    std::size_t taps;
  };
  const Target targets[] = {
      {"foam-ball", 1000}, {"ridged-silicone", 950}, {"silicone-hemisphere", 300}};
  json objects = json::array();
  fmt::print("{:<21} {:>6} {:>8} {:>8} | {:>21} | {:>21}\n", "object", "points", "vertices",
             "faces", "hausdorff mm est/thr", "mean mm est/thr");
  for (Target t : targets) {
    if (!a.objects.empty() &&
        std::find(a.objects.begin(), a.objects.end(), t.name) == a.objects.end())
      continue;
    if (a.taps > 0) t.taps = a.taps;
    const lab::Scene scene = lab::builtin_scene(t.name);
    const lab::Physics physics = lab::physics_from_string(a.physics);
    if (physics == lab::Physics::mujoco && !lab::mujoco_represents(scene.object.shape())) {
      fmt::print("{:<21} skipped: MuJoCo cannot represent a {} shape\n", t.name,
                 scene.object.shape().type_name());
      continue;
    }
    const lab::LabRecording rec = record_taps(
        scene, t.taps, a.seed,
        [&](double f) { cli::progress(std::string("eval shape ") + t.name, f, 0); }, physics);
    const TriMesh reference = reference_mesh(scene.object.shape());
    const ShapeVariant e = run_variant(rec, ContactMethod::Estimate, t.taps, reference, a,
                                       std::string(t.name) + ".estimate");
    const ShapeVariant s = run_variant(rec, ContactMethod::Threshold, t.taps, reference, a,
                                       std::string(t.name) + ".threshold");
    if (!a.out_dir.empty()) write_mesh(a.out_dir + "/" + t.name + ".reference.ply", reference);
    fmt::print("{:<21} {:>6} {:>8} {:>8} | {:>10.3f} {:>10.3f} | {:>10.3f} {:>10.3f}\n", t.name,
               e.points, e.vertices, e.faces, e.cmp.hausdorff, s.cmp.hausdorff, e.cmp.mean,
               s.cmp.mean);
    objects.push_back(
        {{"name", t.name},
         {"points", e.points},
         {"vertices", e.vertices},
         {"faces", e.faces},
         {"hausdorff_mm", {{"estimate", e.cmp.hausdorff}, {"threshold", s.cmp.hausdorff}}},
         {"mean_mm", {{"estimate", e.cmp.mean}, {"threshold", s.cmp.mean}}},
         {"rms_mm", {{"estimate", e.cmp.rms}, {"threshold", s.cmp.rms}}},
         {"threshold_variant",
          {{"points", s.points}, {"vertices", s.vertices}, {"faces", s.faces}}}});
  }
  const json out = {
      {"objects", objects},
      {"units", "mm"},
      {"common_region",
       fmt::format("reference within {} mm of the true contact points, overlap only", a.region_mm)},
      {"icp", a.icp},
      {"normal_overlap", !a.no_normal_overlap},
      {"seed", a.seed}};
  if (!a.json_out.empty()) write_file_atomic(a.json_out, out.dump(2) + "\n");
  tx.commit();
  if (folder) folder->keep();
  if (!a.json_out.empty()) fmt::print("wrote {}\n", a.json_out);
  if (!a.out_dir.empty()) fmt::print("wrote the meshes and points into {}\n", a.out_dir);
}

void register_eval_shape(CLI::App& app) {
  CLI::App* eval;
  try {
    eval = app.get_subcommand("eval");
  } catch (const CLI::OptionNotFound&) {
    eval = app.add_subcommand("eval", "Reproduce the thesis' evaluations on the virtual lab.");
    eval->require_subcommand(1);
  }
  auto c = std::make_shared<EvalContactsArgs>();
  auto* contacts = eval->add_subcommand(
      "contacts",
      "Thesis fig. 3.4: contact-point error (mm) of true-contact estimation and of plain\n"
      "thresholding on the five lab tapping objects (tip probe, simulated operator).");
  contacts->add_option("--json", c->json_out, "write the numbers as JSON");
  contacts->add_option("--taps", c->taps, "taps per object")->check(CLI::Range(1, 100000));
  contacts->add_option("--seed", c->seed, "random seed of the lab (same seed, same numbers)");
  contacts
      ->add_option("--physics", c->physics,
                   "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent "
                   "are skipped)")
      ->capture_default_str()
      ->check(CLI::IsMember({"builtin", "mujoco"}));
  contacts->add_option("--eps", c->eps, "contact threshold, N")->check(CLI::PositiveNumber);
  contacts->add_option("--window", c->window, "knee-fit window, samples")
      ->check(CLI::Range(4, 100000));
  contacts->callback([c] { run_eval_contacts(*c); });

  auto s = std::make_shared<EvalShapeArgs>();
  auto* shape = eval->add_subcommand(
      "shape",
      "Thesis Table 3.1: reconstruct the lab foam ball (1000 taps), ridged silicone (950) and\n"
      "silicone hemisphere (300) from estimated and from thresholded contact points; Hausdorff\n"
      "and mean distance (mm) to the true surface over the common (tapped) region.");
  shape->add_option("--json", s->json_out, "write the numbers as JSON");
  shape->add_option("--seed", s->seed, "random seed of the lab");
  shape
      ->add_option("--physics", s->physics,
                   "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent are "
                   "skipped)")
      ->capture_default_str()
      ->check(CLI::IsMember({"builtin", "mujoco"}));
  shape->add_option("--objects", s->objects, "only these objects (default: all three)")
      ->delimiter(',')
      ->check(CLI::IsMember({"foam-ball", "ridged-silicone", "silicone-hemisphere"}));
  shape->add_option("--taps", s->taps, "taps per object instead of the thesis' 1000/950/300")
      ->check(CLI::Range(20, 100000));
  shape
      ->add_option("--region", s->region_mm,
                   "common region: reference within this distance of the true contact points, mm")
      ->check(CLI::PositiveNumber);
  shape
      ->add_option("--rim-margin", s->rim_margin_mm,
                   "common region: drop reference samples whose closest point on the\n"
                   "reconstruction is within this distance of its rim, mm")
      ->check(CLI::NonNegativeNumber);
  shape->add_flag("--no-normal-overlap", s->no_normal_overlap,
                  "common region: keep samples whose normal line misses the other surface (the\n"
                  "rim test alone, as before; counts e.g. the slab's untapped end walls)");
  shape->add_flag("--icp", s->icp, "ICP-align each reconstruction onto the reference first");
  shape->add_option(
      "--out-dir", s->out_dir,
      "also write points, meshes (vertex property 'error', mm) and references (created if\n"
      "missing; all files of the run or none)");
  shape->callback([s] { run_eval_shape(*s); });
}

}  // namespace

INHAP_COMMAND(80, "eval-shape", register_eval_shape);
