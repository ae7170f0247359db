// Mesh file I/O dispatching on the extension.
#include "inhap/geometry/mesh_io.hpp"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/geometry/obj.hpp"
#include "inhap/geometry/ply.hpp"

namespace inhap {

namespace {

enum class MeshFormat { kPly, kObj };

MeshFormat format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".obj") return MeshFormat::kObj;
  throw Error(fmt::format("{}: expected a mesh file ending in .ply or .obj, got {}", path,
                          ext.empty() ? std::string("no extension") : quote_token(ext)));
}

}  // namespace

TriMesh read_mesh(const std::string& path) {
  return format_of(path) == MeshFormat::kPly ? read_ply(path) : read_obj(path);
}

std::vector<std::string> write_mesh(const std::string& path, const TriMesh& mesh,
                                    const MeshWriteOptions& options) {
  if (format_of(path) == MeshFormat::kObj) return write_obj(path, mesh);
  PlyWriteOptions ply;
  ply.format = options.ascii ? PlyFormat::kAscii : PlyFormat::kBinaryLittleEndian;
  write_ply(path, mesh, ply);
  return {};
}

}  // namespace inhap
