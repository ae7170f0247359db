// Point sets from PLY/OBJ; see point_io.hpp.
#include "inhap/surface/point_io.hpp"

#include <cctype>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"

namespace inhap {

namespace {

/// True when the PLY header declares vertex properties nx, ny and nz (the reader fills
/// default normals otherwise, which must not be taken for measurements).
bool ply_header_has_normals(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  std::string header;
  char buf[4096];
  std::size_t n = 0;
  while (header.find("end_header") == std::string::npos && header.size() < (1u << 20) &&
         (n = std::fread(buf, 1, sizeof buf, f)) > 0)
    header.append(buf, n);
  std::fclose(f);
  header = header.substr(0, header.find("end_header"));
  int found = 0;
  for (const char* name : {" nx\n", " ny\n", " nz\n"})
    found += header.find(name) != std::string::npos ||
             header.find(std::string(name).replace(3, 1, "\r\n")) != std::string::npos;
  return found == 3;
}

bool ends_with_ply(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".ply";
}

}  // namespace

void write_points(const std::string& path, const PointSet& s, bool ascii) {
  if (!s.directions.empty() && s.directions.size() != s.points.size())
    throw Error(fmt::format("{}: expected a direction per point ({}), got {}", path,
                            s.points.size(), s.directions.size()));
  TriMesh m;
  m.positions = s.points;
  m.normals = s.directions;
  write_mesh(path, m, MeshWriteOptions{.ascii = ascii});
}

PointSet read_points(const std::string& path) {
  TriMesh m = read_mesh(path);
  PointSet s;
  s.points = std::move(m.positions);
  if (ends_with_ply(path) && ply_header_has_normals(path) && m.normals.size() == s.points.size())
    s.directions = std::move(m.normals);
  return s;
}

}  // namespace inhap
