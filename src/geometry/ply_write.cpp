// PLY writer: positions, normals and every vertex property as double; faces as
// `list uchar int vertex_indices`. Streams through AtomicFile in 1 MiB chunks.
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/ply.hpp"

namespace inhap {

namespace {

constexpr std::size_t kChunk = 1 << 20;

bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7f) return false;
  return true;
}

void check_writable(const TriMesh& mesh, const std::string& where) {
  mesh.validate(where);
  for (std::size_t i = 0; i < mesh.normals.size(); ++i)
    if (!mesh.normals[i].allFinite())
      throw Error(fmt::format("{}: vertex {}: expected a finite normal, got ({}, {}, {})", where, i,
                              mesh.normals[i].x(), mesh.normals[i].y(), mesh.normals[i].z()));
  for (const auto& [name, values] : mesh.properties) {
    if (!valid_name(name))
      throw Error(fmt::format(
          "{}: vertex property {}: expected a PLY name without spaces or control characters", where,
          quote_token(name)));
    for (const char* reserved : {"x", "y", "z", "nx", "ny", "nz"})
      if (name == reserved)
        throw Error(
            fmt::format("{}: vertex property '{}': expected a name other than x, y, z, nx, ny, nz",
                        where, name));
  }
}

class PlyEmitter {
 public:
  PlyEmitter(PlyFormat format, std::function<void(std::string_view)> sink)
      : format_(format), sink_(std::move(sink)) {
    buf_.reserve(kChunk + 4096);
  }

  void run(const TriMesh& mesh) {
    header(mesh);
    std::vector<const std::vector<double>*> cols;
    for (const auto& [name, values] : mesh.properties) cols.push_back(&values);
    const bool normals = !mesh.normals.empty();
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3& p = mesh.positions[i];
      value(p.x(), true);
      value(p.y(), false);
      value(p.z(), false);
      if (normals) {
        const Vec3& n = mesh.normals[i];
        value(n.x(), false);
        value(n.y(), false);
        value(n.z(), false);
      }
      for (const auto* c : cols) value((*c)[i], false);
      end_line();
    }
    for (const Tri& t : mesh.triangles) {
      if (format_ == PlyFormat::kAscii) {
        fmt::format_to(std::back_inserter(buf_), "3 {} {} {}\n", t[0], t[1], t[2]);
      } else {
        buf_.push_back(3);
        for (auto v : t) raw(std::bit_cast<std::uint32_t>(v));
      }
      maybe_flush();
    }
    flush();
  }

 private:
  void header(const TriMesh& mesh) {
    const char* fmt_name = format_ == PlyFormat::kAscii                ? "ascii"
                           : format_ == PlyFormat::kBinaryLittleEndian ? "binary_little_endian"
                                                                       : "binary_big_endian";
    buf_ += fmt::format("ply\nformat {} 1.0\n", fmt_name);
    buf_ += "comment written by inhap; units: positions mm, stiffness N/mm\n";
    buf_ += fmt::format("element vertex {}\n", mesh.positions.size());
    buf_ += "property double x\nproperty double y\nproperty double z\n";
    if (!mesh.normals.empty())
      buf_ += "property double nx\nproperty double ny\nproperty double nz\n";
    for (const auto& [name, values] : mesh.properties)
      buf_ += fmt::format("property double {}\n", name);
    buf_ += fmt::format("element face {}\n", mesh.triangles.size());
    buf_ += "property list uchar int vertex_indices\nend_header\n";
  }

  void value(double v, bool first) {
    if (format_ == PlyFormat::kAscii) {
      if (!first) buf_.push_back(' ');
      fmt::format_to(std::back_inserter(buf_), "{}", v);  // shortest exact round-trip form
    } else {
      raw(std::bit_cast<std::uint64_t>(v));
    }
  }

  template <class U>
  void raw(U u) {
    const bool big = format_ == PlyFormat::kBinaryBigEndian;
    if (big != (std::endian::native == std::endian::big)) {
      if constexpr (sizeof(U) == 4) u = __builtin_bswap32(u);
      if constexpr (sizeof(U) == 8) u = __builtin_bswap64(u);
    }
    char bytes[sizeof(U)];
    std::memcpy(bytes, &u, sizeof(U));
    buf_.append(bytes, sizeof(U));
  }

  void end_line() {
    if (format_ == PlyFormat::kAscii) buf_.push_back('\n');
    maybe_flush();
  }
  void maybe_flush() {
    if (buf_.size() >= kChunk) flush();
  }
  void flush() {
    sink_(buf_);
    buf_.clear();
  }

  PlyFormat format_;
  std::function<void(std::string_view)> sink_;
  std::string buf_;
};

}  // namespace

void write_ply(const std::string& path, const TriMesh& mesh, const PlyWriteOptions& options) {
  check_writable(mesh, path);
  AtomicFile file(path);
  PlyEmitter(options.format, [&](std::string_view bytes) { file.write(bytes); }).run(mesh);
  file.commit();
}

std::string format_ply(const TriMesh& mesh, const PlyWriteOptions& options) {
  check_writable(mesh, "format_ply");
  std::string out;
  PlyEmitter(options.format, [&](std::string_view bytes) { out.append(bytes); }).run(mesh);
  return out;
}

}  // namespace inhap
