// Wavefront OBJ reading and writing for TriMesh (geometry only). Units: positions in mm.
//
// Reader: `v x y z` (extra values such as w or r g b ignored), `f` with v, v/vt, v//vn and
// v/vt/vn forms and negative (relative) indices; polygons are fan-triangulated; vn, vt, vp, l,
// p, o, g, s, usemtl, mtllib, comments and unknown statements are ignored. Normals are always
// recomputed. Writer: `v` and 1-based `f` lines only. OBJ cannot store per-vertex scalar
// properties: write_obj returns the names it dropped so callers can warn.
// Details: docs/formats-mesh.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// Reads an OBJ file; calls validate(path) and compute_normals(). Throws ParseError / IoError.
TriMesh read_obj(const std::string& path);

/// Same as read_obj on text already in memory; `source` names it in error messages.
TriMesh parse_obj(std::string_view text, const std::string& source);

/// Writes positions and triangles atomically; returns the property names that were dropped.
std::vector<std::string> write_obj(const std::string& path, const TriMesh& mesh);

/// The text write_obj would write.
std::string format_obj(const TriMesh& mesh);

}  // namespace inhap
