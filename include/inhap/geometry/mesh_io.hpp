// Mesh file I/O dispatching on the file extension (.ply or .obj, case-insensitive).
// Units: positions in mm; vertex properties keep their own units (`stiffness` in N/mm).
#pragma once

#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

struct MeshWriteOptions {
  bool ascii = false;  ///< PLY only: ascii instead of binary little-endian
};

/// Reads a .ply or .obj mesh (validated, with normals). Throws Error for another extension,
/// ParseError for bad content, IoError when the file cannot be read.
TriMesh read_mesh(const std::string& path);

/// Writes a .ply or .obj mesh atomically. Returns the names of vertex properties the format
/// could not store (always empty for PLY; every property for OBJ).
std::vector<std::string> write_mesh(const std::string& path, const TriMesh& mesh,
                                    const MeshWriteOptions& options = {});

}  // namespace inhap
