// Numeric CSV tables addressed by header names, and haptic recordings.
//
// Format: optional comment lines starting with '#' (units, provenance), then one header row of
// column names, then rows of numbers separated by commas. Blank lines are ignored. Every row must
// have as many fields as the header. Errors name the file, the line and what was expected.
//
// A *recording* is a CSV with at least the columns t,px,py,pz,fx,fy,fz:
//   t  time stamp in seconds (strictly increasing)
//   px,py,pz  probe position in mm
//   fx,fy,fz  force in N (the force the object exerts on the probe)
// Any further columns (raw sensor, proxy qx,qy,qz, ...) are kept by name.
#pragma once

#include <cstddef>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/types.hpp"

namespace inhap {

/// Streams a numeric CSV file row by row (constant memory).
class CsvReader {
 public:
  /// Opens `path` and reads the header row. Throws IoError / ParseError.
  explicit CsvReader(std::string path);
  ~CsvReader() = default;
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  /// Index of a column, if present.
  std::optional<std::size_t> find(std::string_view name) const;
  /// Index of a column; throws ParseError naming the header line when it is missing.
  std::size_t require(std::string_view name) const;

  /// Reads the next data row; false at end of file. Throws ParseError on a ragged row or a
  /// field that is not a number.
  bool next();
  std::span<const double> values() const { return values_; }
  double operator[](std::size_t column) const { return values_[column]; }
  /// 1-based line number of the current row (or of the header before the first next()).
  std::size_t line() const { return line_; }
  std::size_t header_line() const { return header_line_; }

 private:
  bool read_line();  // into current_; false at EOF
  // Owns the FILE* and getline's buffer; a member, so a throwing constructor still frees them.
  struct Source {
    std::FILE* file = nullptr;
    char* buf = nullptr;
    std::size_t cap = 0;
    Source() = default;
    Source(const Source&) = delete;
    Source& operator=(const Source&) = delete;
    ~Source();
  };
  std::string path_;
  Source src_;
  std::string_view current_;
  std::size_t line_ = 0, header_line_ = 0;
  std::vector<std::string> header_;
  std::vector<double> values_;
};

/// A whole CSV table in memory, column-major.
struct CsvTable {
  std::string path;
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  std::optional<std::size_t> find(std::string_view name) const;
  /// Column by name; throws Error naming the file when missing.
  const std::vector<double>& column(std::string_view name) const;
};

/// Reads a whole table; `required` columns must be present (ParseError otherwise).
CsvTable read_csv(const std::string& path, std::span<const std::string_view> required = {});

/// Writes rows atomically (temporary file + rename on commit()).
class CsvWriter {
 public:
  /// `comments` are written first as "# ..." lines (put the units there).
  CsvWriter(std::string path, std::vector<std::string> header,
            std::span<const std::string> comments = {});
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) {
    row(std::span<const double>(values.begin(), values.size()));
  }
  void commit();
  std::size_t columns() const { return ncols_; }

 private:
  AtomicFile file_;
  std::size_t ncols_;
  std::string buf_;
};

/// A recording from a real or simulated haptic device (see file comment for columns).
struct Recording {
  std::vector<double> t;  ///< s
  std::vector<Vec3> p;    ///< mm
  std::vector<Vec3> f;    ///< N
  std::vector<std::string> extra_names;
  std::vector<std::vector<double>> extra;  ///< one vector per extra column

  std::size_t size() const { return t.size(); }
  /// Extra column by name, nullptr when absent.
  const std::vector<double>* find_extra(std::string_view name) const;
  /// Adds or replaces an extra column (must have size() entries).
  void set_extra(const std::string& name, std::vector<double> values);
};

/// Reads a recording: requires t,px,py,pz,fx,fy,fz, finite values and strictly increasing t.
Recording read_recording(const std::string& path);
/// Writes a recording atomically, with a units comment line.
void write_recording(const std::string& path, const Recording& rec);

/// Parses one number like the CSV reader does (used by other text readers).
bool parse_double(std::string_view token, double& out);
/// Parses exactly `n` comma-separated numbers ("1.5,-2,3") into out[0..n-1] with parse_double;
/// false for another count or a token that is not a number.
bool parse_number_list(std::string_view s, std::size_t n, double* out);

}  // namespace inhap
