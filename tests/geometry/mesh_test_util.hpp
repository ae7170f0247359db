// Helpers for the mesh I/O tests: byte builders for hand-written binary PLY files and a small
// mesh with awkward doubles, normals and properties.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include "inhap/geometry/trimesh.hpp"

namespace inhap::test {

/// Appends values to a byte string in a chosen byte order.
class Bytes {
 public:
  explicit Bytes(bool big_endian) : big_(big_endian) {}
  Bytes& text(const std::string& s) {
    data_ += s;
    return *this;
  }
  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    const bool swap = big_ != (std::endian::native == std::endian::big);
    for (std::size_t i = 0; i < sizeof(T); ++i) data_ += b[swap ? sizeof(T) - 1 - i : i];
    return *this;
  }
  const std::string& str() const { return data_; }

 private:
  bool big_;
  std::string data_;
};

inline std::string write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// Two triangles on 4 vertices with doubles that need all 17 digits, -0.0, a subnormal, large
/// magnitudes, non-unit normals and three properties.
inline TriMesh awkward_mesh() {
  TriMesh m;
  m.positions = {Vec3(0.1, 1.0 / 3.0, -0.0), Vec3(1e-310, 2.0 / 3.0, 7.0),
                 Vec3(123456789.123456789, -1e300, 0.3), Vec3(-5e-324, 1.0 - 1e-16, 42.0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.normals = {Vec3(0, 0, 1), Vec3(0.6, 0.8, 0), Vec3(1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0),
               Vec3(-1, 0, 0)};
  m.properties["stiffness"] = {0.25, 1.0 / 7.0, 3.5e-8, 1e200};
  m.properties["confidence"] = {0.0, 0.999238, 1.0, 0.5};
  m.properties["z_last"] = {-1.0, -0.0, 2.0, std::numeric_limits<double>::min()};
  return m;
}

/// True when both meshes hold bit-identical doubles and equal triangles.
inline bool bit_identical(const TriMesh& a, const TriMesh& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() &&
           (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
  if (!same(a.positions, b.positions) || !same(a.normals, b.normals) || a.triangles != b.triangles)
    return false;
  if (a.properties.size() != b.properties.size()) return false;
  for (const auto& [name, v] : a.properties)
    if (!b.has_property(name) || !same(v, b.property(name))) return false;
  return true;
}

}  // namespace inhap::test
