// PLY header parsing and the checks that bound every later allocation by the file size.
#include <fmt/format.h>

#include <array>
#include <charconv>
#include <limits>

#include "inhap/core/error.hpp"
#include "ply_detail.hpp"

namespace inhap::ply_detail {

namespace {

struct TypeInfo {
  PlyType type;
  const char* name;
  const char* alias;
  std::size_t size;
};

constexpr std::array<TypeInfo, 8> kTypes{{
    {PlyType::kI8, "char", "int8", 1},
    {PlyType::kU8, "uchar", "uint8", 1},
    {PlyType::kI16, "short", "int16", 2},
    {PlyType::kU16, "ushort", "uint16", 2},
    {PlyType::kI32, "int", "int32", 4},
    {PlyType::kU32, "uint", "uint32", 4},
    {PlyType::kF32, "float", "float32", 4},
    {PlyType::kF64, "double", "float64", 8},
}};

constexpr std::uint64_t kMaxIndexable = std::numeric_limits<std::int32_t>::max();

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    const std::size_t start = i;
    while (i < s.size() && !is_space(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

std::uint64_t sat_mul(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a)
    return std::numeric_limits<std::uint64_t>::max();
  return a * b;
}

std::uint64_t sat_add(std::uint64_t a, std::uint64_t b) {
  return b > std::numeric_limits<std::uint64_t>::max() - a
             ? std::numeric_limits<std::uint64_t>::max()
             : a + b;
}

class HeaderParser {
 public:
  HeaderParser(std::string_view bytes, const std::string& source) : b_(bytes), src_(source) {}

  PlyHeader run() {
    if (b_.empty()) fail(1, "expected 'ply' magic, got an empty file");
    std::string_view line;
    next_line(line);
    if (line != "ply") fail(1, fmt::format("expected 'ply' magic, got {}", quote_token(line)));
    bool have_format = false;
    while (true) {
      if (!next_line(line))
        fail(line_,
             fmt::format("expected 'end_header', got end of file after {} header lines", line_));
      const auto tok = split(line);
      if (tok.empty()) continue;
      const std::string_view kw = tok[0];
      if (kw == "comment" || kw == "obj_info") continue;
      if (kw == "end_header") break;
      if (kw == "format") {
        if (have_format) fail(line_, "expected one 'format' line, got a second one");
        parse_format(tok);
        have_format = true;
      } else if (kw == "element") {
        parse_element(tok);
      } else if (kw == "property") {
        parse_property(tok);
      } else {
        fail(line_,
             fmt::format(
                 "expected comment, obj_info, format, element, property or end_header, got {}",
                 quote_token(kw)));
      }
    }
    if (!have_format) fail(line_, "expected a 'format' line before end_header");
    h_.data_offset = pos_;
    h_.lines = line_;
    check_sizes();
    return std::move(h_);
  }

 private:
  [[noreturn]] void fail(std::size_t line, std::string_view msg) const {
    throw ParseError(src_, line, msg);
  }

  bool next_line(std::string_view& out) {
    if (pos_ >= b_.size()) return false;
    const std::size_t nl = b_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? b_.size() : nl;
    out = b_.substr(pos_, end - pos_);
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    pos_ = nl == std::string_view::npos ? b_.size() : nl + 1;
    ++line_;
    return true;
  }

  void parse_format(const std::vector<std::string_view>& tok) {
    if (tok.size() != 3)
      fail(line_,
           fmt::format(
               "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0', got {} words",
               tok.size()));
    if (tok[1] == "ascii")
      h_.format = PlyFormat::kAscii;
    else if (tok[1] == "binary_little_endian")
      h_.format = PlyFormat::kBinaryLittleEndian;
    else if (tok[1] == "binary_big_endian")
      h_.format = PlyFormat::kBinaryBigEndian;
    else
      fail(line_,
           fmt::format("expected format ascii, binary_little_endian or binary_big_endian, got {}",
                       quote_token(tok[1])));
    if (tok[2] != "1.0" && tok[2] != "1")
      fail(line_, fmt::format("expected format version 1.0, got {}", quote_token(tok[2])));
  }

  void parse_element(const std::vector<std::string_view>& tok) {
    if (tok.size() != 3)
      fail(line_, fmt::format("expected 'element <name> <count>', got {} words", tok.size()));
    PlyElement el;
    el.name = std::string(tok[1]);
    el.line = line_;
    const auto c = tok[2];
    const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), el.count);
    if (ec != std::errc() || end != c.data() + c.size())
      fail(line_, fmt::format("expected a non-negative element count, got {}", quote_token(c)));
    for (const auto& e : h_.elements)
      if (e.name == el.name)
        fail(line_,
             fmt::format("expected each element once, got a second {}", quote_token(el.name)));
    if ((el.name == "vertex" || el.name == "face") && el.count > kMaxIndexable)
      fail(line_,
           fmt::format("expected at most {} {} records, got {}", kMaxIndexable, el.name, el.count));
    h_.elements.push_back(std::move(el));
  }

