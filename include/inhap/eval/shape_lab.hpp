// Shape reconstruction on the virtual lab (thesis 3.3, Table 3.1), shared by `inhap eval
// contacts`, `inhap eval shape` and `inhap demo`: record a tapping operator on a lab object with
// ground truth, match the detected contacts to the true taps, reconstruct the surface from the
// contact points and compare it with the object's exact reference mesh ("the optical scan").
// Units: mm, N, s, N/mm.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "inhap/contact/detector.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/compare.hpp"

namespace inhap::eval {

/// Contacts of one method matched to the lab's truth: error = |p(t_c) - true contact point|.
struct MatchedContacts {
  std::vector<Contact> contacts;  ///< detections that belong to a true tap, in time order
  std::vector<Vec3> truth;        ///< true contact point of each
  std::vector<double> error;      ///< mm
  std::vector<double> stiffness;  ///< N/mm (effective, at 5 N) under each
  std::size_t false_detections = 0;
};

/// Detects the contacts of a lab tapping recording with `options` and keeps the first `limit`
/// that belong to distinct true taps.
MatchedContacts match_contacts(const lab::LabRecording& lab, const ContactOptions& options,
                               std::size_t limit);

/// Records the tapping operator (tip probe) on a scene until at least `taps` true taps exist
/// (about 0.7 taps per second). `progress(fraction)` is called while recording (may be empty).
/// Throws inhap::Error when the operator keeps missing.
lab::LabRecording record_taps(const lab::Scene& scene, std::size_t taps, std::uint64_t seed,
                              const std::function<void(double)>& progress,
                              lab::Physics physics = lab::Physics::builtin);

/// Exact closed, outward triangle mesh of a lab shape (sphere, hemisphere, dome, box, ridged
/// slab). Throws inhap::Error for other shapes.
TriMesh reference_mesh(const lab::Shape& shape);

struct ShapeCompareOptions {
  double region_mm = 5.0;      ///< common region: reference within this of the true contacts
  double rim_margin_mm = 1.0;  ///< drop samples whose closest point is this near the rim
  bool normal_overlap = true;  ///< drop samples whose normal line misses the other surface
  bool icp = false;            ///< ICP-align the reconstruction first
};

/// One reconstruction (from estimated or thresholded contact points) and its comparison.
struct ShapeVariant {
  MatchedContacts matched;
  TriMesh mesh;  ///< the reconstruction, aligned (moved by cmp.transform)
  std::size_t points = 0, vertices = 0, faces = 0;
  CompareResult cmp;  ///< cmp.a_vertex_error: per vertex of `mesh`, mm
};

/// Matches the first `taps` contacts of `method`, reconstructs the surface (surface module)
/// and compares it with `reference` over the common region.
ShapeVariant reconstruct_and_compare(const lab::LabRecording& rec, ContactMethod method,
                                     std::size_t taps, const TriMesh& reference,
                                     const ShapeCompareOptions& options = {});

}  // namespace inhap::eval
