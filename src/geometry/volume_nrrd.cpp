// NRRD volume reader (http://teem.sourceforge.net/nrrd/format.html), the subset CT data uses:
// 3-D, raw encoding, integer or floating samples, detached or attached data, one file, a
// numbered file series or a LIST. Units: spacings and origin mm.
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/text.hpp"
#include "inhap/geometry/volume.hpp"

namespace inhap {

namespace {

enum class SampleType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

struct Field {
  std::string value;
  std::size_t line = 0;
};

using text::lower;
using text::trim;

std::size_t type_size(SampleType t) {
  switch (t) {
    case SampleType::kI8:
    case SampleType::kU8:
      return 1;
    case SampleType::kI16:
    case SampleType::kU16:
      return 2;
    case SampleType::kI32:
    case SampleType::kU32:
    case SampleType::kF32:
      return 4;
    case SampleType::kF64:
      return 8;
  }
  return 0;
}

SampleType parse_type(const std::string& path, const Field& f) {
  static const std::map<std::string, SampleType> names = {{"signed char", SampleType::kI8},
                                                          {"int8", SampleType::kI8},
                                                          {"int8_t", SampleType::kI8},
                                                          {"uchar", SampleType::kU8},
                                                          {"unsigned char", SampleType::kU8},
                                                          {"uint8", SampleType::kU8},
                                                          {"uint8_t", SampleType::kU8},
                                                          {"short", SampleType::kI16},
                                                          {"short int", SampleType::kI16},
                                                          {"signed short", SampleType::kI16},
                                                          {"signed short int", SampleType::kI16},
                                                          {"int16", SampleType::kI16},
                                                          {"int16_t", SampleType::kI16},
                                                          {"ushort", SampleType::kU16},
                                                          {"unsigned short", SampleType::kU16},
                                                          {"unsigned short int", SampleType::kU16},
                                                          {"uint16", SampleType::kU16},
                                                          {"uint16_t", SampleType::kU16},
                                                          {"int", SampleType::kI32},
                                                          {"signed int", SampleType::kI32},
                                                          {"int32", SampleType::kI32},
                                                          {"int32_t", SampleType::kI32},
                                                          {"uint", SampleType::kU32},
                                                          {"unsigned int", SampleType::kU32},
                                                          {"uint32", SampleType::kU32},
                                                          {"uint32_t", SampleType::kU32},
                                                          {"float", SampleType::kF32},
                                                          {"double", SampleType::kF64}};
  auto it = names.find(lower(f.value));
  if (it == names.end())
    throw ParseError(
        path, f.line,
        fmt::format("expected a sample type (short, ushort, int, float, double, ...), got {}",
                    quote_token(f.value)));
  return it->second;
}

std::vector<double> parse_numbers(const std::string& path, const Field& f, std::size_t count,
                                  const char* what) {
  std::istringstream in(f.value);
  std::vector<double> out;
  std::string tok;
  while (in >> tok) {
    double v;
    if (lower(tok) == "nan")
      v = std::nan("");
    else if (!parse_double(tok, v))
      throw ParseError(path, f.line,
                       fmt::format("{}: expected a number, got {}", what, quote_token(tok)));
    out.push_back(v);
  }
  if (out.size() != count)
    throw ParseError(path, f.line,
                     fmt::format("{}: expected {} values, got {}", what, count, out.size()));
  return out;
}

// "(a,b,c)" vectors, "none" allowed.
std::vector<Vec3> parse_vectors(const std::string& path, const Field& f, std::size_t count,
                                const char* what) {
  std::vector<Vec3> out;
  std::size_t pos = 0;
  const std::string& s = f.value;
  while (pos < s.size()) {
    while (pos < s.size() && std::isspace(static_cast<unsigned char>(s[pos]))) ++pos;
    if (pos >= s.size()) break;
    if (s.compare(pos, 4, "none") == 0) {
      out.emplace_back(std::nan(""), std::nan(""), std::nan(""));
      pos += 4;
      continue;
    }
    const auto close = s.find(')', pos);
    if (s[pos] != '(' || close == std::string::npos)
      throw ParseError(
          path, f.line,
          fmt::format("{}: expected '(x,y,z)' vectors, got {}", what, quote_token(s.substr(pos))));
    std::string inner = s.substr(pos + 1, close - pos - 1);
    std::replace(inner.begin(), inner.end(), ',', ' ');
    const auto v = parse_numbers(path, Field{inner, f.line}, 3, what);
    out.emplace_back(v[0], v[1], v[2]);
    pos = close + 1;
  }
  if (out.size() != count)
    throw ParseError(path, f.line,
                     fmt::format("{}: expected {} vectors, got {}", what, count, out.size()));
  return out;
}

double load_sample(const char* p, SampleType t, bool swap) {
  unsigned char b[8];
  const std::size_t n = type_size(t);
  std::memcpy(b, p, n);
  if (swap) std::reverse(b, b + n);
  switch (t) {
    case SampleType::kI8:
      return static_cast<double>(static_cast<std::int8_t>(b[0]));
    case SampleType::kU8:
      return b[0];
    case SampleType::kI16: {
      std::int16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case SampleType::kU16: {
      std::uint16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case SampleType::kI32: {
      std::int32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case SampleType::kU32: {
      std::uint32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case SampleType::kF32: {
      float v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case SampleType::kF64: {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
  }
  return 0;
}

// Expands "quarter.%d 1 93 1" into file names.
std::vector<std::string> expand_pattern(const std::string& path, const Field& f) {
  std::istringstream in(f.value);
  std::string pattern, a, b, c;
  in >> pattern >> a >> b >> c;
  double lo, hi, step;
  if (!parse_double(a, lo) || !parse_double(b, hi) || !parse_double(c, step) || step == 0 ||
      lo != std::floor(lo) || hi != std::floor(hi) || step != std::floor(step))
    throw ParseError(path, f.line,
                     fmt::format("data file: expected '<format> <min> <max> <step>', got {}",
                                 quote_token(f.value)));
  const auto pc = pattern.find('%');
  if (pc == std::string::npos || pattern.find('%', pc + 1) != std::string::npos)
    throw ParseError(path, f.line, "data file: expected exactly one %d-style field in the format");
  std::size_t conv = pc + 1;
  while (conv < pattern.size() &&
         (std::isdigit(static_cast<unsigned char>(pattern[conv])) || pattern[conv] == '0'))
    ++conv;
  if (conv >= pattern.size() ||
      (pattern[conv] != 'd' && pattern[conv] != 'i' && pattern[conv] != 'u'))
    throw ParseError(path, f.line,
                     fmt::format("data file: expected an integer field like %d or %03d, got {}",
                                 quote_token(pattern)));
  const std::string width = pattern.substr(pc + 1, conv - pc - 1);
  std::vector<std::string> files;
  for (long i = long(lo); step > 0 ? i <= long(hi) : i >= long(hi); i += long(step)) {
    std::string num = std::to_string(i);
    if (!width.empty()) {
      const bool zero = width[0] == '0';
      const auto w = static_cast<std::size_t>(std::stoul(width));
      if (num.size() < w) num.insert(0, w - num.size(), zero ? '0' : ' ');
    }
    files.push_back(pattern.substr(0, pc) + num + pattern.substr(conv + 1));
    if (files.size() > 100000) throw ParseError(path, f.line, "data file: too many files");
  }
  return files;
}

struct Header {
  std::map<std::string, Field> fields;
  std::vector<std::pair<std::string, std::size_t>> list_files;  // LIST data files, header line
  std::size_t data_offset = std::string::npos;                  // attached data start
  std::size_t last_line = 1;
};

Header parse_nrrd_header(const std::string& path, const std::string& text) {
  Header h;
  auto& fields = h.fields;
  std::size_t pos = text.find('\n') + 1, line = 1;
  bool in_list = false;
  while (pos > 0 && pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string l = trim(std::string_view(text).substr(pos, end - pos));
    ++line;
    const std::size_t next = end + 1;
    if (l.empty()) {  // end of header; attached data (if any) follows
      h.data_offset = std::min(next, text.size());
      break;
    }
    pos = next;
    if (in_list) {
      h.list_files.emplace_back(l, line);
      continue;
    }
    if (l[0] == '#' || l.find(":=") != std::string::npos) continue;  // comment, key/value pair
    const auto colon = l.find(": ");
    if (colon == std::string::npos)
      throw ParseError(path, line, fmt::format("expected 'field: value', got {}", quote_token(l)));
    std::string key = lower(trim(std::string_view(l).substr(0, colon)));
    if (key == "datafile") key = "data file";
    fields[key] = Field{trim(std::string_view(l).substr(colon + 2)), line};
    if (key == "data file" && lower(fields[key].value).rfind("list", 0) == 0) in_list = true;
  }
  h.last_line = line;
  return h;
}

// The raw sample bytes: the attached block or the data file(s), byte skip applied.
std::string gather_nrrd_data(const std::string& path, const std::string& text, const Header& h,
                             std::size_t count, std::size_t bytes_per, long byte_skip) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::vector<std::pair<std::string, std::size_t>> files;  // name, header line
  if (auto it = h.fields.find("data file"); it != h.fields.end()) {
    const std::string val = it->second.value;
    std::istringstream in(val);
    std::string first, rest;
    in >> first >> rest;
    if (lower(first) == "list") {
      files = h.list_files;
    } else if (!rest.empty()) {
      for (auto& f : expand_pattern(path, it->second)) files.emplace_back(f, it->second.line);
    } else {
      files.emplace_back(val, it->second.line);
    }
    if (files.empty())
      throw ParseError(path, it->second.line, "data file: expected at least one file");
  }
  std::string data;
  if (files.empty()) {
    if (h.data_offset == std::string::npos)
      throw ParseError(path, h.last_line,
                       "expected a blank line then the attached data, or a 'data file:' field");
    data = text.substr(h.data_offset);
    if (byte_skip > 0) data.erase(0, std::min<std::size_t>(data.size(), std::size_t(byte_skip)));
    return data;
  }
  if (count % files.size() != 0)
    throw ParseError(
        path, files.front().second,
        fmt::format("{} data files do not divide {} samples evenly", files.size(), count));
  const std::size_t per_file = count / files.size() * bytes_per;
  data.reserve(count * bytes_per);
  for (const auto& [name, fline] : files) {
    const std::filesystem::path p =
        std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : dir / name;
    std::string bytes;
    try {
      bytes = read_file(p.string());
    } catch (const IoError& e) {
      throw ParseError(path, fline,
                       fmt::format("data file {}: {}", quote_token(p.string(), 200), e.what()));
    }
    std::size_t skip = byte_skip >= 0 ? std::size_t(byte_skip)
                                      : (bytes.size() >= per_file ? bytes.size() - per_file : 0);
    if (bytes.size() < skip + per_file)
      throw ParseError(path, fline,
                       fmt::format("data file {}: expected {} bytes, got {}",
                                   quote_token(p.string(), 200), skip + per_file, bytes.size()));
    data.append(bytes, skip, per_file);
  }
  return data;
}

}  // namespace

Volume read_nrrd(const std::string& path) {
  const std::string text = read_file(path);
  if (text.rfind("NRRD000", 0) != 0)
    throw ParseError(
        path, 1,
        fmt::format("expected the magic 'NRRD000x', got {}", quote_token(text.substr(0, 8))));
  const Header h = parse_nrrd_header(path, text);
  const auto& fields = h.fields;
  const auto need = [&](const char* key) -> const Field& {
    auto it = fields.find(key);
    if (it == fields.end())
      throw ParseError(path, 0, fmt::format("expected a '{}:' field in the header", key));
    return it->second;
  };
  const Field& dim_f = need("dimension");
  if (trim(dim_f.value) != "3")
    throw ParseError(path, dim_f.line,
                     fmt::format("expected dimension 3, got {}", quote_token(dim_f.value)));
  const SampleType type = parse_type(path, need("type"));
  const auto sizes = parse_numbers(path, need("sizes"), 3, "sizes");
  for (double s : sizes)
    if (!(s >= 1) || s != std::floor(s) || s > 1e5)
      throw ParseError(path, need("sizes").line, "sizes: expected three positive integers");
  if (auto it = fields.find("encoding"); it != fields.end() && lower(it->second.value) != "raw")
    throw ParseError(path, it->second.line,
                     fmt::format("expected encoding raw, got {}", quote_token(it->second.value)));
  bool swap = false;
  if (auto it = fields.find("endian"); it != fields.end()) {
    const std::string e = lower(it->second.value);
    if (e != "little" && e != "big")
      throw ParseError(path, it->second.line,
                       fmt::format("expected endian little or big, got {}", quote_token(e)));
    swap = (e == "big") != (std::endian::native == std::endian::big);
  } else if (type_size(type) > 1) {
    throw ParseError(path, 0, "expected an 'endian:' field for multi-byte samples");
  }

  Volume v;
  v.nx = int(sizes[0]);
  v.ny = int(sizes[1]);
  v.nz = int(sizes[2]);
  // An unknown spacing ("nan", a "none" direction) is an error, not a silent 1 mm: the mesh
  // built from the volume would have the wrong size.
  std::size_t spacing_line = 0;
  if (auto it = fields.find("spacings"); it != fields.end()) {
    const auto s = parse_numbers(path, it->second, 3, "spacings");
    for (int a = 0; a < 3; ++a) v.spacing[a] = s[a];
    spacing_line = it->second.line;
  } else if (auto sd = fields.find("space directions"); sd != fields.end()) {
    const auto dirs = parse_vectors(path, sd->second, 3, "space directions");
    for (int a = 0; a < 3; ++a) v.spacing[a] = dirs[a].allFinite() ? dirs[a].norm() : std::nan("");
    spacing_line = sd->second.line;
  }
  for (int a = 0; a < 3; ++a)
    if (!(v.spacing[a] > 0) || !std::isfinite(v.spacing[a]))
      throw ParseError(path, spacing_line,
                       fmt::format("expected three positive finite spacings in mm, got {} {} {}",
                                   v.spacing.x(), v.spacing.y(), v.spacing.z()));
  if (auto it = fields.find("space origin"); it != fields.end()) {
    const auto o = parse_vectors(path, it->second, 1, "space origin");
    if (!o[0].allFinite())
      throw ParseError(path, it->second.line, "space origin: expected a finite point in mm");
    v.origin = o[0];
  }
  long byte_skip = 0;
  if (auto it = fields.find("byte skip"); it != fields.end()) {
    double b;
    if (!parse_double(it->second.value, b) || b < -1 || b != std::floor(b))
      throw ParseError(
          path, it->second.line,
          fmt::format("expected byte skip >= -1, got {}", quote_token(it->second.value)));
    byte_skip = long(b);
  }

  const std::size_t bytes_per = type_size(type), count = std::size_t(v.nx) * v.ny * v.nz;
  const std::string data = gather_nrrd_data(path, text, h, count, bytes_per, byte_skip);
  if (data.size() < count * bytes_per)
    throw ParseError(path, 0,
                     fmt::format("expected {} x {} x {} samples ({} bytes) of data, got {} bytes",
                                 v.nx, v.ny, v.nz, count * bytes_per, data.size()));
  v.values.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double s = load_sample(data.data() + i * bytes_per, type, swap);
    if (!std::isfinite(s)) throw ParseError(path, 0, fmt::format("sample {} is not finite", i));
    v.values[i] = static_cast<float>(s);
  }
  return v;
}

}  // namespace inhap
