// PLY reader: the header is parsed by ply_header.cpp, the data by one templated element reader
// over two value sources (ascii tokens with line numbers; binary bytes with record indices).
#include "inhap/geometry/ply.hpp"

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "ply_detail.hpp"
#include "polygon_detail.hpp"

namespace inhap {

using namespace ply_detail;

namespace {

bool ply_is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// ---------------------------------------------------------------------------------------------
// Binary values: bounds-checked reads from the in-memory file, byte-swapped when needed.
class BinarySource {
 public:
  BinarySource(std::string_view data, bool swap, const std::string& source)
      : p_(data.data()), end_(data.data() + data.size()), swap_(swap), src_(source) {}

  void begin_record(const PlyElement& el, std::uint64_t r) {
    el_ = &el;
    rec_ = r;
  }
  void end_record() {}

  double scalar(const PlyProperty& p) { return read_value(p.type, p); }

  std::uint64_t list_count(const PlyProperty& p) {
    const auto c = read_int(p.count_type, p);
    if (c < 0) fail(p, fmt::format("expected a non-negative list count, got {}", c));
    const auto n = static_cast<std::uint64_t>(c);
    if (n > static_cast<std::uint64_t>(end_ - p_) / type_size(p.type))
      fail(p, fmt::format(
                  "expected {} list items of {} bytes, got only {} bytes before the end of file", n,
                  type_size(p.type), end_ - p_));
    return n;
  }

  std::int64_t index(const PlyProperty& p) { return read_int(p.type, p); }

  void skip_scalar(const PlyProperty& p) { advance(type_size(p.type), p); }
  void skip_list(const PlyProperty& p) { advance(list_count(p) * type_size(p.type), p); }

  /// Skips a whole element of scalars at once. False when it has lists.
  bool skip_fixed_element(const PlyElement& el) {
    std::uint64_t size = 0;
    for (const auto& p : el.props) {
      if (p.is_list) return false;
      size += type_size(p.type);
    }
    // parse_header checked count * size against the file size.
    const std::uint64_t bytes = el.count * size;
    begin_record(el, 0);
    if (!el.props.empty()) advance(bytes, el.props.front());
    return true;
  }

  void finish() {}

  [[noreturn]] void fail(const PlyProperty& p, std::string_view what) const {
    throw ParseError(
        src_, 0,
        fmt::format("element '{}' record {}, property '{}': {}", el_->name, rec_, p.name, what));
  }

 private:
  template <class U>
  U load(const PlyProperty& p) {
    if (static_cast<std::size_t>(end_ - p_) < sizeof(U))
      fail(p, fmt::format("expected {} more bytes, got end of file", sizeof(U)));
    U u;
    std::memcpy(&u, p_, sizeof(U));
    p_ += sizeof(U);
    if (swap_) {
      if constexpr (sizeof(U) == 2) u = __builtin_bswap16(u);
      if constexpr (sizeof(U) == 4) u = __builtin_bswap32(u);
      if constexpr (sizeof(U) == 8) u = __builtin_bswap64(u);
    }
    return u;
  }

  std::int64_t read_int(PlyType t, const PlyProperty& p) {
    switch (t) {
      case PlyType::kI8:
        return std::bit_cast<std::int8_t>(load<std::uint8_t>(p));
      case PlyType::kU8:
        return load<std::uint8_t>(p);
      case PlyType::kI16:
        return std::bit_cast<std::int16_t>(load<std::uint16_t>(p));
      case PlyType::kU16:
        return load<std::uint16_t>(p);
      case PlyType::kI32:
        return std::bit_cast<std::int32_t>(load<std::uint32_t>(p));
      case PlyType::kU32:
        return load<std::uint32_t>(p);
      default:
        fail(p, "expected an integer type");  // excluded by the header checks
    }
  }

  double read_value(PlyType t, const PlyProperty& p) {
    if (t == PlyType::kF32) return std::bit_cast<float>(load<std::uint32_t>(p));
    if (t == PlyType::kF64) return std::bit_cast<double>(load<std::uint64_t>(p));
    return static_cast<double>(read_int(t, p));
  }

  void advance(std::uint64_t bytes, const PlyProperty& p) {
    if (bytes > static_cast<std::uint64_t>(end_ - p_))
      fail(p,
           fmt::format("expected {} more bytes, got {} before the end of file", bytes, end_ - p_));
    p_ += bytes;
  }

