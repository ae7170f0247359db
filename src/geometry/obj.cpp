// Wavefront OBJ reader and writer (geometry only: v and f).
#include "inhap/geometry/obj.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "polygon_detail.hpp"

namespace inhap {

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool is_identifier(std::string_view s) {
  for (char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
      return false;
  return !s.empty();
}

class ObjParser {
 public:
  ObjParser(std::string_view text, const std::string& source) : t_(text), src_(source) {}

  TriMesh run() {
    std::size_t pos = 0;
    while (pos < t_.size()) {
      const std::size_t nl = t_.find('\n', pos);
      const std::size_t end = nl == std::string_view::npos ? t_.size() : nl;
      line_ = t_.substr(pos, end - pos);
      pos = nl == std::string_view::npos ? t_.size() : nl + 1;
      ++line_no_;
      if (const auto hash = line_.find('#'); hash != std::string_view::npos)
        line_ = line_.substr(0, hash);
      cur_ = 0;
      statement();
    }
    if (mesh_.positions.empty())
      throw ParseError(src_, 0, "expected at least one 'v' line, got none");
    if (max_ref_ > static_cast<std::int64_t>(mesh_.positions.size()))
      throw ParseError(
          src_, max_ref_line_,
          fmt::format("face: expected vertex indices up to {} (the file's vertex count), got {}",
                      mesh_.positions.size(), max_ref_));
    mesh_.validate(src_);
    mesh_.compute_normals();
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(std::string_view msg) const { throw ParseError(src_, line_no_, msg); }

  std::string_view token() {
    while (cur_ < line_.size() && is_space(line_[cur_])) ++cur_;
    const std::size_t start = cur_;
    while (cur_ < line_.size() && !is_space(line_[cur_])) ++cur_;
    return line_.substr(start, cur_ - start);
  }

  void statement() {
    const auto kw = token();
    if (kw.empty()) return;
    if (kw == "v") return vertex();
    if (kw == "f") return face();
    // vn, vt, vp, l, p, o, g, s, usemtl, mtllib, curves and surfaces: not geometry we keep.
    if (!is_identifier(kw))
      fail(fmt::format("expected an OBJ statement (v, f, vn, vt, o, g, s, usemtl, ...), got {}",
                       quote_token(kw)));
  }

  void vertex() {
    Vec3 p;
    for (int c = 0; c < 3; ++c) {
      const auto tok = token();
      const char* axis = c == 0 ? "x" : c == 1 ? "y" : "z";
      if (tok.empty()) fail(fmt::format("v: expected 3 coordinates, got {} (no {})", c, axis));
      std::string_view s = tok;
      if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
      double v = 0;
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
      if (ec != std::errc() || end != s.data() + s.size())
        fail(fmt::format("v: expected a number for {}, got {}", axis, quote_token(tok)));
      if (!std::isfinite(v))
        fail(fmt::format("v: expected a finite {}, got {}", axis, quote_token(tok)));
      p[c] = v;
    }
    // Anything after x y z (w, or r g b colours) is ignored.
    mesh_.positions.push_back(p);
  }

  std::int32_t resolve(std::string_view tok) {
    const std::size_t slash = tok.find('/');
    const std::string_view num = tok.substr(0, slash);
    std::int64_t k = 0;
    const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), k);
    if (ec != std::errc() || end != num.data() + num.size() || num.empty())
      fail(fmt::format("f: expected a vertex reference v, v/vt, v//vn or v/vt/vn, got {}",
                       quote_token(tok)));
    const auto nv = static_cast<std::int64_t>(mesh_.positions.size());
    constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
    if (k == 0)
      fail(fmt::format("f: expected a non-zero vertex index (OBJ counts from 1), got {}",
                       quote_token(tok)));
    if (k > kMax) fail(fmt::format("f: expected a vertex index up to {}, got {}", kMax, k));
    if (k < 0) {
      if (nv + k < 0)
        fail(fmt::format("f: expected a relative index from -1 to -{} (vertices so far), got {}",
                         nv, k));
      return static_cast<std::int32_t>(nv + k);
    }
    if (k > max_ref_) {  // checked at the end: the vertex may be defined later in the file
      max_ref_ = k;
      max_ref_line_ = line_no_;
    }
    return static_cast<std::int32_t>(k - 1);
  }

  void face() {
    poly_.clear();
    for (auto tok = token(); !tok.empty(); tok = token()) poly_.push_back(resolve(tok));
    if (poly_.size() < 3)
      fail(fmt::format("f: expected at least 3 vertices, got {}", poly_.size()));
    const std::string why = mesh_detail::fan_triangulate(poly_, mesh_.triangles);
    if (!why.empty()) fail("f: " + why);
  }

  std::string_view t_;
  const std::string& src_;
  std::string_view line_;
  std::size_t cur_ = 0, line_no_ = 0;
  TriMesh mesh_;
  std::vector<std::int32_t> poly_;
  std::int64_t max_ref_ = 0;
  std::size_t max_ref_line_ = 0;
};

}  // namespace

TriMesh parse_obj(std::string_view text, const std::string& source) {
  return ObjParser(text, source).run();
}

TriMesh read_obj(const std::string& path) {
  return parse_obj(read_file(path), path);
}

std::string format_obj(const TriMesh& mesh) {
  std::string out = "# written by inhap; units: mm\n";
  auto it = std::back_inserter(out);
  for (const Vec3& p : mesh.positions) fmt::format_to(it, "v {} {} {}\n", p.x(), p.y(), p.z());
  for (const Tri& t : mesh.triangles)
    fmt::format_to(it, "f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  return out;
}

std::vector<std::string> write_obj(const std::string& path, const TriMesh& mesh) {
  mesh.validate(path);
  write_file_atomic(path, format_obj(mesh));
  std::vector<std::string> dropped;
  for (const auto& [name, values] : mesh.properties) dropped.push_back(name);
  return dropped;
}

}  // namespace inhap
