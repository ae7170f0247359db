// `inhap shape ...`: shape modeling of soft objects by tapping (thesis ch. 3): contact points
// from a recording, mesh reconstruction, surface comparison. Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>

#include "command.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/contact/tapping.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/point_io.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace {

using namespace inhap;

struct ContactsArgs {
  std::string rec, out, csv, method = "estimate", force = "auto";
  double eps = 0.2;
  std::size_t window = 100, post = 0, min_contact = 5;
  bool no_refine = false, ascii = false;
};

void run_contacts(const ContactsArgs& a) {
  ContactOptions o;
  o.method = a.method == "threshold" ? ContactMethod::kThreshold : ContactMethod::kEstimate;
  o.eps_f = a.eps;
  o.window = a.window;
  o.post = a.post;
  o.min_contact = a.min_contact;
  o.refine = !a.no_refine;
  const ForceSource source = a.force == "raw"        ? ForceSource::kRaw
                             : a.force == "recorded" ? ForceSource::kRecorded
                                                     : ForceSource::kAuto;
  check_output_path(a.out);
  if (!a.csv.empty()) check_output_path(a.csv);
  const Recording rec = read_recording(a.rec);
  const TappingResult res = contacts_from_recording(rec, o, source);
  for (const auto& note : res.notes) fmt::print(stderr, "{}: {}\n", a.rec, note);
  OutputTransaction tx;  // the PLY and the CSV table: both or neither
  write_contact_points(a.out, res.contacts, a.ascii);
  if (!a.csv.empty()) write_contact_table(a.csv, res.contacts);
  tx.commit();
  std::size_t estimated = 0;
  for (const auto& c : res.contacts) estimated += c.estimated;
  const std::string force =
      res.source == ForceSource::kRaw
          ? fmt::format("raw sensor compensated offline (tool mass {:.4f} kg, offset {:.3f} N)",
                        res.compensation.mass_kg, res.compensation.offset.norm())
          : std::string("recorded contact force");
  fmt::print("{} taps ({} by true-contact estimation, {} by thresholding); force: {}\nwrote {}\n",
             res.contacts.size(), estimated, res.contacts.size() - estimated, force, a.out);
}

struct ReconstructArgs {
  std::string points, out, alpha = "auto", mode = "shell", directions = "auto";
  std::size_t taubin = 10, subdivide = 1, jet_k = 18, outlier_k = 8;
  double outlier_sigmas = 6.0, shell_depth = 0, lambda = 0.5, mu = -0.53;
  double max_face_normal_deg = ReconstructOptions{}.max_face_normal_deg;
  bool ascii = false;
};

void run_reconstruct(const ReconstructArgs& a) {
  ReconstructOptions o;
  if (a.alpha != "auto") {
    double v = 0;
    if (!parse_double(a.alpha, v) || !(v > 0))
      throw Error(fmt::format("--alpha: expected auto or a radius in mm > 0, got '{}'", a.alpha));
    o.alpha = v;
  }
  o.mode = a.mode == "solid" ? SurfaceMode::kSolid : SurfaceMode::kShell;
  o.taubin_iterations = a.taubin;
  o.taubin_lambda = a.lambda;
  o.taubin_mu = a.mu;
  o.subdivisions = a.subdivide;
  o.jet_k = a.jet_k;
  o.outlier_k = a.outlier_k;
  o.outlier_sigmas = a.outlier_sigmas;
  o.shell_depth = a.shell_depth;
  o.max_face_normal_deg = a.max_face_normal_deg;
  const PointSet pts = read_points(a.points);
  const bool use_dirs = a.directions == "auto" && !pts.directions.empty();
  ReconstructReport rep;
  const TriMesh mesh = reconstruct_surface(
      pts.points, use_dirs ? std::span<const Vec3>(pts.directions) : std::span<const Vec3>(), o,
      &rep);
  MeshWriteOptions wo;
  wo.ascii = a.ascii;
  write_mesh(a.out, mesh, wo);
  fmt::print(
      "{} points ({} outliers removed), {} mode{}, alpha {:.3f} mm{}\n"
      "mesh: {} vertices, {} faces{}\nwrote {}\n",
      rep.points_in, rep.outliers, a.mode,
      o.mode == SurfaceMode::kShell
          ? fmt::format(" (shell depth {:.3f} mm, normals oriented by {})", rep.shell_depth,
                        use_dirs ? "contact directions" : "the alpha solid")
          : std::string(),
      rep.alpha, o.alpha > 0 ? " (given)" : " (auto)", rep.vertices, rep.faces,
      rep.components_dropped ? fmt::format(" ({} smaller pieces dropped)", rep.components_dropped)
                             : std::string(),
      a.out);
}

