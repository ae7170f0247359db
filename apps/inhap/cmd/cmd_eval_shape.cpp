// `inhap eval contacts` and `inhap eval shape`: thesis fig. 3.4 and Table 3.1 on the virtual
// lab's tapping objects (simulated operator, tip probe, ground truth per tap).
// Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "command.hpp"
#include "demo/demo_strokes.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/contacts_lab.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/eval/shape_study.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/compare.hpp"

namespace {

using namespace inhap;
using namespace inhap::cli;
using namespace inhap::eval;
using json = nlohmann::json;

json to_json(const ErrorSummary& s) {
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
  ContactObjectOptions o;
  o.taps = a.taps;
  o.seed = a.seed;
  o.eps = a.eps;
  o.window = a.window;
  o.physics = lab::physics_from_string(a.physics);
  for (const std::string& name : lab::tapping_scene_names()) {
    o.progress = [&](const std::string&, double f, double) {
      cli::progress("eval contacts " + name, f, 0);
    };
    const ContactObjectResult r = run_contact_object(name, o);
    if (r.skipped) {
      fmt::print("{:<21} skipped: MuJoCo cannot represent a {} shape\n", name, r.skipped_shape);
      continue;
    }
    const ErrorSummary &se = r.estimate, &st = r.threshold;
    fmt::print(
        "{:<21} {:>8.2f} {:>5} | {:>7.3f} {:>7.3f} {:>9.3f} | {:>7.3f} {:>7.3f} {:>9.3f} | "
        "{:>5.1f}\n",
        name, r.stiffness_n_per_mm, r.taps, se.median, se.p95, se.max, st.median, st.p95, st.max,
        se.median > 0 ? st.median / se.median : 0.0);
    objects.push_back({{"name", name},
                       {"stiffness_n_per_mm", r.stiffness_n_per_mm},
                       {"taps", r.taps},
                       {"false_detections", r.false_detections},
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
  std::string json_out, out_dir, data;
  std::vector<std::string> objects;
  std::size_t taps = 0;  ///< 0: the thesis' counts
  std::uint64_t seed = 1;
  double region_mm = 5.0, rim_margin_mm = 1.0;
  bool icp = false, no_normal_overlap = false, quick = false, top_only = false;
  std::string physics = "builtin";
};

/// Writes one variant's points and error-coloured mesh (temporaries of the command's
/// OutputTransaction).
void write_variant(const std::string& dir, const std::string& tag, const ShapeVariant& v) {
  write_contact_points(dir + "/" + tag + ".points.ply", v.matched.contacts);
  TriMesh colored = v.mesh;
  colored.set_property("error", v.cmp.a_vertex_error);
  write_mesh(dir + "/" + tag + ".mesh.ply", colored);
}

struct ShapeTarget {
  std::string name;
  std::size_t taps;
};

/// Records, reconstructs and scores one object (eval::run_shape_object); prints its row and
/// returns its JSON.
json eval_shape_object(const ShapeTarget& t, const lab::Scene& scene, const EvalShapeArgs& a) {
  ShapeObjectOptions o;
  o.taps = t.taps;
  o.seed = a.seed;
  o.physics = lab::physics_from_string(a.physics);
  o.tap.whole_object = !a.top_only;
  o.compare.icp = a.icp;
  o.compare.region_mm = a.region_mm;
  o.compare.rim_margin_mm = a.rim_margin_mm;
  o.compare.normal_overlap = !a.no_normal_overlap;
  o.compare.uncropped_reconstruction = !a.top_only;
  o.score_reachable_part = !a.top_only;
  o.coverage_samples = a.quick ? 5000 : 20000;
  o.count_entry_sides = true;
  o.progress = [&](const std::string&, double f, double) {
    cli::progress("eval shape " + t.name, f, 0);
  };
  const ShapeObjectResult r = run_shape_object(scene, o);
  const ShapeVariant &e = r.estimate, &s = r.threshold;
  if (!a.out_dir.empty()) {
    write_variant(a.out_dir, t.name + ".estimate", e);
    write_variant(a.out_dir, t.name + ".threshold", s);
    write_mesh(a.out_dir + "/" + t.name + ".reference.ply", r.reference);
  }
  fmt::print(
      "{:<21} {:>6} {:>8} {:>8} | {:>10.3f} {:>10.3f} | {:>10.3f} {:>10.3f} | {:>8.3f} {:>7.1f} "
      "{:>5}\n",
      t.name, e.points, e.vertices, e.faces, e.cmp.hausdorff, s.cmp.hausdorff, e.cmp.mean,
      s.cmp.mean, r.coverage, r.taps_per_minute, r.sides.far_side_first_contacts);
  auto side = [](const OneSided& d) { return json{{"max", d.max}, {"mean", d.mean}}; };
  return {
      {"name", t.name},
      {"points", e.points},
      {"vertices", e.vertices},
      {"faces", e.faces},
      {"hausdorff_mm", {{"estimate", e.cmp.hausdorff}, {"threshold", s.cmp.hausdorff}}},
      {"mean_mm", {{"estimate", e.cmp.mean}, {"threshold", s.cmp.mean}}},
      {"rms_mm", {{"estimate", e.cmp.rms}, {"threshold", s.cmp.rms}}},
      {"threshold_variant", {{"points", s.points}, {"vertices", s.vertices}, {"faces", s.faces}}},
      {"coverage", r.coverage},
      {"taps_per_minute", r.taps_per_minute},
      {"recording_s", r.recording_s},
      {"reconstruction_to_reference_mm",
       {{"estimate", side(e.cmp.a_to_b)}, {"threshold", side(s.cmp.a_to_b)}}},
      {"reference_to_reconstruction_mm",
       {{"estimate", side(e.cmp.b_to_a)}, {"threshold", side(s.cmp.b_to_a)}}},
      {"episodes", r.sides.episodes},
      {"far_side_first_contacts", r.sides.far_side_first_contacts},
      {"force_reversals", r.sides.force_reversals}};
}

void run_eval_shape(const EvalShapeArgs& a) {
  // All outputs or none: the folder and the JSON path are checked before the taps (minutes), and
  // every file is renamed into place after the last one is written.
  std::optional<OutputFolder> folder;
  if (!a.out_dir.empty()) folder.emplace(a.out_dir);
  if (!a.json_out.empty()) check_output_path(a.json_out);
  OutputTransaction tx;
  std::vector<ShapeTarget> targets = {
      {"foam-ball", 1000}, {"ridged-silicone", 950}, {"silicone-hemisphere", 300}, {"bunny", 1000}};
  if (a.top_only) targets.pop_back();  // the top-cap protocol has no bunny
  json objects = json::array();
  fmt::print("{:<21} {:>6} {:>8} {:>8} | {:>21} | {:>21} | {:>8} {:>7} {:>5}\n", "object", "points",
             "vertices", "faces", "hausdorff mm est/thr", "mean mm est/thr", "coverage", "taps/min",
             "far");
  for (ShapeTarget t : targets) {
    if (!a.objects.empty() &&
        std::find(a.objects.begin(), a.objects.end(), t.name) == a.objects.end())
      continue;
    if (a.taps > 0)
      t.taps = a.taps;
    else if (a.quick)
      t.taps = std::max<std::size_t>(60, t.taps / 5);
    const lab::Scene scene = t.name == "bunny"
                                 ? bunny_scene((std::filesystem::path(demo::find_data_dir(a.data)) /
                                                "bunny" / "bun_zipper.ply")
                                                   .string())
                                 : lab::builtin_scene(t.name);
    const lab::Physics physics = lab::physics_from_string(a.physics);
    if (physics == lab::Physics::kMujoco && !lab::mujoco_represents(scene.object.shape())) {
      fmt::print("{:<21} skipped: MuJoCo cannot represent a {} shape\n", t.name,
                 scene.object.shape().type_name());
      continue;
    }
    objects.push_back(eval_shape_object(t, scene, a));
  }
  const json out = {
      {"objects", objects},
      {"units", "mm; coverage: share of the reachable surface within 5 mm of a tap"},
      {"protocol", a.top_only ? "top caps (region seen from above)" : "whole objects"},
      {"common_region",
       fmt::format("reference within {} mm of the true contact points, overlap only; the "
                   "reconstruction {}",
                   a.region_mm, a.top_only ? "cropped likewise" : "uncropped")},
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
  CLI::App* eval = eval_group(app);
  auto c = std::make_shared<EvalContactsArgs>();
  auto* contacts = eval->add_subcommand(
      "contacts",
      "Thesis fig. 3.4: contact-point error (mm) of true-contact estimation and of plain\n"
      "thresholding on the five lab tapping objects (tip probe, simulated operator).");
  contacts->add_option("--json", c->json_out, "write the numbers as JSON");
  contacts->add_option("--taps", c->taps, "taps per object")->check(CLI::Range(1, 100000));
  contacts->add_option("--seed", c->seed, "random seed of the lab (same seed, same numbers)");
  cli::add_physics_option(*contacts, c->physics,
                          "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent "
                          "are skipped)");
  contacts->add_option("--eps", c->eps, "contact threshold, N")->check(CLI::PositiveNumber);
  contacts->add_option("--window", c->window, "knee-fit window, samples")
      ->check(CLI::Range(4, 100000));
  contacts->callback([c] { run_eval_contacts(*c); });

  auto s = std::make_shared<EvalShapeArgs>();
  auto* shape = eval->add_subcommand(
      "shape",
      "Thesis Table 3.1 on whole objects: the lab operator taps the foam ball (1000 taps), ridged\n"
      "silicone (950), silicone hemisphere (300) and the Stanford bunny scaled to 100 mm in\n"
      "Ecoflex 00-30 (1000) all over what a stylus reaches (base excluded); each is reconstructed\n"
      "from estimated and from thresholded contact points. Hausdorff and mean distance (mm): the\n"
      "reconstruction uncropped, the reference cropped to the tapped part; coverage = share of\n"
      "the reachable surface within 5 mm of a tap; taps per simulated minute.");
  shape->add_option("--json", s->json_out, "write the numbers as JSON");
  shape->add_option("--seed", s->seed, "random seed of the lab");
  cli::add_physics_option(
      *shape, s->physics,
      "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent are "
      "skipped)");
  shape->add_option("--objects", s->objects, "only these objects (default: all four)")
      ->delimiter(',')
      ->check(CLI::IsMember({"foam-ball", "ridged-silicone", "silicone-hemisphere", "bunny"}));
  shape
      ->add_option("--taps", s->taps,
                   "taps per object instead of the thesis' 1000/950/300 (bunny 1000)")
      ->check(CLI::Range(20, 100000));
  shape->add_flag("--quick", s->quick,
                  "a fifth of the taps (at least 60) and a coarser coverage estimate (tests)");
  shape->add_flag("--top-only", s->top_only,
                  "the earlier protocol: taps on the region seen from above, both sides cropped");
  shape->add_option("--data", s->data,
                    "folder with bunny/bun_zipper.ply (default: INHAP_DATA, else data/ near the "
                    "program)");
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
