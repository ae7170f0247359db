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
#include <string>
#include <vector>

#include "command.hpp"
#include "inhap/contact/contact_io.hpp"
#include "inhap/contact/tapping.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace {

using namespace inhap;
using json = nlohmann::json;

// --- recordings with ground truth ------------------------------------------------------------

/// Contacts of one method matched to the lab's truth: error = |p(t_c) - true contact point|.
struct Matched {
  std::vector<Contact> contacts;  ///< detections that belong to a true tap, in time order
  std::vector<Vec3> truth;        ///< true contact point of each
  std::vector<double> error;      ///< mm
  std::vector<double> stiffness;  ///< N/mm (effective, at 5 N) under each
  std::size_t false_detections = 0;
};

Matched match(const lab::LabRecording& lab, const ContactOptions& o, std::size_t limit) {
  Matched m;
  const TappingResult res = contacts_from_recording(lab.rec, o, ForceSource::Auto);
  long last_tap = -1;
  for (const Contact& c : res.contacts) {
    const long tap = lab.truth.tap[c.detect_index];
    if (tap < 0 || tap == last_tap) {  // noise, or a second detection within one true contact
      ++m.false_detections;
      continue;
    }
    last_tap = tap;
    if (m.contacts.size() == limit) break;
    m.contacts.push_back(c);
    m.truth.push_back(lab.truth.c[c.detect_index]);
    m.error.push_back((c.point - lab.truth.c[c.detect_index]).norm());
    m.stiffness.push_back(lab.truth.k[c.detect_index]);
  }
  return m;
}

/// Records the tapping operator on a scene until at least `taps` true taps exist.
lab::LabRecording record_taps(const lab::Scene& scene, std::size_t taps, std::uint64_t seed,
                              const std::string& what) {
  lab::RecordSpec spec;
  spec.operator_name = "tap";
  spec.probe = lab::ProbeSpec::tip();
  spec.seed = seed;
  spec.seconds = 10.0 + 1.7 * static_cast<double>(taps);  // about 0.7 taps per second
  for (int attempt = 0; attempt < 4; ++attempt) {
    lab::LabRecording rec =
        lab::record_scene(scene, spec, [&](double f) { cli::progress(what, f, 0); });
    long n = 0;
    for (long t : rec.truth.tap) n = std::max(n, t + 1);
    if (static_cast<std::size_t>(n) >= taps) return rec;
    spec.seconds *= 1.6;
  }
  throw Error(
      fmt::format("eval: the tapping operator gave fewer than {} taps on {}", taps, scene.name));
}

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
};

