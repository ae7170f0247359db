#include "inhap/core/csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/core/text.hpp"

namespace inhap {

namespace {

std::string_view csv_trim(std::string_view s) {
  return text::trim_view(s);
}

bool blank(std::string_view s) {
  return csv_trim(s).empty();
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? "," : "") + names[i];
  return out;
}

}  // namespace

bool parse_double(std::string_view token, double& out) {
  token = csv_trim(token);
  if (token.empty()) return false;
  if (token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, out);
  if (ec == std::errc::result_out_of_range) {
    // Denormals and overflow: fall back to strtod semantics (inf / 0 are still numbers).
    std::string tmp(token);
    char* e = nullptr;
    out = std::strtod(tmp.c_str(), &e);
    return e == tmp.c_str() + tmp.size();
  }
  return ec == std::errc() && ptr == end;
}

bool parse_number_list(std::string_view s, std::size_t n, double* out) {
  std::size_t start = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t end = s.find(',', start);
    const bool last = k + 1 == n;
    if ((end == std::string_view::npos) != last) return false;  // too few or too many
    if (!parse_double(s.substr(start, last ? std::string_view::npos : end - start), out[k]))
      return false;
    start = end + 1;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
CsvReader::CsvReader(std::string path) : path_(std::move(path)) {
  std::error_code dir_ec;
  if (std::filesystem::is_directory(path_, dir_ec))
    throw Error(path_ + ": expected a CSV file, got a directory");
  errno = 0;
  src_.file = std::fopen(path_.c_str(), "rb");
  if (!src_.file) throw IoError(path_, "cannot open for reading");
  static constexpr std::size_t kBuf = 1 << 20;
  std::setvbuf(src_.file, nullptr, _IOFBF, kBuf);
  while (true) {
    if (!read_line())
      throw ParseError(path_, line_ ? line_ : 1,
                       "empty file: expected a header row of column names");
    std::string_view t = csv_trim(current_);
    if (t.empty() || t.front() == '#') continue;
    break;
  }
  header_line_ = line_;
  std::string_view rest = current_;
  while (true) {
    std::size_t comma = rest.find(',');
    std::string_view field = csv_trim(rest.substr(0, comma));
    if (field.empty())
      throw ParseError(path_, line_,
                       fmt::format("empty column name in header (column {})", header_.size() + 1));
    double dummy;
    if (header_.empty() && parse_double(field, dummy))
      throw ParseError(
          path_, line_,
          fmt::format(
              "expected a header row of column names (e.g. t,px,py,pz,fx,fy,fz), got number {}",
              quote_token(field)));
    if (std::find(header_.begin(), header_.end(), field) != header_.end())
      throw ParseError(path_, line_, fmt::format("duplicate column name {}", quote_token(field)));
    header_.emplace_back(field);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  values_.resize(header_.size());
}

CsvReader::Source::~Source() {
  if (file) std::fclose(file);
  std::free(buf);
}

bool CsvReader::read_line() {
  ssize_t n = ::getline(&src_.buf, &src_.cap, src_.file);
  if (n < 0) {
    if (std::ferror(src_.file)) throw IoError(path_, "read failed");
    return false;
  }
  ++line_;
  std::size_t len = static_cast<std::size_t>(n);
  if (len && src_.buf[len - 1] == '\n') --len;
  if (len && src_.buf[len - 1] == '\r') --len;
  if (std::memchr(src_.buf, '\0', len))
    throw ParseError(path_, line_, "binary data (NUL byte) in a text CSV file");
  current_ = std::string_view(src_.buf, len);
  return true;
}

std::optional<std::size_t> CsvReader::find(std::string_view name) const {
  auto it = std::find(header_.begin(), header_.end(), name);
  if (it == header_.end()) return std::nullopt;
  return static_cast<std::size_t>(it - header_.begin());
}

std::size_t CsvReader::require(std::string_view name) const {
  if (auto i = find(name)) return *i;
  throw ParseError(path_, header_line_,
                   fmt::format("missing column '{}' (header has: {})", name, join(header_)));
}

bool CsvReader::next() {
  do {
    if (!read_line()) return false;
  } while (blank(current_) || csv_trim(current_).front() == '#');
  std::string_view rest = current_;
  std::size_t col = 0;
  while (true) {
    std::size_t comma = rest.find(',');
    std::string_view field = rest.substr(0, comma);
    if (col >= values_.size())
      throw ParseError(
          path_, line_,
          fmt::format("expected {} fields as in the header, got more", values_.size()));
    if (!parse_double(field, values_[col]))
      throw ParseError(path_, line_,
                       fmt::format("column '{}': expected a number, got {}", header_[col],
                                   quote_token(csv_trim(field))));
    ++col;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (col != values_.size())
    throw ParseError(
        path_, line_,
        fmt::format("expected {} fields as in the header, got {}", values_.size(), col));
  return true;
}

// ---------------------------------------------------------------------------------------------
std::optional<std::size_t> CsvTable::find(std::string_view name) const {
  auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return std::nullopt;
  return static_cast<std::size_t>(it - names.begin());
}

const std::vector<double>& CsvTable::column(std::string_view name) const {
  if (auto i = find(name)) return columns[*i];
  throw Error(fmt::format("{}: missing column '{}' (header has: {})", path, name, join(names)));
}

CsvTable read_csv(const std::string& path, std::span<const std::string_view> required) {
  CsvReader r(path);
  for (auto name : required) r.require(name);
  CsvTable t;
  t.path = path;
  t.names = r.header();
  t.columns.resize(t.names.size());
  while (r.next()) {
    auto v = r.values();
    for (std::size_t c = 0; c < v.size(); ++c) t.columns[c].push_back(v[c]);
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
CsvWriter::CsvWriter(std::string path, std::vector<std::string> header,
                     std::span<const std::string> comments)
    : file_(std::move(path)), ncols_(header.size()) {
  for (const auto& c : comments) file_.write("# " + c + "\n");
  std::string h;
  for (std::size_t i = 0; i < header.size(); ++i) h += (i ? "," : "") + header[i];
  file_.write(h + "\n");
  buf_.reserve(1 << 16);
}

void CsvWriter::row(std::span<const double> values) {
  if (values.size() != ncols_)
    throw Error(fmt::format("{}: internal error: row with {} values for {} columns", file_.path(),
                            values.size(), ncols_));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) buf_ += ',';
    // Shortest representation that round-trips: deterministic bytes, exact reload.
    fmt::format_to(std::back_inserter(buf_), "{}", values[i]);
  }
  buf_ += '\n';
  if (buf_.size() > (1 << 16) - 512) {
    file_.write(buf_);
    buf_.clear();
  }
}

void CsvWriter::commit() {
  file_.write(buf_);
  buf_.clear();
  file_.commit();
}

// ---------------------------------------------------------------------------------------------
const std::vector<double>* Recording::find_extra(std::string_view name) const {
  for (std::size_t i = 0; i < extra_names.size(); ++i)
    if (extra_names[i] == name) return &extra[i];
  return nullptr;
}

void Recording::set_extra(const std::string& name, std::vector<double> values) {
  if (values.size() != size())
    throw Error(fmt::format("recording column '{}' has {} values, expected {}", name, values.size(),
                            size()));
  for (std::size_t i = 0; i < extra_names.size(); ++i)
    if (extra_names[i] == name) {
      extra[i] = std::move(values);
      return;
    }
  extra_names.push_back(name);
  extra.push_back(std::move(values));
}

static constexpr std::string_view kRecordingColumns[] = {"t", "px", "py", "pz", "fx", "fy", "fz"};

Recording read_recording(const std::string& path) {
  CsvReader r(path);
  std::size_t idx[7];
  for (int i = 0; i < 7; ++i) idx[i] = r.require(kRecordingColumns[i]);
  std::vector<std::size_t> extra_idx;
  Recording rec;
  for (std::size_t c = 0; c < r.header().size(); ++c) {
    if (std::find(std::begin(idx), std::end(idx), c) != std::end(idx)) continue;
    extra_idx.push_back(c);
    rec.extra_names.push_back(r.header()[c]);
  }
  rec.extra.resize(extra_idx.size());
  while (r.next()) {
    for (std::size_t c = 0; c < r.values().size(); ++c)
      if (!std::isfinite(r[c]))
        throw ParseError(
            path, r.line(),
            fmt::format("column '{}': expected a finite number, got {}", r.header()[c], r[c]));
    double t = r[idx[0]];
    if (!rec.t.empty() && !(t > rec.t.back()))
      throw ParseError(
          path, r.line(),
          fmt::format("time must be strictly increasing: t = {} after t = {}", t, rec.t.back()));
    rec.t.push_back(t);
    rec.p.emplace_back(r[idx[1]], r[idx[2]], r[idx[3]]);
    rec.f.emplace_back(r[idx[4]], r[idx[5]], r[idx[6]]);
    for (std::size_t e = 0; e < extra_idx.size(); ++e) rec.extra[e].push_back(r[extra_idx[e]]);
  }
  return rec;
}

void write_recording(const std::string& path, const Recording& rec) {
  std::vector<std::string> header(std::begin(kRecordingColumns), std::end(kRecordingColumns));
  header.insert(header.end(), rec.extra_names.begin(), rec.extra_names.end());
  const std::string comments[] = {"inhap recording; units: t s, px py pz mm, fx fy fz N"};
  CsvWriter w(path, header, comments);
  std::vector<double> row(header.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    row[0] = rec.t[i];
    for (int k = 0; k < 3; ++k) {
      row[1 + k] = rec.p[i][k];
      row[4 + k] = rec.f[i][k];
    }
    for (std::size_t e = 0; e < rec.extra.size(); ++e) row[7 + e] = rec.extra[e][i];
    w.row(row);
  }
  w.commit();
}

}  // namespace inhap
