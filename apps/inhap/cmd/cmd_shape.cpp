// `inhap shape ...`: shape modeling of soft objects by tapping (thesis ch. 3): contact points
// from a recording, mesh reconstruction, surface comparison. Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/contact/tapping.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/shape_files.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/point_io.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace {

using namespace inhap;

struct ContactsArgs {
  eval::ContactsRequest req;
  std::string rec, out, csv;
  bool ascii = false;
};

void run_contacts(const ContactsArgs& a) {
  const ContactOptions o = eval::contact_options(a.req);
  const ForceSource source = eval::force_source(a.req);
  check_output_path(a.out);
  if (!a.csv.empty()) check_output_path(a.csv);
  const Recording rec = read_recording(a.rec);
  const TappingResult res = contacts_from_recording(rec, o, source);
  for (const auto& note : res.notes) fmt::print(stderr, "{}: {}\n", a.rec, note);
  OutputTransaction tx;  // the PLY and the CSV table: both or neither
  write_contact_points(a.out, res.contacts, a.ascii);
  if (!a.csv.empty()) write_contact_table(a.csv, res.contacts);
  tx.commit();
  fmt::print("{}\nwrote {}\n", eval::contacts_summary(res), a.out);
}

struct ReconstructArgs {
  eval::ReconstructRequest req;
  std::string points, out, directions = "auto";
  bool ascii = false;
};

void run_reconstruct(const ReconstructArgs& a) {
  const ReconstructOptions o = eval::reconstruct_options(a.req);
  const PointSet pts = read_points(a.points);
  const bool use_dirs = a.directions == "auto" && !pts.directions.empty();
  ReconstructReport rep;
  const TriMesh mesh = reconstruct_surface(
      pts.points, use_dirs ? std::span<const Vec3>(pts.directions) : std::span<const Vec3>(), o,
      &rep);
  MeshWriteOptions wo;
  wo.ascii = a.ascii;
  write_mesh(a.out, mesh, wo);
  fmt::print("{}\nwrote {}\n", eval::reconstruct_summary(rep, o, a.req.mode, use_dirs), a.out);
}

struct CompareArgs {
  eval::CompareRequest req;
  std::string a, b, json, colored;
};

void run_compare(const CompareArgs& args) {
  const TriMesh a = read_mesh(args.a), b = read_mesh(args.b);
  const eval::CompareReport rep = eval::compare_meshes(args.a, a, args.b, b, args.req);
  fmt::print("{}", eval::compare_text(rep));
  OutputTransaction tx;  // the coloured mesh and the JSON: both or neither
  if (!args.colored.empty()) {
    write_mesh(args.colored, eval::error_colored(a, rep.result));
    fmt::print("wrote {} (vertex property 'error', mm)\n", args.colored);
  }
  if (!args.json.empty()) write_file_atomic(args.json, eval::compare_json(rep));
  tx.commit();
}

void add_contacts(CLI::App& shape);
void add_reconstruct(CLI::App& shape);
void add_compare(CLI::App& shape);

void register_shape(CLI::App& app) {
  auto* shape = app.add_subcommand(
      "shape",
      "Shape modeling of soft objects by tapping (thesis ch. 3): contact points, mesh\n"
      "reconstruction, surface comparison. Units: mm, N, s.");
  shape->require_subcommand(1);
  add_contacts(*shape);
  add_reconstruct(*shape);
  add_compare(*shape);
}

void add_contacts(CLI::App& shape_cmd) {
  CLI::App* shape = &shape_cmd;
  auto c = std::make_shared<ContactsArgs>();
  auto* contacts = shape->add_subcommand(
      "contacts",
      "Contact points of a tapping recording (CSV t,px,py,pz,fx,fy,fz[,rfx,rfy,rfz]; t s, p mm,\n"
      "f N): contact when ||f|| > eps N, true contact time by a two-segment fit of ||f(t)|| over\n"
      "the window of N samples before detection, point p(t_c). Writes a point PLY (x,y,z mm;\n"
      "nx,ny,nz = unit force direction at the tap's peak; tap, t_contact s, t_detect s,\n"
      "peak_force N, estimated 0/1). No contact: an empty PLY and a message.");
  contacts->add_option("recording", c->rec, "recording CSV")->required()->check(CLI::ExistingFile);
  contacts->add_option("--out,-o", c->out, "output point PLY")->required();
  contacts->add_option("--method", c->req.method, "estimate (knee fit) | threshold")
      ->capture_default_str()
      ->check(CLI::IsMember({"estimate", "threshold"}));
  contacts->add_option("--eps", c->req.eps, "contact threshold on ||f||, N")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  contacts->add_option("--window", c->req.window, "knee-fit window before detection, samples")
      ->capture_default_str()
      ->check(CLI::Range(4, 100000));
  contacts->add_option("--post", c->req.post, "samples after detection added to the fit window")
      ->capture_default_str();
  contacts
      ->add_option("--min-contact", c->req.min_contact,
                   "samples ||f|| must stay above eps for a tap (rejects noise spikes)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  contacts->add_flag("--no-refine", c->req.no_refine,
                     "knee on a sample time only (no continuous refinement between samples)");
  contacts
      ->add_option("--force", c->req.force,
                   "auto (raw columns compensated offline if present) | recorded | raw")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "recorded", "raw"}));
  contacts->add_option("--csv", c->csv, "also write a per-tap CSV table");
  contacts->add_flag("--ascii", c->ascii, "ASCII PLY");
  contacts->callback([c] { run_contacts(*c); });
}

