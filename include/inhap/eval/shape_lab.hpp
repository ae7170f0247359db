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
#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/surface/compare.hpp"
#include "inhap/surface/reconstruct.hpp"

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

/// Contact episodes of a lab recording that start on the far side: the previous episode ended
/// with the probe on the far side of where it entered (the closest surface's normal there
/// opposite, dot < -0.5, to the previous entry normal), and this one starts with an entry normal
/// opposite to the previous one while the probe never got `approach_mm` or more from the
/// surface in between — the tip passed through a thin part and touched its far side within the
/// same tap. (Tapping the back of an ear right after its front, going round its rim, is not.) A
/// force reversal is an episode in which the (noise-free) force's component along its first-tick
/// direction falls below -reversal_n newtons.
struct EntrySideCounts {
  std::size_t episodes = 0;
  std::size_t far_side_first_contacts = 0;
  std::size_t force_reversals = 0;
};
EntrySideCounts count_far_side_contacts(const lab::LabRecording& rec, const lab::SoftObject& object,
                                        double probe_radius_mm = 0.0, double approach_mm = 5.0,
                                        double reversal_n = 0.5);

/// Records the tapping operator (tip probe) on a scene until at least `taps` true taps exist
/// (whole-object mode (`tap.whole_object`, the default) about 1.1 taps per second, region mode
/// about 0.7).
/// `progress` is called while recording (may be empty). Throws inhap::Error when the
/// operator keeps missing.
lab::LabRecording record_taps(const lab::Scene& scene, std::size_t taps, std::uint64_t seed,
                              const Progress& progress,
                              lab::Physics physics = lab::Physics::kBuiltin,
                              const lab::TapOptions& tap = {});

/// True taps (contact episodes) per simulated minute of a recording.
double taps_per_minute(const lab::LabRecording& rec);

/// Share of the object's reachable surface (lab/reach.hpp, approach along the normal; tip
/// probe) within `radius_mm` of one of `taps` (true contact points): `samples` area-uniform
/// surface samples, seeded.
double tap_coverage(const lab::SoftObject& object, const std::vector<Vec3>& taps,
                    double radius_mm = 5.0, std::size_t samples = 20000,
                    const lab::ReachOptions& reach = {});

/// The lab's bunny: the Stanford bunny (`ply_path`, metres, y up) scaled so that its largest
/// extent is `size_mm`, centred on the z axis and standing on z = 0, in Ecoflex 00-30 (the
/// `planar` scene's material). Throws inhap::Error when the file cannot be read.
lab::Scene bunny_scene(const std::string& ply_path, double size_mm = 100.0);

/// Exact closed, outward triangle mesh of a lab shape (sphere, hemisphere, dome, box, ridged
/// slab); for a mesh shape the mesh itself (as placed; it need not be closed: the Stanford
/// bunny has holes in its base). Throws inhap::Error for other shapes.
TriMesh reference_mesh(const lab::Shape& shape);

struct ShapeCompareOptions {
  double region_mm = 5.0;      ///< common region: reference within this of the true contacts
  double rim_margin_mm = 1.0;  ///< drop samples whose closest point is this near the rim
  bool normal_overlap = true;  ///< drop samples whose normal line misses the other surface
  bool icp = false;            ///< ICP-align the reconstruction first
  /// The reference is complete: crop only its side to the common region and score every part
  /// of the reconstruction (CropSides::kB); false crops both sides (the top-cap protocol).
  bool uncropped_reconstruction = true;
  /// When set: the reference's reachable part (reachable_part()), used for the reference ->
  /// reconstruction side instead of `reference` (the thesis crops to the reachable, tapped part:
  /// the base band and the underside near the table are never tapped).
  const TriMesh* reachable_reference = nullptr;
  ReconstructOptions reconstruct;  ///< the surface pipeline's options (defaults: the study's)
};

/// The faces of `reference` whose centroid is reachable (lab/reach.hpp, tip probe, approach
/// along the face normal).
TriMesh reachable_part(const TriMesh& reference, const lab::SoftObject& object,
                       const lab::ReachOptions& reach = {});

/// One reconstruction (from estimated or thresholded contact points) and its comparison.
struct ShapeVariant {
  MatchedContacts matched;
  TriMesh mesh;  ///< the reconstruction, aligned (moved by cmp.transform)
  std::size_t points = 0, vertices = 0, faces = 0;
  CompareResult cmp;         ///< cmp.a_vertex_error: per vertex of `mesh`, mm
  std::vector<Vec3> region;  ///< true contact points of the taps the model was built from
};

/// Matches the first `taps` contacts of `method`, reconstructs the surface (surface module)
/// and compares it with `reference` over the common region.
ShapeVariant reconstruct_and_compare(const lab::LabRecording& rec, ContactMethod method,
                                     std::size_t taps, const TriMesh& reference,
                                     const ShapeCompareOptions& options = {});

}  // namespace inhap::eval
