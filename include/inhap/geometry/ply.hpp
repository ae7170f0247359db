// PLY (Stanford polygon file) reading and writing for TriMesh. Units: positions in mm; every
// extra vertex property keeps its own unit (`stiffness` in N/mm, `confidence` unitless).
//
// Reader: ascii, binary_little_endian and binary_big_endian; vertex x/y/z of any numeric type;
// nx/ny/nz become TriMesh::normals; every other scalar vertex property is kept as a double
// under its own name; faces (`vertex_indices` or `vertex_index`) are fan-triangulated; every
// other element and property is skipped. Bad input throws inhap::ParseError naming the file
// and the header/ascii line or, for binary data, the element and record index.
// Writer: all three formats, positions/normals/properties as double, through AtomicFile.
// Details: docs/formats-mesh.md.
#pragma once

#include <string>
#include <string_view>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyWriteOptions {
  PlyFormat format = PlyFormat::kBinaryLittleEndian;
};

/// Reads a PLY file (whole file read into memory once). Calls validate(path) and computes
/// normals when the file has none. Throws ParseError / IoError.
TriMesh read_ply(const std::string& path);

/// Same as read_ply on bytes already in memory; `source` names them in error messages.
TriMesh parse_ply(std::string_view bytes, const std::string& source);

/// Writes `mesh` atomically (temp file + rename). Throws Error when the mesh is invalid or a
/// property name cannot be stored in a PLY header, IoError when the file cannot be written.
void write_ply(const std::string& path, const TriMesh& mesh, const PlyWriteOptions& options = {});

/// The bytes write_ply would write (for tests and in-memory use).
std::string format_ply(const TriMesh& mesh, const PlyWriteOptions& options = {});

}  // namespace inhap