struct CompareArgs {
  std::string a, b, json, crop_points, colored, crop_sides = "auto";
  bool icp = false, overlap_only = false, normal_overlap = false;
  double crop_radius = 0, crop_distance = 0, density = 4.0, rim_margin = 0;
};

void run_compare(const CompareArgs& args) {
  const TriMesh a = read_mesh(args.a), b = read_mesh(args.b);
  CompareOptions o;
  o.icp = args.icp;
  o.density = args.density;
  o.crop_distance = args.crop_distance;
  o.exclude_boundary = args.overlap_only;
  o.rim_margin = args.rim_margin;
  o.normal_overlap = args.normal_overlap;
  if (!args.crop_points.empty()) {
    if (!(args.crop_radius > 0)) throw Error("--crop-points needs --crop-radius MM > 0");
    o.region = read_points(args.crop_points).points;
    o.region_radius = args.crop_radius;
  }
  const bool auto_sides = args.crop_sides == "auto";
  o.crop_sides = auto_sides ? auto_crop_sides(a, b) : crop_sides_from_string(args.crop_sides);
  const CroppedSides cropped = cropped_sides(o);
  const bool crop_a = cropped.a, crop_b = cropped.b;
  const CompareResult r = compare_surfaces(a, b, o);
  fmt::print("hausdorff {:.4f} mm, mean {:.4f} mm, rms {:.4f} mm\n", r.hausdorff, r.mean, r.rms);
  fmt::print("  cropped: {} {}, {} {}{}\n", args.a, crop_a ? "yes" : "no (every sample scored)",
             args.b, crop_b ? "yes" : "no (every sample scored)",
             (crop_a || crop_b) && auto_sides && o.crop_sides != CropSides::kBoth
                 ? " (auto: only the closed mesh is cropped)"
                 : "");
  for (const auto& [from, to, side] :
       {std::tuple(&args.a, &args.b, &r.a_to_b), std::tuple(&args.b, &args.a, &r.b_to_a)})
    fmt::print(
        "  {} -> {}: max {:.4f} (at {:.3f} {:.3f} {:.3f}) mean {:.4f} rms {:.4f} mm ({} samples)\n",
        *from, *to, side->max, side->max_at.x(), side->max_at.y(), side->max_at.z(), side->mean,
        side->rms, side->samples);
  if (o.icp) {
    const Eigen::AngleAxisd aa(r.transform.R);
    fmt::print("  icp: rotation {:.4f} deg, translation ({:.4f}, {:.4f}, {:.4f}) mm\n",
               aa.angle() * 180.0 / M_PI, r.transform.t.x(), r.transform.t.y(), r.transform.t.z());
  }
  OutputTransaction tx;  // the coloured mesh and the JSON: both or neither
  if (!args.colored.empty()) {
    TriMesh out = a;
    for (Vec3& p : out.positions) p = r.transform.apply(p);
    out.compute_normals();
    out.set_property("error", r.a_vertex_error);
    write_mesh(args.colored, out);
    fmt::print("wrote {} (vertex property 'error', mm)\n", args.colored);
  }
  if (!args.json.empty()) {
    nlohmann::json j;
    j["a"] = args.a;
    j["b"] = args.b;
    j["units"] = "mm";
    j["hausdorff_mm"] = r.hausdorff;
    j["mean_mm"] = r.mean;
    j["rms_mm"] = r.rms;
    auto side = [](const OneSided& s) {
      return nlohmann::json{{"max_mm", s.max},
                            {"max_at_mm", {s.max_at.x(), s.max_at.y(), s.max_at.z()}},
                            {"mean_mm", s.mean},
                            {"rms_mm", s.rms},
                            {"samples", s.samples}};
    };
    j["a_to_b"] = side(r.a_to_b);
    j["b_to_a"] = side(r.b_to_a);
    j["icp"] = o.icp;
    j["normal_overlap"] = o.normal_overlap;
    j["cropped"] = {{"a", crop_a}, {"b", crop_b}};
    write_file_atomic(args.json, j.dump(2) + "\n");
  }
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
  contacts->add_option("--method", c->method, "estimate (knee fit) | threshold")
      ->capture_default_str()
      ->check(CLI::IsMember({"estimate", "threshold"}));
  contacts->add_option("--eps", c->eps, "contact threshold on ||f||, N")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  contacts->add_option("--window", c->window, "knee-fit window before detection, samples")
      ->capture_default_str()
      ->check(CLI::Range(4, 100000));
  contacts->add_option("--post", c->post, "samples after detection added to the fit window")
      ->capture_default_str();
  contacts
      ->add_option("--min-contact", c->min_contact,
                   "samples ||f|| must stay above eps for a tap (rejects noise spikes)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  contacts->add_flag("--no-refine", c->no_refine,
                     "knee on a sample time only (no continuous refinement between samples)");
  contacts
      ->add_option("--force", c->force,
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
  rec->add_option("--alpha", r->alpha,
                  "auto (from the point spacing: the smallest alpha whose boundary is a closed\n"
                  "manifold of one or more components, docs/shape-modeling.md) or a radius in mm");
  rec->add_option("--mode", r->mode,
                  "shell (points + inner twins: for partial samplings, default) | solid (the\n"
                  "thesis' alpha solid)")
      ->check(CLI::IsMember({"shell", "solid"}));
  rec->add_option("--taubin", r->taubin, "Taubin smoothing iterations (0: none)");
  rec->add_option("--lambda", r->lambda, "Taubin lambda")->check(CLI::Range(0.0, 1.0));
  rec->add_option("--mu", r->mu, "Taubin mu (< -lambda)")->check(CLI::Range(-1.0, 0.0));
  rec->add_option("--subdivide", r->subdivide, "sqrt(3) subdivision steps (0: none)")
      ->check(CLI::Range(0, 6));
  rec->add_option("--jet-k", r->jet_k, "neighbours of the jet fit (0: no smoothing)");
  rec->add_option("--outlier-k", r->outlier_k, "neighbours of the outlier test (0: none)");
  rec->add_option("--outlier-sigmas", r->outlier_sigmas, "robust z-score of an outlier")
      ->check(CLI::PositiveNumber);
  rec->add_option("--shell-depth", r->shell_depth, "shell twin depth, mm (0: point spacing)");
  rec->add_option("--max-face-normal", r->max_face_normal_deg,
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
  cmp->add_flag("--icp", m->icp, "align A onto B by point-to-plane ICP first");
  cmp->add_option("--json", m->json, "write the numbers as JSON");
  cmp->add_option("--crop-points", m->crop_points,
                  "common region: only surface within --crop-radius of these points counts");
  cmp->add_option("--crop-radius", m->crop_radius, "mm")->check(CLI::NonNegativeNumber);
  cmp->add_option("--crop-distance", m->crop_distance,
                  "ignore samples farther than this from the other surface, mm (0: off)")
      ->check(CLI::NonNegativeNumber);
  cmp->add_flag("--overlap-only", m->overlap_only,
                "drop samples whose closest point is on the other surface's open rim (compare a\n"
                "partial reconstruction with a complete reference over their overlap)");
  cmp->add_option("--rim-margin", m->rim_margin,
                  "with --overlap-only: also drop samples whose closest point is within this\n"
                  "distance of the other surface's rim, mm")
      ->check(CLI::NonNegativeNumber);
  cmp->add_flag("--normal-overlap", m->normal_overlap,
                "drop samples whose normal line (both ways) does not meet the other surface (e.g.\n"
                "a reference's side wall below a partial reconstruction's rim)");
  cmp->add_option("--crop-sides", m->crop_sides,
                  "which meshes the crops above apply to: auto | both | a | b. auto: when exactly\n"
                  "one mesh is closed (a complete reference) only it is cropped and the other is\n"
                  "scored whole, so a partial reconstruction's stray parts cannot hide; else both")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "both", "a", "b"}));
  cmp->add_option("--density", m->density, "face samples per mm^2")->check(CLI::PositiveNumber);
  cmp->add_option("--colored", m->colored,
                  "write A (aligned) with vertex property 'error' (mm) for colouring");
  cmp->callback([m] { run_compare(*m); });
}

}  // namespace

INHAP_COMMAND(30, "shape", register_shape);
