// WSxM `.top` topography reader (Nanotec Electronica / WSxM solutions).
//
// Layout: an ASCII header ("WSxM file copyright ...", "SxM Image file", then
// "Image header size: N", sections "[Control]" ... "[Header end]", CR LF line ends) of exactly N
// bytes, followed by rows x columns samples, row-major, little-endian. The sample type is given
// by "Image Data Type" (short = int16 when absent, as in old files; also int, float, double).
// Heights: integer samples are scaled so that their full range spans "Z Amplitude" (e.g.
// "59.7449 nm" over raw -19468..-5073 gives 0.0041504 nm per count, the same as "Conversion
// Factor 00" / 3276.8); floating-point samples are already in Z units. The result is in the
// file's Z unit (nm for AFM topography) — callers scale it (e.g. into a 100 mm cube).
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/text.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace inhap {

namespace {

struct HeaderValue {
  std::string text;
  std::size_t line = 0;
};

using text::lower;
using text::trim;

// "key: value" lines of the header, keys lower-cased; [sections] and blank lines skipped.
std::map<std::string, HeaderValue> parse_header(std::string_view header) {
  std::map<std::string, HeaderValue> kv;
  std::size_t pos = 0, line = 0;
  while (pos < header.size()) {
    std::size_t end = header.find('\n', pos);
    if (end == std::string_view::npos) end = header.size();
    const std::string_view l = header.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    const auto colon = l.find(':');
    if (colon == std::string_view::npos) continue;
    const std::string key = lower(trim(l.substr(0, colon)));
    if (!key.empty() && !kv.count(key)) kv[key] = {trim(l.substr(colon + 1)), line};
  }
  return kv;
}

long parse_count(const std::string& path, const HeaderValue& v, const char* what) {
  double d;
  if (!parse_double(v.text, d) || d < 1 || d > 1e6 || d != std::floor(d))
    throw ParseError(
        path, v.line,
        fmt::format("expected a positive integer {}, got {}", what, quote_token(v.text)));
  return static_cast<long>(d);
}

template <typename T>
T load_le(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    auto* b = reinterpret_cast<unsigned char*>(&v);
    std::reverse(b, b + sizeof(T));
  }
  return v;
}

}  // namespace

Grid read_wsxm_top(const std::string& path) {
  const std::string bytes = read_file(path);
  // The header size line comes first; look for it in the first few lines only.
  const std::string_view head(bytes.data(), std::min<std::size_t>(bytes.size(), 512));
  const auto key_pos = head.find("Image header size:");
  if (bytes.rfind("WSxM file copyright", 0) != 0 || key_pos == std::string_view::npos)
    throw ParseError(path, 1,
                     "expected a WSxM file ('WSxM file copyright' and 'Image header size:' lines)");
  const std::size_t key_line = 1 + std::count(head.begin(), head.begin() + key_pos, '\n');
  const auto eol = head.find('\n', key_pos);
  const std::string size_text = trim(head.substr(
      key_pos + 18, (eol == std::string_view::npos ? head.size() : eol) - key_pos - 18));
  double header_size_d;
  if (!parse_double(size_text, header_size_d) || header_size_d < 1 ||
      header_size_d != std::floor(header_size_d) || header_size_d > double(bytes.size()))
    throw ParseError(
        path, key_line,
        fmt::format("expected a header size between 1 and the file size {} bytes, got {}",
                    bytes.size(), quote_token(size_text)));
  const auto header_size = static_cast<std::size_t>(header_size_d);
  const std::string_view header(bytes.data(), header_size);
  if (header.find("[Header end]") == std::string_view::npos)
    throw ParseError(
        path, key_line,
        fmt::format("expected '[Header end]' within the {} header bytes", header_size));
  const auto kv = parse_header(header);
  const auto get = [&](const char* key) -> const HeaderValue* {
    auto it = kv.find(key);
    return it == kv.end() ? nullptr : &it->second;
  };
  const HeaderValue* cols_v = get("number of columns");
  const HeaderValue* rows_v = get("number of rows");
  if (!cols_v || !rows_v)
    throw ParseError(path, key_line,
                     "expected 'Number of columns:' and 'Number of rows:' in the header");
  const long cols = parse_count(path, *cols_v, "number of columns");
  const long rows = parse_count(path, *rows_v, "number of rows");

  std::string type = "short";
  std::size_t type_line = 0;
  if (const HeaderValue* t = get("image data type")) {
    type = lower(t->text);
    type_line = t->line;
  }
  std::size_t bytes_per = 0;
  if (type == "short" || type == "int16")
    bytes_per = 2;
  else if (type == "int" || type == "integer" || type == "int32")
    bytes_per = 4;
  else if (type == "float")
    bytes_per = 4;
  else if (type == "double")
    bytes_per = 8;
  else
    throw ParseError(path, type_line,
                     fmt::format("expected Image Data Type short, int, float or double, got {}",
                                 quote_token(type)));

  const std::size_t n = std::size_t(rows) * std::size_t(cols);
  if (bytes.size() < header_size + n * bytes_per)
    throw ParseError(
        path, 0,
        fmt::format("expected {} rows x {} columns of {} samples ({} bytes) after the {}-byte "
                    "header, got {} bytes",
                    rows, cols, type, n * bytes_per, header_size, bytes.size() - header_size));
  Grid g(static_cast<int>(cols), static_cast<int>(rows));
  const char* data = bytes.data() + header_size;
  const bool integer = type != "float" && type != "double";
  for (std::size_t i = 0; i < n; ++i) {
    const char* p = data + i * bytes_per;
    double v;
    if (bytes_per == 2)
      v = load_le<std::int16_t>(p);
    else if (type == "float")
      v = load_le<float>(p);
    else if (bytes_per == 4)
      v = load_le<std::int32_t>(p);
    else
      v = load_le<double>(p);
    if (!std::isfinite(v))
      throw ParseError(
          path, 0,
          fmt::format("sample {} (row {}, column {}) is not finite", i, i / cols, i % cols));
    g.values[i] = v;
  }
  if (integer) {
    // Scale raw counts so that the data range spans the Z amplitude.
    if (const HeaderValue* za = get("z amplitude")) {
      double amp;
      const std::string num = za->text.substr(0, za->text.find_first_of(" \t"));
      if (!parse_double(num, amp) || !(amp >= 0) || !std::isfinite(amp))
        throw ParseError(
            path, za->line,
            fmt::format("expected 'Z Amplitude: <number> <unit>', got {}", quote_token(za->text)));
      const double lo = g.min(), hi = g.max();
      if (hi > lo)
        for (auto& v : g.values) v *= amp / (hi - lo);
    }
  }
  return g;
}

}  // namespace inhap