void run_eval_contacts(const EvalContactsArgs& a) {
  json objects = json::array();
  fmt::print("{:<21} {:>8} {:>5} | {:>25} | {:>25} | {:>5}\n", "object", "k N/mm", "taps",
             "estimate mm (med/p95/max)", "threshold mm (med/p95/max)", "ratio");
  for (const std::string& name : lab::tapping_scene_names()) {
    const lab::Scene scene = lab::builtin_scene(name);
    const lab::LabRecording rec = record_taps(scene, a.taps, a.seed, "eval contacts " + name);
    ContactOptions est, thr;
    est.eps_f = thr.eps_f = a.eps;
    est.window = thr.window = a.window;
    thr.method = ContactMethod::Threshold;
    const Matched me = match(rec, est, a.taps), mt = match(rec, thr, a.taps);
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

// --- reference surfaces of the lab shapes ("the optical scan") -------------------------------

/// Closed mesh of a spherical cap on the plane z = base.z: sphere part + base disc.
TriMesh dome_mesh(const Vec3& base, double a, double h) {
  const double rs = (a * a + h * h) / (2 * h);
  const Vec3 c = base + Vec3(0, 0, h - rs);
  const double theta_max = std::atan2(a, rs - h);  // polar angle of the rim
  const int rings = 120, sectors = 360;
  TriMesh m;
  m.positions.push_back(c + Vec3(0, 0, rs));
  for (int i = 1; i <= rings; ++i) {
    const double th = theta_max * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double ph = 2 * std::numbers::pi * j / sectors;
      m.positions.push_back(
          c + rs * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  auto v = [&](int i, int j) { return 1 + (i - 1) * sectors + (j % sectors); };
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({0, v(1, j), v(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  const int centre = static_cast<int>(m.positions.size());
  m.positions.push_back(base);
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({centre, v(rings, j + 1), v(rings, j)});
  return m;
}

/// A sphere: the cap of height 2r over a vanishing base circle.
TriMesh sphere_mesh(const Vec3& c, double r) {
  return dome_mesh(c - Vec3(0, 0, r), 1e-6 * r, 2 * r);
}

/// Prism over y in [-hy, hy] whose (x, z) section is bounded below by z = zb and above by the
/// x-monotone chain `top` (x increasing, z > zb); the caps are triangulated in vertical strips.
TriMesh prism_mesh(const std::vector<Vec2>& top, double zb, const Vec3& origin, double hy) {
  TriMesh m;
  const int n = static_cast<int>(top.size());
  // Per side: top chain (0..n-1), then the bottom points below it (n..2n-1).
  for (double y : {-hy, hy}) {
    for (const Vec2& p : top) m.positions.push_back(origin + Vec3(p.x(), y, p.y()));
    for (const Vec2& p : top) m.positions.push_back(origin + Vec3(p.x(), y, zb));
  }
  auto v = [&](int side, int bottom, int i) { return side * 2 * n + bottom * n + i; };
  auto quad = [&](int a, int b, int c, int d) {  // a-b-c-d clockwise seen from outside
    m.triangles.push_back({a, c, b});
    m.triangles.push_back({a, d, c});
  };
  for (int i = 0; i + 1 < n; ++i) {
    quad(v(0, 0, i), v(1, 0, i), v(1, 0, i + 1), v(0, 0, i + 1));  // top
    quad(v(0, 1, i), v(0, 1, i + 1), v(1, 1, i + 1), v(1, 1, i));  // bottom
    quad(v(0, 1, i), v(0, 0, i), v(0, 0, i + 1), v(0, 1, i + 1));  // cap y = -hy
    quad(v(1, 1, i), v(1, 1, i + 1), v(1, 0, i + 1), v(1, 0, i));  // cap y = +hy
  }
  quad(v(0, 1, 0), v(1, 1, 0), v(1, 0, 0), v(0, 0, 0));                  // wall x = x_first
  quad(v(0, 1, n - 1), v(0, 0, n - 1), v(1, 0, n - 1), v(1, 1, n - 1));  // wall x = x_last
  return m;
}

TriMesh reference_mesh(const lab::Shape& shape) {
  TriMesh m;
  if (const auto* s = std::get_if<lab::SphereShape>(&shape.variant())) {
    m = sphere_mesh(s->center, s->radius);
  } else if (const auto* h = std::get_if<lab::HemisphereShape>(&shape.variant())) {
    m = dome_mesh(h->base_center, h->radius, h->radius);
  } else if (const auto* d = std::get_if<lab::DomeShape>(&shape.variant())) {
    m = dome_mesh(d->base_center, d->base_radius, d->height);
  } else if (const auto* b = std::get_if<lab::BoxShape>(&shape.variant())) {
    const Vec3 hs = b->half_size;
    m = prism_mesh({{-hs.x(), hs.z()}, {hs.x(), hs.z()}}, -hs.z(), b->center, hs.y());
  } else if (const auto* r = std::get_if<lab::RidgedSlabShape>(&shape.variant())) {
    // The lab's profile: flat top of the slab with triangular ridges (x increasing).
    const double hw = 0.5 * r->size_x, pitch = r->size_x / r->ridges;
    std::vector<Vec2> top{{-hw, r->thickness}};
    for (int i = 0; i < r->ridges; ++i) {
      const double xc = -hw + (i + 0.5) * pitch;
      for (const Vec2& p :
           {Vec2(xc - 0.5 * r->ridge_width, r->thickness), Vec2(xc, r->thickness + r->ridge_height),
            Vec2(xc + 0.5 * r->ridge_width, r->thickness)})
        if ((top.back() - p).norm() > 1e-9) top.push_back(p);
    }
    if ((top.back() - Vec2(hw, r->thickness)).norm() > 1e-9) top.emplace_back(hw, r->thickness);
    m = prism_mesh(top, 0.0, r->base_center, 0.5 * r->size_y);
  } else {
    throw Error(fmt::format("eval shape: no reference mesh for a {} shape", shape.type_name()));
  }
  m.compute_normals();
  // The distances are only as good as this mesh: it must be closed and outward.
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  double volume = 0;
  for (const Tri& t : m.triangles)
    volume += m.positions[t[0]].dot(m.positions[t[1]].cross(m.positions[t[2]])) / 6.0;
  if (!topo.watertight() || !topo.oriented() || !(volume > 0))
    throw Error(
        fmt::format("eval shape: internal error: the reference mesh of the {} shape is "
                    "not closed and outward",
                    shape.type_name()));
  return m;
}

// --- eval shape -------------------------------------------------------------------------------

struct EvalShapeArgs {
  std::string json_out, out_dir;
  std::vector<std::string> objects;
  std::size_t taps = 0;  ///< 0: the thesis' counts
  std::uint64_t seed = 1;
  double region_mm = 5.0, rim_margin_mm = 1.0;
  bool icp = false;
};

struct Variant {
  std::size_t points = 0, vertices = 0, faces = 0;
  CompareResult cmp;
};

Variant run_variant(const lab::LabRecording& rec, ContactMethod method, std::size_t taps,
                    const TriMesh& reference, const EvalShapeArgs& a, const std::string& tag) {
  ContactOptions o;
  o.method = method;
  const Matched m = match(rec, o, taps);
  std::vector<Vec3> pts, dirs;
  for (const Contact& c : m.contacts) pts.push_back(c.point), dirs.push_back(c.direction);
  ReconstructReport rep;
  const TriMesh mesh = reconstruct_surface(pts, dirs, {}, &rep);
  // Common region: the reference near the true contact points of the taps the model was built
  // from (an outlier tap, e.g. a tip that slipped down a wall, is not part of the model).
  std::vector<Vec3> region;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (rep.used[i]) region.push_back(m.truth[i]);
  CompareOptions co;
  co.icp = a.icp;
  co.region = region;
  co.region_radius = a.region_mm;
  co.exclude_boundary = true;
  co.rim_margin = a.rim_margin_mm;
  Variant v;
  v.points = pts.size();
  v.vertices = mesh.num_vertices();
  v.faces = mesh.num_triangles();
  v.cmp = compare_surfaces(mesh, reference, co);
  if (!a.out_dir.empty()) {
    std::filesystem::create_directories(a.out_dir);
    write_contact_points(a.out_dir + "/" + tag + ".points.ply", m.contacts);
    TriMesh colored = mesh;
    for (Vec3& p : colored.positions) p = v.cmp.transform.apply(p);
    colored.set_property("error", v.cmp.a_vertex_error);
    write_mesh(a.out_dir + "/" + tag + ".mesh.ply", colored);
  }
  return v;
}

void run_eval_shape(const EvalShapeArgs& a) {
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
    const lab::LabRecording rec =
        record_taps(scene, t.taps, a.seed, std::string("eval shape ") + t.name);
    const TriMesh reference = reference_mesh(scene.object.shape());
    const Variant e = run_variant(rec, ContactMethod::Estimate, t.taps, reference, a,
                                  std::string(t.name) + ".estimate");
    const Variant s = run_variant(rec, ContactMethod::Threshold, t.taps, reference, a,
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
      {"seed", a.seed}};
  if (!a.json_out.empty()) {
    write_file_atomic(a.json_out, out.dump(2) + "\n");
    fmt::print("wrote {}\n", a.json_out);
  }
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
  shape->add_flag("--icp", s->icp, "ICP-align each reconstruction onto the reference first");
  shape->add_option("--out-dir", s->out_dir,
                    "also write points, meshes (vertex property 'error', mm) and references");
  shape->callback([s] { run_eval_shape(*s); });
}

}  // namespace

INHAP_COMMAND(80, "eval-shape", register_eval_shape);