  const char* p_;
  const char* end_;
  bool swap_;
  const std::string& src_;
  const PlyElement* el_ = nullptr;
  std::uint64_t rec_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Ascii values: one record per line, whitespace-separated tokens, line numbers for errors.
class AsciiSource {
 public:
  AsciiSource(std::string_view data, std::size_t first_line, const std::string& source)
      : d_(data), line_no_(first_line), src_(source) {}

  void begin_record(const PlyElement& el, std::uint64_t r) {
    el_ = &el;
    rec_ = r;
    while (true) {
      if (pos_ >= d_.size())
        throw ParseError(
            src_, line_no_,
            fmt::format(
                "element '{}' record {}: expected a line with the record's values, got end of file",
                el.name, r));
      if (next_line()) return;
    }
  }

  void end_record() {
    const auto tok = next_token();
    if (!tok.empty())
      throw ParseError(
          src_, line_no_,
          fmt::format("element '{}' record {}: expected end of line after {} properties, got {}",
                      el_->name, rec_, el_->props.size(), quote_token(tok)));
  }

  double scalar(const PlyProperty& p) { return parse_value(p.type, p, token(p)); }

  std::uint64_t list_count(const PlyProperty& p) {
    const auto c = parse_int(p.count_type, p, token(p));
    if (c < 0) fail(p, fmt::format("expected a non-negative list count, got {}", c));
    return static_cast<std::uint64_t>(c);
  }

  std::int64_t index(const PlyProperty& p) { return parse_int(p.type, p, token(p)); }

  void skip_scalar(const PlyProperty& p) { scalar(p); }
  void skip_list(const PlyProperty& p) {
    const auto n = list_count(p);
    for (std::uint64_t i = 0; i < n; ++i) parse_value(p.type, p, token(p));
  }
  bool skip_fixed_element(const PlyElement&) { return false; }

  /// After the last element only whitespace may follow.
  void finish() {
    while (pos_ < d_.size()) {
      if (next_line()) {
        const auto tok = next_token();
        throw ParseError(
            src_, line_no_,
            fmt::format("expected end of file after the last element, got {}", quote_token(tok)));
      }
    }
  }

  [[noreturn]] void fail(const PlyProperty& p, std::string_view what) const {
    throw ParseError(
        src_, line_no_,
        fmt::format("element '{}' record {}, property '{}': {}", el_->name, rec_, p.name, what));
  }

 private:
  /// Moves to the next line; true when it holds a token.
  bool next_line() {
    const std::size_t nl = d_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? d_.size() : nl;
    cur_ = pos_;
    line_end_ = end;
    pos_ = nl == std::string_view::npos ? d_.size() : nl + 1;
    ++line_no_;
    while (cur_ < line_end_ && ply_is_space(d_[cur_])) ++cur_;
    return cur_ < line_end_;
  }

  std::string_view next_token() {
    while (cur_ < line_end_ && ply_is_space(d_[cur_])) ++cur_;
    const std::size_t start = cur_;
    while (cur_ < line_end_ && !ply_is_space(d_[cur_])) ++cur_;
    return d_.substr(start, cur_ - start);
  }

  std::string_view token(const PlyProperty& p) {
    const auto tok = next_token();
    if (tok.empty())
      fail(p, fmt::format("expected a {} value, got end of line", type_name(p.type)));
    return tok;
  }

  std::int64_t parse_int(PlyType t, const PlyProperty& p, std::string_view tok) const {
    std::string_view s = tok;
    if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    const bool ok = ec == std::errc() && end == s.data() + s.size();
    std::int64_t lo = 0, hi = 0;
    switch (t) {
      case PlyType::kI8:
        lo = -128, hi = 127;
        break;
      case PlyType::kU8:
        lo = 0, hi = 255;
        break;
      case PlyType::kI16:
        lo = -32768, hi = 32767;
        break;
      case PlyType::kU16:
        lo = 0, hi = 65535;
        break;
      case PlyType::kI32:
        lo = std::numeric_limits<std::int32_t>::min(),
        hi = std::numeric_limits<std::int32_t>::max();
        break;
      default:
        lo = 0, hi = std::numeric_limits<std::uint32_t>::max();
        break;
    }
    if (!ok || v < lo || v > hi)
      fail(p, fmt::format("expected an integer of type {} in [{}, {}], got {}", type_name(t), lo,
                          hi, quote_token(tok)));
    return v;
  }

