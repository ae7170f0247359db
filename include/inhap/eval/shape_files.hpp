// Shape modeling by tapping (thesis ch. 3) on files: the reports `inhap shape contacts |
// reconstruct | compare` print and write. Units: mm, N, s.
#pragma once

#include <string>

#include "inhap/contact/tapping.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::eval {

/// The flags of `shape contacts` that set the detection (the command's defaults).
struct ContactsRequest {
  std::string method = "estimate";                      ///< estimate | threshold
  std::string force = "auto";                           ///< auto | recorded | raw
  double eps = 0.2;                                     ///< N
  std::size_t window = 100, post = 0, min_contact = 5;  ///< samples
  bool no_refine = false;
};
ContactOptions contact_options(const ContactsRequest& r);
ForceSource force_source(const ContactsRequest& r);

/// "N taps (n by true-contact estimation, m by thresholding); force: ..." for `shape contacts`.
std::string contacts_summary(const TappingResult& r);

/// Points, outliers, mode, alpha (given or auto), mesh size and dropped pieces of a
/// reconstruction; `mode` as given on the command line, `by_directions` whether the shell's
/// normals were oriented by the contact directions.
std::string reconstruct_summary(const ReconstructReport& rep, const ReconstructOptions& o,
                                const std::string& mode, bool by_directions);

/// `shape compare`: the mesh files `a`, `b` and what was compared.
struct CompareReport {
  std::string a, b;
  CompareOptions options;
  CroppedSides cropped;
  bool auto_sides = false;  ///< the cropped sides were chosen automatically
  CompareResult result;
};
/// The flags of `shape compare` that set the comparison.
struct CompareRequest {
  std::string crop_points;          ///< point file: only surface within crop_radius counts
  std::string crop_sides = "auto";  ///< auto | both | a | b
  bool icp = false, overlap_only = false, normal_overlap = false;
  double crop_radius = 0, crop_distance = 0, density = 4.0, rim_margin = 0;  ///< mm, 1/mm^2
};
/// Compares mesh `a` (file `a_path`) with `b` (`b_path`) as asked. Error when crop points come
/// without a radius > 0.
CompareReport compare_meshes(const std::string& a_path, const TriMesh& a, const std::string& b_path,
                             const TriMesh& b, const CompareRequest& r);
/// Mesh `a` moved by the comparison's transform, with normals and the vertex property 'error'
/// (mm).
TriMesh error_colored(const TriMesh& a, const CompareResult& r);

/// The flags of `shape reconstruct` that set the reconstruction (the command's defaults).
struct ReconstructRequest {
  std::string alpha = "auto", mode = "shell";
  std::size_t taubin = 10, subdivide = 1, jet_k = 18, outlier_k = 8;
  double outlier_sigmas = 6.0, shell_depth = 0, lambda = 0.5, mu = -0.53;
  double max_face_normal_deg = ReconstructOptions{}.max_face_normal_deg;
};
/// ReconstructOptions of the request. Error for an --alpha that is neither auto nor a radius > 0.
ReconstructOptions reconstruct_options(const ReconstructRequest& r);

/// Distances both ways (max with where, mean, rms, samples), what was cropped, the ICP transform.
std::string compare_text(const CompareReport& r);
/// The same as JSON text (keys in docs/shape.md).
std::string compare_json(const CompareReport& r);

}  // namespace inhap::eval
