// Height and stiffness map writers (grid_io.hpp).
#include "inhap/geometry/grid_io.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"

namespace inhap {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string csv_text(const Grid& g) {
  std::string s;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      if (x) s += ',';
      s += fmt::format("{}", g.at(x, y));
    }
    s += '\n';
  }
  return s;
}

std::string pgm_bytes(const std::string& path, const Grid& g) {
  std::string s = fmt::format("P5\n{} {}\n65535\n", g.width, g.height);
  for (std::size_t i = 0; i < g.values.size(); ++i) {
    const double v = g.values[i];
    if (!(v >= 0 && v <= 65535 && v == std::floor(v)))
      throw Error(fmt::format(
          "{}: PGM: expected integer levels in [0, 65535], got {} at x {}, y {} (write .csv to "
          "keep any value)",
          path, v, i % static_cast<std::size_t>(g.width), i / static_cast<std::size_t>(g.width)));
    const auto level = static_cast<unsigned>(v);
    s += static_cast<char>(level >> 8);  // big-endian, as the format says
    s += static_cast<char>(level & 0xFF);
  }
  return s;
}

}  // namespace

void write_grid(const std::string& path, const Grid& grid) {
  if (grid.width < 1 || grid.height < 1 ||
      grid.values.size() != static_cast<std::size_t>(grid.width) * grid.height)
    throw Error(fmt::format("{}: expected a grid of width x height values, got {} x {} with {}",
                            path, grid.width, grid.height, grid.values.size()));
  const std::string ext = lower_extension(path);
  if (ext == ".csv") {
    for (double v : grid.values)
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: expected finite values, got {}", path, v));
    write_file_atomic(path, csv_text(grid));
  } else if (ext == ".pgm") {
    write_file_atomic(path, pgm_bytes(path, grid));
  } else {
    throw Error(fmt::format("{}: expected a .csv or .pgm file name", path));
  }
}

}  // namespace inhap