  double parse_value(PlyType t, const PlyProperty& p, std::string_view tok) const {
    if (is_integer(t)) return static_cast<double>(parse_int(t, p, tok));
    std::string_view s = tok;
    if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);
    double v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size())
      fail(p, fmt::format("expected a {} number, got {}", type_name(t), quote_token(tok)));
    if (t == PlyType::kF32) {
      // Same value as the binary float would give; out-of-range would be undefined behaviour.
      if (std::isfinite(v) && std::fabs(v) > std::numeric_limits<float>::max())
        fail(p,
             fmt::format("expected a float number, got {} (out of float range)", quote_token(tok)));
      v = static_cast<float>(v);
    }
    return v;
  }

  std::string_view d_;
  std::size_t pos_ = 0, cur_ = 0, line_end_ = 0, line_no_;
  const std::string& src_;
  const PlyElement* el_ = nullptr;
  std::uint64_t rec_ = 0;
};

// ---------------------------------------------------------------------------------------------
// What to do with each vertex / face property.
enum class Target : std::uint8_t { kX, kY, kZ, kNx, kNy, kNz, kProp, kSkip };

struct VertexPlan {
  const PlyElement* el = nullptr;
  std::vector<Target> targets;
  std::vector<std::size_t> slots;  ///< property column per target (Target::kProp only)
  std::vector<std::string> names;  ///< property names, by slot
  bool normals = false;
};

struct FacePlan {
  const PlyElement* el = nullptr;
  std::size_t list = 0;  ///< index of vertex_indices / vertex_index
};

const PlyProperty* find_prop(const PlyElement& el, std::string_view name) {
  for (const auto& p : el.props)
    if (p.name == name) return &p;
  return nullptr;
}

VertexPlan plan_vertices(const PlyHeader& h, const std::string& src) {
  VertexPlan plan;
  for (const auto& el : h.elements)
    if (el.name == "vertex") plan.el = &el;
  if (!plan.el)
    throw ParseError(src, h.lines, "expected an 'element vertex' in the header, got none");
  const PlyElement& el = *plan.el;
  for (const char* axis : {"x", "y", "z"}) {
    const PlyProperty* p = find_prop(el, axis);
    if (!p)
      throw ParseError(
          src, el.line,
          fmt::format("element 'vertex': expected a scalar property '{}', got none", axis));
    if (p->is_list)
      throw ParseError(
          src, p->line,
          fmt::format("property '{}' of element 'vertex': expected a scalar, got a list", axis));
  }
  int scalar_normals = 0;
  for (const char* n : {"nx", "ny", "nz"}) {
    const PlyProperty* p = find_prop(el, n);
    scalar_normals += p && !p->is_list;
  }
  plan.normals = scalar_normals == 3;
  for (const auto& p : el.props) {
    Target t = Target::kProp;
    if (p.is_list)
      t = Target::kSkip;
    else if (p.name == "x")
      t = Target::kX;
    else if (p.name == "y")
      t = Target::kY;
    else if (p.name == "z")
      t = Target::kZ;
    else if (plan.normals && p.name == "nx")
      t = Target::kNx;
    else if (plan.normals && p.name == "ny")
      t = Target::kNy;
    else if (plan.normals && p.name == "nz")
      t = Target::kNz;
    plan.targets.push_back(t);
    plan.slots.push_back(plan.names.size());
    if (t == Target::kProp) plan.names.push_back(p.name);
  }
  return plan;
}

FacePlan plan_faces(const PlyHeader& h, const std::string& src) {
  FacePlan plan;
  for (const auto& el : h.elements)
    if (el.name == "face") plan.el = &el;
  if (!plan.el) return plan;
  const PlyElement& el = *plan.el;
  for (std::size_t i = 0; i < el.props.size(); ++i) {
    const auto& p = el.props[i];
    if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
    if (!p.is_list)
      throw ParseError(
          src, p.line,
          fmt::format("property '{}' of element 'face': expected a list, got a scalar {}", p.name,
                      type_name(p.type)));
    if (!is_integer(p.type))
      throw ParseError(
          src, p.line,
          fmt::format("property '{}' of element 'face': expected an integer index type, got {}",
                      p.name, type_name(p.type)));
    plan.list = i;
    return plan;
  }
  throw ParseError(
      src, el.line,
      "element 'face': expected a list property 'vertex_indices' or 'vertex_index', got none");
}

// ---------------------------------------------------------------------------------------------
template <class Src>
void read_vertices(Src& s, const VertexPlan& plan, TriMesh& mesh) {
  const PlyElement& el = *plan.el;
  // parse_header bounded el.count by the bytes in the file, so these sizes are not absurd.
  const auto n = static_cast<std::size_t>(el.count);
  mesh.positions.assign(n, Vec3::Zero());
  if (plan.normals) mesh.normals.assign(n, Vec3::Zero());
  std::vector<double*> cols;
  for (const auto& name : plan.names) {
    auto& col = mesh.properties[name];
    col.assign(n, 0.0);
    cols.push_back(col.data());
  }
  for (std::size_t r = 0; r < n; ++r) {
    s.begin_record(el, r);
    Vec3& pos = mesh.positions[r];
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const PlyProperty& p = el.props[k];
      const Target t = plan.targets[k];
      if (t == Target::kSkip) {
        s.skip_list(p);
        continue;
      }
      const double v = s.scalar(p);
      if (!std::isfinite(v)) s.fail(p, fmt::format("expected a finite number, got {}", v));
      switch (t) {
        case Target::kX:
          pos.x() = v;
          break;
        case Target::kY:
          pos.y() = v;
          break;
        case Target::kZ:
          pos.z() = v;
          break;
        case Target::kNx:
          mesh.normals[r].x() = v;
          break;
        case Target::kNy:
          mesh.normals[r].y() = v;
          break;
        case Target::kNz:
          mesh.normals[r].z() = v;
          break;
        default:
          cols[plan.slots[k]][r] = v;
          break;
      }
    }
    s.end_record();
  }
}

