// inhap studio: light meshes for the page to draw (a browser without a GPU draws 86,400
// triangles at a few frames per second). What the servo loop renders is never simplified; only
// what is sent to the page. Units: mm.
#pragma once

#include <string>

#include "inhap/geometry/trimesh.hpp"
#include "inhap/lab/shape.hpp"

namespace inhap::studio {

/// The mesh as seen from above (+z), resampled on an n x n grid over its xy bounds by vertical
/// rays (first hit from above); the vertex property `property` (if present) interpolated at the
/// hits. Returns the mesh itself when it has at most max_faces triangles.
TriMesh top_view_mesh(const TriMesh& mesh, const std::string& property, int n = 80,
                      std::size_t max_faces = 12000);

/// The top of a lab shape seen from above: Shape::drop (a sharp probe lowered from above) on an
/// n x n grid over its xy bounds.
TriMesh top_view_mesh(const lab::Shape& shape, int n = 64);

}  // namespace inhap::studio