  PlyType parse_type(std::string_view name) const {
    for (const auto& t : kTypes)
      if (name == t.name || name == t.alias) return t.type;
    fail(line_, fmt::format("expected a property type (char, uchar, short, ushort, int, uint, "
                            "float, double or int8..float64), got {}",
                            quote_token(name)));
  }

  void parse_property(const std::vector<std::string_view>& tok) {
    if (h_.elements.empty()) fail(line_, "expected an 'element' line before the first property");
    PlyProperty p;
    p.line = line_;
    if (tok.size() >= 2 && tok[1] == "list") {
      if (tok.size() != 5)
        fail(line_,
             fmt::format("expected 'property list <count type> <item type> <name>', got {} words",
                         tok.size()));
      p.is_list = true;
      p.count_type = parse_type(tok[2]);
      if (!is_integer(p.count_type))
        fail(line_,
             fmt::format("expected an integer list count type, got {}", quote_token(tok[2])));
      p.type = parse_type(tok[3]);
      p.name = std::string(tok[4]);
    } else {
      if (tok.size() != 3)
        fail(line_, fmt::format("expected 'property <type> <name>', got {} words", tok.size()));
      p.type = parse_type(tok[1]);
      p.name = std::string(tok[2]);
    }
    auto& el = h_.elements.back();
    for (const auto& q : el.props)
      if (q.name == p.name)
        fail(line_, fmt::format("expected distinct property names in element '{}', got {} twice",
                                el.name, quote_token(p.name)));
    el.props.push_back(std::move(p));
  }

  /// Binary: every record needs at least the sum of its scalar sizes and list-count sizes.
  /// Ascii: every value is a token of at least one byte followed by a separator.
  void check_sizes() const {
    const std::uint64_t remaining = b_.size() - h_.data_offset;
    std::uint64_t total = 0;
    for (const auto& el : h_.elements) {
      if (h_.format == PlyFormat::kAscii) {
        total = sat_add(total, sat_mul(el.count, el.props.size()));
        if (total > (remaining + 1) / 2)
          fail(el.line,
               fmt::format("expected at most {} values in the data, but element '{}' declares {} "
                           "records of {} values "
                           "(only {} bytes follow the header)",
                           (remaining + 1) / 2, el.name, el.count, el.props.size(), remaining));
      } else {
        std::uint64_t min_size = 0;
        for (const auto& p : el.props) min_size += type_size(p.is_list ? p.count_type : p.type);
        total = sat_add(total, sat_mul(el.count, min_size));
        if (total > remaining)
          fail(el.line, fmt::format("expected at most {} bytes of data, but element '{}' declares "
                                    "{} records of at least {} bytes",
                                    remaining, el.name, el.count, min_size));
      }
    }
  }

  std::string_view b_;
  const std::string& src_;
  std::size_t pos_ = 0, line_ = 0;
  PlyHeader h_;
};

}  // namespace

std::size_t type_size(PlyType t) {
  return kTypes[static_cast<std::size_t>(t)].size;
}
bool is_integer(PlyType t) {
  return t != PlyType::kF32 && t != PlyType::kF64;
}
const char* type_name(PlyType t) {
  return kTypes[static_cast<std::size_t>(t)].name;
}

PlyHeader parse_header(std::string_view bytes, const std::string& source) {
  return HeaderParser(bytes, source).run();
}

}  // namespace inhap::ply_detail
