#include "inhap/geometry/heightmap.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"

namespace inhap {

double Grid::min() const {
  return values.empty() ? 0.0 : *std::min_element(values.begin(), values.end());
}
double Grid::max() const {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

namespace {

[[maybe_unused]] bool has_extension(const std::string& path, const char* ext) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e == ext;
}

// Reads a grid of numbers, one grid row per line, separated by commas (or blanks).
Grid read_csv_grid(const std::string& path, const std::string& text) {
  Grid g;
  std::size_t line_no = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
      line.remove_suffix(1);
    std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;
    int count = 0;
    std::size_t i = 0;
    while (i <= line.size()) {
      std::size_t j = line.find_first_of(",; \t", i);
      if (j == std::string_view::npos) j = line.size();
      std::string_view tok = line.substr(i, j - i);
      if (!tok.empty()) {
        double v;
        if (!parse_double(tok, v) || !std::isfinite(v))
          throw ParseError(path, line_no,
                           fmt::format("column {}: expected a finite number, got {}", count + 1,
                                       quote_token(tok)));
        g.values.push_back(v);
        ++count;
      } else if (j < line.size() && line[j] == ',') {
        throw ParseError(
            path, line_no,
            fmt::format("column {}: expected a number, got an empty field", count + 1));
      }
      i = j + 1;
    }
    if (g.width == 0) g.width = count;
    if (count != g.width)
      throw ParseError(
          path, line_no,
          fmt::format("expected {} values as in the first row, got {}", g.width, count));
    ++g.height;
  }
  if (g.width < 2 || g.height < 2)
    throw ParseError(
        path, 0,
        fmt::format("expected a grid of at least 2x2 values, got {}x{}", g.width, g.height));
  return g;
}

// PGM: "P2"/"P5", width, height, maxval, separated by whitespace with '#' comments.
Grid read_pgm(const std::string& path, const std::string& data) {
  std::size_t pos = 2, line = 1;
  auto next_token = [&](const char* what) -> long {
    while (pos < data.size()) {
      char c = data[pos];
      if (c == '#') {
        while (pos < data.size() && data[pos] != '\n') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        if (c == '\n') ++line;
        ++pos;
      } else {
        break;
      }
    }
    std::size_t start = pos;
    while (pos < data.size() && std::isdigit(static_cast<unsigned char>(data[pos]))) ++pos;
    if (start == pos || pos - start > 9)
      throw ParseError(path, line,
                       fmt::format("PGM header: expected {} (a positive integer), got {}", what,
                                   quote_token(std::string_view(data).substr(start, 8))));
    return std::stol(data.substr(start, pos - start));
  };
  const bool binary = data[1] == '5';
  long w = next_token("width"), h = next_token("height"), maxval = next_token("maxval");
  if (w < 2 || h < 2 || w > 100000 || h > 100000)
    throw ParseError(
        path, line,
        fmt::format("PGM header: expected width and height in [2, 100000], got {}x{}", w, h));
  if (maxval < 1 || maxval > 65535)
    throw ParseError(path, line,
                     fmt::format("PGM header: expected maxval in [1, 65535], got {}", maxval));
  // The declared size is checked against the file before anything is allocated: a 300-byte
  // file declaring 20000x20000 pixels is truncated, not a 3 GB grid.
  const std::size_t n = std::size_t(w) * std::size_t(h);
  const std::size_t bytes = maxval > 255 ? 2 : 1;
  if (binary) ++pos;  // exactly one whitespace after maxval
  const std::size_t left = data.size() > pos ? data.size() - pos : 0;
  // ASCII pixels take at least one digit and one separator each (the last one no separator).
  const std::size_t needed = binary ? n * bytes : 2 * n - 1;
  if (left < needed)
    throw ParseError(path, 0,
                     fmt::format("truncated PGM data: {}x{} pixels need at least {} bytes, got {}",
                                 w, h, needed, left));
  Grid g(static_cast<int>(w), static_cast<int>(h));
  if (binary) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto* b = reinterpret_cast<const unsigned char*>(data.data() + pos + i * bytes);
      g.values[i] = bytes == 2 ? double((b[0] << 8) | b[1]) : double(b[0]);  // PGM is big-endian
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      long v = next_token("a pixel value");
      if (v > maxval)
        throw ParseError(path, line, fmt::format("pixel value {} exceeds maxval {}", v, maxval));
      g.values[i] = double(v);
    }
  }
  return g;
}

}  // namespace

