// What `inhap mesh info|convert|heightmap` compute between reading and writing a mesh: the mesh's
// report (counts, bounding box, properties, topology) as text and JSON, the linear map of a
// property onto stiffness, and scaling / centring. Units: mm, N/mm.
#pragma once

#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// The report of `mesh info` on `mesh` read from `file`: the text it prints.
std::string mesh_info_text(const std::string& file, const TriMesh& mesh);
/// The same as JSON text (keys: file, vertices, faces, edges, bbox_mm, properties, manifold,
/// watertight, oriented, boundary_loops, boundary_edges, components).
std::string mesh_info_json(const std::string& file, const TriMesh& mesh);

/// `values` mapped linearly from their [min, max] onto [lo, hi]; all `hi` when they are all
/// equal (or empty input: empty output).
std::vector<double> map_linear(const std::vector<double>& values, double lo, double hi);

/// Scales the mesh uniformly so its largest bounding-box side is `scale_to` mm (0: no scaling)
/// and, when `center`, moves the box centre to the origin. Error naming `what` for a mesh of zero
/// size that should be scaled.
void scale_and_center(TriMesh& mesh, double scale_to, bool center, const std::string& what);

}  // namespace inhap
