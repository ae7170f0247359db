// Shape modeling by tapping on files: the reports of `inhap shape ...`. Units: mm, N, s.
#include "inhap/eval/shape_files.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <tuple>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/surface/point_io.hpp"

namespace inhap::eval {

std::string contacts_summary(const TappingResult& res) {
  std::size_t estimated = 0;
  for (const auto& c : res.contacts) estimated += c.estimated;
  const std::string force =
      res.source == ForceSource::kRaw
          ? fmt::format("raw sensor compensated offline (tool mass {:.4f} kg, offset {:.3f} N)",
                        res.compensation.mass_kg, res.compensation.offset.norm())
          : std::string("recorded contact force");
  return fmt::format("{} taps ({} by true-contact estimation, {} by thresholding); force: {}",
                     res.contacts.size(), estimated, res.contacts.size() - estimated, force);
}

std::string reconstruct_summary(const ReconstructReport& rep, const ReconstructOptions& o,
                                const std::string& mode, bool use_dirs) {
  return fmt::format(
      "{} points ({} outliers removed), {} mode{}, alpha {:.3f} mm{}\n"
      "mesh: {} vertices, {} faces{}",
      rep.points_in, rep.outliers, mode,
      o.mode == SurfaceMode::kShell
          ? fmt::format(" (shell depth {:.3f} mm, normals oriented by {})", rep.shell_depth,
                        use_dirs ? "contact directions" : "the alpha solid")
          : std::string(),
      rep.alpha, o.alpha > 0 ? " (given)" : " (auto)", rep.vertices, rep.faces,
      rep.components_dropped ? fmt::format(" ({} smaller pieces dropped)", rep.components_dropped)
                             : std::string());
}

std::string compare_text(const CompareReport& r) {
  const CompareResult& res = r.result;
  const CompareOptions& o = r.options;
  const bool crop_a = r.cropped.a, crop_b = r.cropped.b, auto_sides = r.auto_sides;
  std::string s;
  s += fmt::format("hausdorff {:.4f} mm, mean {:.4f} mm, rms {:.4f} mm\n", res.hausdorff, res.mean,
                   res.rms);
  s += fmt::format("  cropped: {} {}, {} {}{}\n", r.a, crop_a ? "yes" : "no (every sample scored)",
                   r.b, crop_b ? "yes" : "no (every sample scored)",
                   (crop_a || crop_b) && auto_sides && o.crop_sides != CropSides::kBoth
                       ? " (auto: only the closed mesh is cropped)"
                       : "");
  for (const auto& [from, to, side] :
       {std::tuple(&r.a, &r.b, &res.a_to_b), std::tuple(&r.b, &r.a, &res.b_to_a)})
    s += fmt::format(
        "  {} -> {}: max {:.4f} (at {:.3f} {:.3f} {:.3f}) mean {:.4f} rms {:.4f} mm ({} samples)\n",
        *from, *to, side->max, side->max_at.x(), side->max_at.y(), side->max_at.z(), side->mean,
        side->rms, side->samples);
  if (o.icp) {
    const Eigen::AngleAxisd aa(res.transform.R);
    s += fmt::format("  icp: rotation {:.4f} deg, translation ({:.4f}, {:.4f}, {:.4f}) mm\n",
                     aa.angle() * 180.0 / M_PI, res.transform.t.x(), res.transform.t.y(),
                     res.transform.t.z());
  }
  return s;
}

std::string compare_json(const CompareReport& r) {
  const CompareResult& res = r.result;
  nlohmann::json j;
  j["a"] = r.a;
  j["b"] = r.b;
  j["units"] = "mm";
  j["hausdorff_mm"] = res.hausdorff;
  j["mean_mm"] = res.mean;
  j["rms_mm"] = res.rms;
  auto side = [](const OneSided& s) {
    return nlohmann::json{{"max_mm", s.max},
                          {"max_at_mm", {s.max_at.x(), s.max_at.y(), s.max_at.z()}},
                          {"mean_mm", s.mean},
                          {"rms_mm", s.rms},
                          {"samples", s.samples}};
  };
  j["a_to_b"] = side(res.a_to_b);
  j["b_to_a"] = side(res.b_to_a);
  j["icp"] = r.options.icp;
  j["normal_overlap"] = r.options.normal_overlap;
  j["cropped"] = {{"a", r.cropped.a}, {"b", r.cropped.b}};
  return j.dump(2) + "\n";
}

CompareReport compare_meshes(const std::string& a_path, const TriMesh& a, const std::string& b_path,
                             const TriMesh& b, const CompareRequest& r) {
  CompareOptions o;
  o.icp = r.icp;
  o.density = r.density;
  o.crop_distance = r.crop_distance;
  o.exclude_boundary = r.overlap_only;
  o.rim_margin = r.rim_margin;
  o.normal_overlap = r.normal_overlap;
  if (!r.crop_points.empty()) {
    if (!(r.crop_radius > 0)) throw Error("--crop-points needs --crop-radius MM > 0");
    o.region = read_points(r.crop_points).points;
    o.region_radius = r.crop_radius;
  }
  const bool auto_sides = r.crop_sides == "auto";
  o.crop_sides = auto_sides ? auto_crop_sides(a, b) : crop_sides_from_string(r.crop_sides);
  return {a_path, b_path, o, cropped_sides(o), auto_sides, compare_surfaces(a, b, o)};
}

TriMesh error_colored(const TriMesh& a, const CompareResult& r) {
  TriMesh out = a;
  for (Vec3& p : out.positions) p = r.transform.apply(p);
  out.compute_normals();
  out.set_property("error", r.a_vertex_error);
  return out;
}

ReconstructOptions reconstruct_options(const ReconstructRequest& a) {
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
  return o;
}

ContactOptions contact_options(const ContactsRequest& a) {
  ContactOptions o;
  o.method = a.method == "threshold" ? ContactMethod::kThreshold : ContactMethod::kEstimate;
  o.eps_f = a.eps;
  o.window = a.window;
  o.post = a.post;
  o.min_contact = a.min_contact;
  o.refine = !a.no_refine;
  return o;
}

ForceSource force_source(const ContactsRequest& a) {
  return a.force == "raw"        ? ForceSource::kRaw
         : a.force == "recorded" ? ForceSource::kRecorded
                                 : ForceSource::kAuto;
}

}  // namespace inhap::eval