Grid read_grid(const std::string& path) {
  std::string data = read_file(path);
  if (data.rfind("WSxM file copyright", 0) == 0) return read_wsxm_top(path);  // AFM topography
  if (data.empty())
    throw ParseError(path, 0, "empty file: expected a height/stiffness grid (CSV or PGM)");
  if (data.size() >= 2 && data[0] == 'P' && (data[1] == '2' || data[1] == '5'))
    return read_pgm(path, data);
  if (data.size() >= 2 && data[0] == 'P')
    throw ParseError(path, 1,
                     fmt::format("expected a PGM (P2 or P5) or a CSV grid, got magic {}",
                                 quote_token(data.substr(0, 2))));
  return read_csv_grid(path, data);
}

Grid resample_bilinear(const Grid& raw, int n) {
  Grid out(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double gx = x * double(raw.width - 1) / (n - 1),
                   gy = y * double(raw.height - 1) / (n - 1);
      const int ix = std::min(raw.width - 2, int(gx)), iy = std::min(raw.height - 2, int(gy));
      const double fx = gx - ix, fy = gy - iy;
      out.at(x, y) = (1 - fx) * (1 - fy) * raw.at(ix, iy) + fx * (1 - fy) * raw.at(ix + 1, iy) +
                     (1 - fx) * fy * raw.at(ix, iy + 1) + fx * fy * raw.at(ix + 1, iy + 1);
    }
  return out;
}

void level_plane(Grid& grid) {
  // Least squares z = a x + b y + c over all pixels (normal equations on centred coordinates).
  const double cx = 0.5 * (grid.width - 1), cy = 0.5 * (grid.height - 1);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      Eigen::Vector3d r(x - cx, y - cy, 1.0);
      A += r * r.transpose();
      b += r * grid.at(x, y);
    }
  Eigen::Vector3d c = A.ldlt().solve(b);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) grid.at(x, y) -= c[0] * (x - cx) + c[1] * (y - cy) + c[2];
}

Grid downsample(const Grid& grid, int factor) {
  if (factor < 1) throw Error(fmt::format("downsample factor must be >= 1, got {}", factor));
  const int w = grid.width / factor, h = grid.height / factor;
  if (w < 2 || h < 2)
    throw Error(
        fmt::format("downsampling a {}x{} grid by {} leaves {}x{} pixels: need at least 2x2",
                    grid.width, grid.height, factor, w, h));
  Grid out(w, h);
  const double inv = 1.0 / (double(factor) * factor);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (int j = 0; j < factor; ++j)
        for (int i = 0; i < factor; ++i) sum += grid.at(x * factor + i, y * factor + j);
      out.at(x, y) = sum * inv;
    }
  return out;
}

TriMesh grid_to_mesh(const Grid& height, double spacing_mm, const Grid* stiffness) {
  if (height.width < 2 || height.height < 2)
    throw Error(
        fmt::format("height map must be at least 2x2, got {}x{}", height.width, height.height));
  if (!(spacing_mm > 0) || !std::isfinite(spacing_mm))
    throw Error(fmt::format("pixel spacing must be a positive number of mm, got {}", spacing_mm));
  if (stiffness && (stiffness->width != height.width || stiffness->height != height.height))
    throw Error(fmt::format(
        "stiffness map is {}x{} but the height map is {}x{}: they must be the same size",
        stiffness->width, stiffness->height, height.width, height.height));
  const int W = height.width, H = height.height;
  TriMesh m;
  m.positions.reserve(std::size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      m.positions.emplace_back(x * spacing_mm, y * spacing_mm, height.at(x, y));
  m.triangles.reserve(2 * std::size_t(W - 1) * (H - 1));
  for (int y = 0; y + 1 < H; ++y)
    for (int x = 0; x + 1 < W; ++x) {
      const std::int32_t a = y * W + x, b = a + 1, c = a + W, d = c + 1;
      // Alternate the diagonal (checkerboard) so the tessellation has no preferred direction.
      if ((x + y) % 2 == 0) {
        m.triangles.push_back({a, b, d});
        m.triangles.push_back({a, d, c});
      } else {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({b, d, c});
      }
    }
  if (stiffness) {
    for (double k : stiffness->values)
      if (!std::isfinite(k) || k < 0)
        throw Error(fmt::format("stiffness map: expected finite values >= 0 N/mm, got {}", k));
    m.set_property("stiffness", stiffness->values);
  }
  m.compute_normals();
  return m;
}

}  // namespace inhap
