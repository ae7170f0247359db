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
#include "inhap/contact/contact_io.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/contacts_lab.hpp"
#include "inhap/eval/lab_objects.hpp"
#include "inhap/eval/shape_lab.hpp"
#include "inhap/eval/shape_study.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/report/strokes.hpp"
#include "inhap/surface/compare.hpp"

namespace {

using namespace inhap;
using namespace inhap::cli;
using namespace inhap::eval;
using json = nlohmann::json;

// --- eval contacts ----------------------------------------------------------------------------

struct EvalContactsArgs {
  ContactObjectOptions o;  // taps, seed, eps, window (flags; physics below)
  std::string json_out;
  std::string physics = "builtin";
};

void run_eval_contacts(const EvalContactsArgs& a) {
  json objects = json::array();
  fmt::print("{:<21} {:>8} {:>5} | {:>25} | {:>25} | {:>5}\n", "object", "k N/mm", "taps",
             "estimate mm (med/p95/max)", "threshold mm (med/p95/max)", "ratio");
  ContactObjectOptions o = a.o;
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
    objects.push_back(contact_object_json(r));
  }
  const json out = contacts_run_json(objects, o.eps, o.window, o.seed);
  if (!a.json_out.empty()) {
    write_file_atomic(a.json_out, out.dump(2) + "\n");
    fmt::print("wrote {}\n", a.json_out);
  }
}

// --- eval shape -------------------------------------------------------------------------------

struct EvalShapeArgs {
  ShapeEvalSettings st;  // seed, protocol, comparison (flags; physics below)
  std::string json_out, out_dir, data;
  std::vector<std::string> objects;
  std::size_t taps = 0;  ///< 0: the thesis' counts
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

ShapeEvalSettings settings_of(const EvalShapeArgs& a) {
  ShapeEvalSettings st = a.st;
  st.physics = lab::physics_from_string(a.physics);
  return st;
}

/// Records, reconstructs and scores one object (eval::run_shape_object); prints its row and
/// returns its JSON.
json eval_shape_object(const ShapeTarget& t, const lab::Scene& scene, const EvalShapeArgs& a) {
  ShapeObjectOptions o = shape_object_options(t.taps, settings_of(a));
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
  return shape_object_json(t.name, r);
}

void run_eval_shape(const EvalShapeArgs& a) {
  // All outputs or none: the folder and the JSON path are checked before the taps (minutes), and
  // every file is renamed into place after the last one is written.
  std::optional<OutputFolder> folder;
  if (!a.out_dir.empty()) folder.emplace(a.out_dir);
  if (!a.json_out.empty()) check_output_path(a.json_out);
  OutputTransaction tx;
  json objects = json::array();
  fmt::print("{:<21} {:>6} {:>8} {:>8} | {:>21} | {:>21} | {:>8} {:>7} {:>5}\n", "object", "points",
             "vertices", "faces", "hausdorff mm est/thr", "mean mm est/thr", "coverage", "taps/min",
             "far");
  for (const ShapeTarget& t : shape_targets(a.st.top_only, a.objects, a.taps, a.st.quick)) {
    const std::string bunny =  // only the bunny needs the data folder
        t.name != "bunny"
            ? std::string()
            : (std::filesystem::path(report::find_data_dir(a.data)) / "bunny" / "bun_zipper.ply")
                  .string();
    const lab::Scene scene = shape_target_scene(t.name, bunny);
    const lab::Physics physics = lab::physics_from_string(a.physics);
    if (physics == lab::Physics::kMujoco && !lab::mujoco_represents(scene.object.shape())) {
      fmt::print("{:<21} skipped: MuJoCo cannot represent a {} shape\n", t.name,
                 scene.object.shape().type_name());
      continue;
    }
    objects.push_back(eval_shape_object(t, scene, a));
  }
  const json out = shape_run_json(objects, settings_of(a));
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
  contacts->add_option("--taps", c->o.taps, "taps per object")->check(CLI::Range(1, 100000));
  contacts->add_option("--seed", c->o.seed, "random seed of the lab (same seed, same numbers)");
  cli::add_physics_option(*contacts, c->physics,
                          "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent "
                          "are skipped)");
  contacts->add_option("--eps", c->o.eps, "contact threshold, N")->check(CLI::PositiveNumber);
  contacts->add_option("--window", c->o.window, "knee-fit window, samples")
      ->check(CLI::Range(4, 100000));
  contacts->callback([c] { run_eval_contacts(*c); });

  auto s = std::make_shared<EvalShapeArgs>();
  auto* shape = eval->add_subcommand(
      "shape",
      "Thesis Table 3.1 on whole objects: the lab operator taps the foam ball (1000 taps), ridged\n"
      "silicone (950), silicone hemisphere (300) and the Stanford bunny scaled to 100 mm in\n"
      "Ecoflex 00-30 (1500) all over what a stylus reaches (base excluded); each is reconstructed\n"
      "from estimated and from thresholded contact points. Hausdorff and mean distance (mm): the\n"
      "reconstruction uncropped, the reference cropped to the tapped part; coverage = share of\n"
      "the reachable surface within 5 mm of a tap; taps per simulated minute.");
  shape->add_option("--json", s->json_out, "write the numbers as JSON");
  shape->add_option("--seed", s->st.seed, "random seed of the lab");
  cli::add_physics_option(
      *shape, s->physics,
      "lab contact physics: builtin | mujoco (objects MuJoCo cannot represent are "
      "skipped)");
  shape->add_option("--objects", s->objects, "only these objects (default: all four)")
      ->delimiter(',')
      ->check(CLI::IsMember({"foam-ball", "ridged-silicone", "silicone-hemisphere", "bunny"}));
  shape
      ->add_option("--taps", s->taps,
                   "taps per object instead of the thesis' 1000/950/300 (bunny 1500)")
      ->check(CLI::Range(20, 100000));
  shape->add_flag("--quick", s->st.quick,
                  "a fifth of the taps (at least 60) and a coarser coverage estimate (tests)");
  shape->add_flag("--top-only", s->st.top_only,
                  "the earlier protocol: taps on the region seen from above, both sides cropped");
  shape->add_option("--data", s->data,
                    "folder with bunny/bun_zipper.ply (default: INHAP_DATA, else data/ near the "
                    "program)");
  shape
      ->add_option("--region", s->st.region_mm,
                   "common region: reference within this distance of the true contact points, mm")
      ->check(CLI::PositiveNumber);
  shape
      ->add_option("--rim-margin", s->st.rim_margin_mm,
                   "common region: drop reference samples whose closest point on the\n"
                   "reconstruction is within this distance of its rim, mm")
      ->check(CLI::NonNegativeNumber);
  shape->add_flag("--no-normal-overlap", s->st.no_normal_overlap,
                  "common region: keep samples whose normal line misses the other surface (the\n"
                  "rim test alone, as before; counts e.g. the slab's untapped end walls)");
  shape->add_flag("--icp", s->st.icp, "ICP-align each reconstruction onto the reference first");
  shape->add_option(
      "--out-dir", s->out_dir,
      "also write points, meshes (vertex property 'error', mm) and references (created if\n"
      "missing; all files of the run or none)");
  shape->callback([s] { run_eval_shape(*s); });
}

}  // namespace

INHAP_COMMAND(80, "eval-shape", register_eval_shape);
