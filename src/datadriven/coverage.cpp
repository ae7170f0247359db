// Coverage of a training recording (see coverage.hpp). Units: mm, N.
#include "inhap/datadriven/coverage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"

namespace inhap::datadriven {

namespace {

std::array<int, 3> cell_of(const Vec3& q, double cell) {
  std::array<int, 3> i{};
  for (int a = 0; a < 3; ++a)
    i[static_cast<std::size_t>(a)] = static_cast<int>(std::floor(q[a] / cell));
  return i;
}

}  // namespace

std::uint64_t CoverageMap::key(const std::array<int, 3>& i) {
  auto u = [](int v) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v) & 0x1fffff);
  };
  return u(i[0]) | (u(i[1]) << 21) | (u(i[2]) << 42);
}

void CoverageMap::index_cells() {
  std::sort(cells_.begin(), cells_.end(),
            [](const CoverageCell& a, const CoverageCell& b) { return a.index < b.index; });
  lookup_.clear();
  for (std::size_t c = 0; c < cells_.size(); ++c) lookup_[key(cells_[c].index)] = c;
}

CoverageMap::CoverageMap(const std::vector<Vec3>& q, const std::vector<Vec3>& f,
                         const CoverageParams& p)
    : p_(p) {
  if (!(p.cell_mm > 0) || !std::isfinite(p.cell_mm))
    throw Error(fmt::format("coverage: expected a cell size > 0 mm, got {}", p.cell_mm));
  if (q.size() != f.size()) throw Error("coverage: expected as many forces as proxy positions");
  std::unordered_map<std::uint64_t, std::size_t> at;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (!q[i].allFinite() || !f[i].allFinite()) continue;
    const auto idx = cell_of(q[i], p.cell_mm);
    auto [it, added] = at.emplace(key(idx), cells_.size());
    if (added) cells_.push_back({idx, 0, 0.0});
    CoverageCell& c = cells_[it->second];
    ++c.samples;
    c.f_max = std::max(c.f_max, f[i].norm());
  }
  index_cells();
}

CoverageMap::CoverageMap(std::vector<CoverageCell> cells, const CoverageParams& p)
    : p_(p), cells_(std::move(cells)) {
  index_cells();
}

double CoverageMap::neighbourhood_force(const Vec3& q) const {
  if (!q.allFinite() || cells_.empty()) return -1;
  const auto c = cell_of(q, p_.cell_mm);
  double best = -1;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = lookup_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
        if (it != lookup_.end()) best = std::max(best, cells_[it->second].f_max);
      }
  return best;
}

bool CoverageMap::outside(const Vec3& q, double f_mag) const {
  const double fmax = neighbourhood_force(q);
  if (fmax < 0) return true;
  return f_mag >= 0 && f_mag > p_.force_slack * fmax + p_.force_margin_n;
}

std::vector<CoverageGap> coverage_gaps(const CoverageMap& map, std::size_t max_gaps) {
  std::vector<CoverageGap> gaps;
  if (map.cells().empty()) return gaps;
  int x0 = map.cells()[0].index[0], x1 = x0, y0 = map.cells()[0].index[1], y1 = y0;
  for (const CoverageCell& c : map.cells()) {
    x0 = std::min(x0, c.index[0]), x1 = std::max(x1, c.index[0]);
    y0 = std::min(y0, c.index[1]), y1 = std::max(y1, c.index[1]);
  }
  const auto nx = static_cast<std::size_t>(x1 - x0 + 1), ny = static_cast<std::size_t>(y1 - y0 + 1);
  if (nx * ny > 4'000'000) return gaps;
  std::vector<char> state(nx * ny, 0);  // 0 empty, 1 visited, 2 in a gap already
  for (const CoverageCell& c : map.cells())
    state[static_cast<std::size_t>(c.index[0] - x0) +
          nx * static_cast<std::size_t>(c.index[1] - y0)] = 1;
  const double cell = map.params().cell_mm;
  std::vector<std::size_t> stack;
  for (std::size_t s = 0; s < state.size(); ++s) {
    if (state[s] != 0) continue;
    CoverageGap g;
    double sx = 0, sy = 0;
    stack.assign(1, s);
    state[s] = 2;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      const std::size_t i = c % nx, j = c / nx;
      ++g.cells;
      sx += (static_cast<double>(x0) + static_cast<double>(i) + 0.5) * cell;
      sy += (static_cast<double>(y0) + static_cast<double>(j) + 0.5) * cell;
      const std::size_t nb[4] = {i > 0 ? c - 1 : c, i + 1 < nx ? c + 1 : c, j > 0 ? c - nx : c,
                                 j + 1 < ny ? c + nx : c};
      for (std::size_t k : nb)
        if (state[k] == 0) state[k] = 2, stack.push_back(k);
    }
    g.x_mm = sx / static_cast<double>(g.cells);
    g.y_mm = sy / static_cast<double>(g.cells);
    gaps.push_back(g);
  }
  std::stable_sort(gaps.begin(), gaps.end(),
                   [](const CoverageGap& a, const CoverageGap& b) { return a.cells > b.cells; });
  if (gaps.size() > max_gaps) gaps.resize(max_gaps);
  return gaps;
}

std::string coverage_path_for(const std::string& model_path) {
  const std::string ext = ".json";
  if (model_path.size() > ext.size() &&
      model_path.compare(model_path.size() - ext.size(), ext.size(), ext) == 0)
    return model_path.substr(0, model_path.size() - ext.size()) + ".coverage.csv";
  return model_path + ".coverage.csv";
}

void write_coverage(const std::string& path, const CoverageMap& map) {
  const std::vector<std::string> comments{
      "training coverage: cells of the proxy positions q visited in contact",
      "units: x y z (cell centre) mm, cell_mm mm, f_max_n (largest |f| in the cell) N"};
  CsvWriter w(path, {"x", "y", "z", "cell_mm", "samples", "f_max_n"}, comments);
  const double c = map.params().cell_mm;
  for (const CoverageCell& cell : map.cells())
    w.row({(cell.index[0] + 0.5) * c, (cell.index[1] + 0.5) * c, (cell.index[2] + 0.5) * c, c,
           static_cast<double>(cell.samples), cell.f_max});
  w.commit();
}

// Data rows start at line 4 (two comment lines and the header precede them).
CoverageMap read_coverage(const std::string& path) {
  static constexpr std::string_view kCols[] = {"x", "y", "z", "cell_mm", "samples", "f_max_n"};
  const CsvTable t = read_csv(path, kCols);
  CoverageParams p;
  std::vector<CoverageCell> cells;
  const auto &x = t.column("x"), &y = t.column("y"), &z = t.column("z");
  const auto &cm = t.column("cell_mm"), &n = t.column("samples"), &fm = t.column("f_max_n");
  for (std::size_t i = 0; i < t.rows(); ++i) {
    if (!(cm[i] > 0) || !std::isfinite(cm[i]) || (i > 0 && cm[i] != cm[0]))
      throw ParseError(path, i + 4, fmt::format("expected one positive cell size, got {}", cm[i]));
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i]) ||
        !std::isfinite(fm[i]) || !(n[i] >= 0))
      throw ParseError(path, i + 4, "expected finite x, y, z, f_max_n and samples >= 0");
    p.cell_mm = cm[i];
    cells.push_back(
        {cell_of(Vec3(x[i], y[i], z[i]), cm[i]), static_cast<std::size_t>(n[i]), fm[i]});
  }
  return CoverageMap(std::move(cells), p);
}

}  // namespace inhap::datadriven