template <class Src>
void read_faces(Src& s, const FacePlan& plan, std::uint64_t num_vertices, TriMesh& mesh) {
  const PlyElement& el = *plan.el;
  mesh.triangles.reserve(static_cast<std::size_t>(el.count));  // bounded by the file size
  std::vector<std::int32_t> poly;
  for (std::uint64_t r = 0; r < el.count; ++r) {
    s.begin_record(el, r);
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const PlyProperty& p = el.props[k];
      if (k != plan.list) {
        if (p.is_list)
          s.skip_list(p);
        else
          s.skip_scalar(p);
        continue;
      }
      const std::uint64_t n = s.list_count(p);
      if (n < 3) s.fail(p, fmt::format("expected at least 3 vertex indices, got {}", n));
      poly.clear();
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::int64_t v = s.index(p);
        if (v < 0) s.fail(p, fmt::format("expected a non-negative vertex index, got {}", v));
        if (static_cast<std::uint64_t>(v) >= num_vertices)
          s.fail(p, fmt::format("expected a vertex index in [0, {}), got {}", num_vertices, v));
        poly.push_back(static_cast<std::int32_t>(v));
      }
      const std::string why = mesh_detail::fan_triangulate(poly, mesh.triangles);
      if (!why.empty()) s.fail(p, why);
    }
    s.end_record();
  }
}

template <class Src>
void read_other(Src& s, const PlyElement& el) {
  if (el.props.empty() || s.skip_fixed_element(el)) return;
  for (std::uint64_t r = 0; r < el.count; ++r) {
    s.begin_record(el, r);
    for (const auto& p : el.props) {
      if (p.is_list)
        s.skip_list(p);
      else
        s.skip_scalar(p);
    }
    s.end_record();
  }
}

template <class Src>
void read_body(Src& s, const PlyHeader& h, const VertexPlan& vp, const FacePlan& fp,
               TriMesh& mesh) {
  for (const auto& el : h.elements) {
    if (&el == vp.el)
      read_vertices(s, vp, mesh);
    else if (&el == fp.el)
      read_faces(s, fp, vp.el->count, mesh);
    else
      read_other(s, el);
  }
  s.finish();
}

}  // namespace

TriMesh parse_ply(std::string_view bytes, const std::string& source) {
  const PlyHeader h = parse_header(bytes, source);
  const VertexPlan vp = plan_vertices(h, source);
  const FacePlan fp = plan_faces(h, source);
  const std::string_view data = bytes.substr(h.data_offset);
  TriMesh mesh;
  if (h.format == PlyFormat::kAscii) {
    AsciiSource s(data, h.lines, source);
    read_body(s, h, vp, fp, mesh);
  } else {
    const bool file_big = h.format == PlyFormat::kBinaryBigEndian;
    BinarySource s(data, file_big != (std::endian::native == std::endian::big), source);
    read_body(s, h, vp, fp, mesh);
  }
  mesh.validate(source);
  if (mesh.normals.empty()) mesh.compute_normals();
  return mesh;
}

TriMesh read_ply(const std::string& path) {
  return parse_ply(read_file(path), path);
}

}  // namespace inhap
