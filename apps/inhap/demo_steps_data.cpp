// inhap demo: strokes on the real data sets of thesis fig. 5.3 (Stanford bunny, CT head, AFM
// topography) when --data DIR holds them. Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <filesystem>
#include <limits>

#include "demo.hpp"
#include "demo_strokes.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/volume.hpp"

namespace inhap::demo {
namespace {

namespace fs = std::filesystem;

struct DataSet {
  std::string name, file;
  std::function<TriMesh(const std::string&)> load;
};

// Bunny: metres -> mm, y-up -> z-up; stiffness from height (softer at the top, 0.3-1.0 N/mm).
TriMesh load_bunny(const std::string& path) {
  TriMesh m = read_mesh(path);
  for (auto& p : m.positions) p = Vec3(p.x(), -p.z(), p.y()) * 1000.0;
  m.normals.clear();
  m.compute_normals();
  const Box3 b = m.bbox();
  std::vector<double> k;
  for (const auto& p : m.positions)
    k.push_back(1.0 - 0.7 * (p.z() - b.min.z()) / std::max(1e-9, b.max.z() - b.min.z()));
  m.set_property("stiffness", k);
  return m;
}

// AFM: levelled, resampled to 129 x 129 over 100 mm, height range 10 mm, stiffness from height.
TriMesh load_afm(const std::string& path) {
  Grid raw = read_wsxm_top(path);
  level_plane(raw);
  const int n = 129;
  Grid h(n, n), k(n, n);
  const double lo = raw.min(), span = std::max(raw.max() - lo, 1e-12);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int ix = std::min(raw.width - 1, int(std::lround(x * double(raw.width - 1) / (n - 1))));
      const int iy =
          std::min(raw.height - 1, int(std::lround(y * double(raw.height - 1) / (n - 1))));
      const double v = (raw.at(ix, iy) - lo) / span;
      h.at(x, y) = 10.0 * v;
      k.at(x, y) = 1.0 - 0.8 * v;
    }
  return grid_to_mesh(h, 100.0 / (n - 1), &k);
}

TriMesh load_head(const std::string& path) {
  return head_from_volume(read_nrrd(path)).mesh;
}

}  // namespace

StepResult step_data_strokes(const Context& c) {
  StepResult r;
  if (c.options.data.empty()) {
    r.available = false;
    r.note = "no --data DIR given (bunny/, headsq/, afm-topography/)";
    r.rows.push_back({"strokes on bunny / CT head / AFM", "skipped: no --data", "fig. 5.3"});
    return r;
  }
  const std::vector<DataSet> sets = {{"bunny", "bunny/bun_zipper.ply", load_bunny},
                                     {"ct-head", "headsq/quarter.nhdr", load_head},
                                     {"afm", "afm-topography/sample_0.top", load_afm}};
  int done = 0;
  for (const auto& d : sets) {
    const fs::path file = fs::path(c.options.data) / d.file;
    if (!fs::exists(file)) {
      r.rows.push_back({fmt::format("strokes on {}", d.name), "skipped: file missing", "-"});
      continue;
    }
    c.progress(double(done) / double(sets.size()), "loading " + d.name);
    const render::Model model(d.load(file.string()));
    const Box3 b = model.mesh().bbox();
    const Vec2 mid((b.min.x() + b.max.x()) / 2, (b.min.y() + b.max.y()) / 2);
    const double half = 0.12 * std::min(b.max.x() - b.min.x(), b.max.y() - b.min.y());
    StrokeCase sc;
    sc.name = d.name;
    sc.from = mid - Vec2(half, 0);
    sc.to = mid + Vec2(half, 0);
    // True surface: the mesh's top under (x, y) (first hit of a vertical segment), NaN off it.
    sc.truth = [&model, b](double x, double y) {
      const auto hit =
          model.index().first_hit(Vec3(x, y, b.max.z() + 1.0), Vec3(x, y, b.min.z() - 1.0));
      return hit ? hit->point.z() : std::numeric_limits<double>::quiet_NaN();
    };
    try {
      const StrokePair p = run_stroke_pair(model, sc, c.options.seed);
      r.figures.push_back(
          stroke_figure(sc, p, "fig5_data_" + d.name,
                        fmt::format("Stroke across the {} (fig. 5.3 data)", d.name)));
      write_stroke_csv(c.file(r, fmt::format("stroke_{}.csv", d.name)), p);
      r.figures.push_back(mesh_figure(
          model.mesh(), "stiffness", {{p.tca, "#1f77b4"}, {p.cba, "#ff7f0e"}}, "mesh_" + d.name,
          fmt::format("The {} mesh, coloured by stiffness", d.name),
          fmt::format("{} triangles; blue soft to red hard. Lines: IHIP paths (TCA-MESH blue, "
                      "CBA orange).",
                      model.mesh().num_triangles())));
      r.rows.push_back({fmt::format("{}: stroke shape distortion RMS, TCA-MESH / CBA (mm)", d.name),
                        fmt::format("{:.3f} / {:.3f}", p.distortion_tca, p.distortion_cba), "-"});
    } catch (const Error& e) {
      r.rows.push_back(
          {fmt::format("strokes on {}", d.name), fmt::format("failed: {}", e.what()), "-"});
    }
    ++done;
    c.progress(double(done) / double(sets.size()), d.name);
  }
  return r;
}

}  // namespace inhap::demo