void add_reconstruct(CLI::App& shape_cmd) {
  CLI::App* shape = &shape_cmd;
  auto r = std::make_shared<ReconstructArgs>();
  auto* rec = shape->add_subcommand(
      "reconstruct",
      "Mesh from contact points (PLY/OBJ vertices, mm): k-NN outlier removal, local quadric\n"
      "(jet) projection, alpha shape, manifold repair, Taubin smoothing, sqrt(3) subdivision.");
  rec->add_option("points", r->points, "point PLY/OBJ (faces ignored)")
      ->required()
      ->check(CLI::ExistingFile);
  rec->add_option("--out,-o", r->out, "output mesh (.ply or .obj)")->required();
  rec->add_option("--alpha", r->req.alpha,
                  "auto (from the point spacing: the smallest alpha whose boundary is a closed\n"
                  "manifold of one or more components, docs/shape-modeling.md) or a radius in mm");
  rec->add_option("--mode", r->req.mode,
                  "shell (points + inner twins: for partial samplings, default) | solid (the\n"
                  "thesis' alpha solid)")
      ->check(CLI::IsMember({"shell", "solid"}));
  rec->add_option("--taubin", r->req.taubin, "Taubin smoothing iterations (0: none)");
  rec->add_option("--lambda", r->req.lambda, "Taubin lambda")->check(CLI::Range(0.0, 1.0));
  rec->add_option("--mu", r->req.mu, "Taubin mu (< -lambda)")->check(CLI::Range(-1.0, 0.0));
  rec->add_option("--subdivide", r->req.subdivide, "sqrt(3) subdivision steps (0: none)")
      ->check(CLI::Range(0, 6));
  rec->add_option("--jet-k", r->req.jet_k, "neighbours of the jet fit (0: no smoothing)");
  rec->add_option("--outlier-k", r->req.outlier_k, "neighbours of the outlier test (0: none)");
  rec->add_option("--outlier-sigmas", r->req.outlier_sigmas, "robust z-score of an outlier")
      ->check(CLI::PositiveNumber);
  rec->add_option("--shell-depth", r->req.shell_depth, "shell twin depth, mm (0: point spacing)");
  rec->add_option("--max-face-normal", r->req.max_face_normal_deg,
                  "shell: drop faces whose normal is more than this from a point's normal, deg\n"
                  "(faces across a thin part sampled on both sides; 0: keep all)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
  rec->add_option("--directions", r->directions,
                  "auto (orient normals by the PLY's nx,ny,nz when present) | none")
      ->check(CLI::IsMember({"auto", "none"}));
  rec->add_flag("--ascii", r->ascii, "ASCII PLY");
  rec->callback([r] { run_reconstruct(*r); });
}

void add_compare(CLI::App& shape_cmd) {
  CLI::App* shape = &shape_cmd;
  auto m = std::make_shared<CompareArgs>();
  auto* cmp = shape->add_subcommand(
      "compare",
      "Distances between two surfaces (PLY/OBJ, mm) as Metro does: dense samples of each\n"
      "surface (vertices + about DENSITY points per mm^2), closest points on the other;\n"
      "symmetric Hausdorff, mean and RMS in mm. Optionally ICP-align A onto B first.");
  cmp->add_option("a", m->a, "first mesh (moved by --icp)")->required()->check(CLI::ExistingFile);
  cmp->add_option("b", m->b, "second mesh (reference)")->required()->check(CLI::ExistingFile);
  cmp->add_flag("--icp", m->req.icp, "align A onto B by point-to-plane ICP first");
  cmp->add_option("--json", m->json, "write the numbers as JSON");
  cmp->add_option("--crop-points", m->req.crop_points,
                  "common region: only surface within --crop-radius of these points counts");
  cmp->add_option("--crop-radius", m->req.crop_radius, "mm")->check(CLI::NonNegativeNumber);
  cmp->add_option("--crop-distance", m->req.crop_distance,
                  "ignore samples farther than this from the other surface, mm (0: off)")
      ->check(CLI::NonNegativeNumber);
  cmp->add_flag("--overlap-only", m->req.overlap_only,
                "drop samples whose closest point is on the other surface's open rim (compare a\n"
                "partial reconstruction with a complete reference over their overlap)");
  cmp->add_option("--rim-margin", m->req.rim_margin,
                  "with --overlap-only: also drop samples whose closest point is within this\n"
                  "distance of the other surface's rim, mm")
      ->check(CLI::NonNegativeNumber);
  cmp->add_flag("--normal-overlap", m->req.normal_overlap,
                "drop samples whose normal line (both ways) does not meet the other surface (e.g.\n"
                "a reference's side wall below a partial reconstruction's rim)");
  cmp->add_option("--crop-sides", m->req.crop_sides,
                  "which meshes the crops above apply to: auto | both | a | b. auto: when exactly\n"
                  "one mesh is closed (a complete reference) only it is cropped and the other is\n"
                  "scored whole, so a partial reconstruction's stray parts cannot hide; else both")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "both", "a", "b"}));
  cmp->add_option("--density", m->req.density, "face samples per mm^2")->check(CLI::PositiveNumber);
  cmp->add_option("--colored", m->colored,
                  "write A (aligned) with vertex property 'error' (mm) for colouring");
  cmp->callback([m] { run_compare(*m); });
}

}  // namespace

INHAP_COMMAND(30, "shape", register_shape);
