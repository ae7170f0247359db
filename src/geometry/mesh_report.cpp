// `inhap mesh info|convert|heightmap`: the mesh report, linear maps, scaling. Units: mm, N/mm.
#include "inhap/geometry/mesh_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>

#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"

namespace inhap {

namespace {

std::pair<double, double> range_of(const std::vector<double>& v) {
  if (v.empty()) return {0.0, 0.0};
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {*lo, *hi};
}

}  // namespace

std::string mesh_info_text(const std::string& file, const TriMesh& m) {
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  const Box3 b = m.bbox();
  std::string s = fmt::format("file        {}\n", file);
  s += fmt::format("vertices    {}\n", m.num_vertices());
  s += fmt::format("faces       {}\n", m.num_triangles());
  s += fmt::format("edges       {}\n", topo.edges);
  if (!b.empty()) {
    s += fmt::format("bbox min    {:.6g} {:.6g} {:.6g} mm\n", b.min.x(), b.min.y(), b.min.z());
    s += fmt::format("bbox max    {:.6g} {:.6g} {:.6g} mm\n", b.max.x(), b.max.y(), b.max.z());
    const Vec3 z = b.size();
    s += fmt::format("size        {:.6g} x {:.6g} x {:.6g} mm\n", z.x(), z.y(), z.z());
  }
  for (const auto& [name, v] : m.properties) {
    const auto [l, h] = range_of(v);
    s += fmt::format("property    {} in [{:.6g}, {:.6g}]{}\n", name, l, h,
                     name == "stiffness" ? " N/mm" : "");
  }
  s += fmt::format("manifold    {}{}\n", topo.manifold() ? "yes" : "no",
                   topo.manifold()
                       ? ""
                       : fmt::format(" ({} non-manifold edges, {} non-manifold vertices)",
                                     topo.nonmanifold_edges, topo.nonmanifold_vertices));
  s += fmt::format("watertight  {}\n", topo.watertight() ? "yes" : "no");
  s += fmt::format("boundary    {} loops, {} edges\n", topo.boundary_loops, topo.boundary_edges);
  s += fmt::format("oriented    {}{}\n", topo.oriented() ? "yes" : "no",
                   topo.oriented() ? ""
                                   : fmt::format(" ({} edges with inconsistent faces)",
                                                 topo.inconsistent_edges));
  s += fmt::format("components  {}\n", topo.components);
  return s;
}

std::string mesh_info_json(const std::string& file, const TriMesh& m) {
  const MeshTopology topo = analyze_topology(m, build_adjacency(m));
  const Box3 b = m.bbox();
  nlohmann::json props = nlohmann::json::object();
  for (const auto& [name, v] : m.properties) {
    const auto [l, h] = range_of(v);
    props[name] = {{"min", l}, {"max", h}};
  }
  const nlohmann::json j = {
      {"file", file},
      {"vertices", m.num_vertices()},
      {"faces", m.num_triangles()},
      {"edges", topo.edges},
      {"bbox_mm",
       {{"min", {b.min.x(), b.min.y(), b.min.z()}}, {"max", {b.max.x(), b.max.y(), b.max.z()}}}},
      {"properties", props},
      {"manifold", topo.manifold()},
      {"watertight", topo.watertight()},
      {"oriented", topo.oriented()},
      {"boundary_loops", topo.boundary_loops},
      {"boundary_edges", topo.boundary_edges},
      {"components", topo.components}};
  return j.dump(2) + "\n";
}

std::vector<double> map_linear(const std::vector<double>& v, double lo, double hi) {
  const auto [a, b] = range_of(v);
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = b > a ? lo + (v[i] - a) / (b - a) * (hi - lo) : hi;
  return out;
}

void scale_and_center(TriMesh& m, double scale_to, bool center, const std::string& what) {
  const Box3 b = m.bbox();
  const Vec3 origin = center ? b.center() : Vec3::Zero();
  double scale = 1.0;
  if (scale_to > 0) {
    const double largest = b.size().maxCoeff();
    if (!(largest > 0)) throw Error(fmt::format("{}: cannot scale a mesh of zero size", what));
    scale = scale_to / largest;
  }
  if (center || scale != 1.0) m.transform(scale, origin);
}

void stiffness_from_property(TriMesh& m, const std::string& prop,
                             const std::vector<double>& k_range) {
  if (prop.empty()) {
    if (!k_range.empty()) throw Error("--k-range needs --stiffness-from PROP");
    return;
  }
  if (k_range.size() != 2) throw Error("--stiffness-from needs --k-range KMIN KMAX (N/mm)");
  if (!(k_range[0] >= 0) || !(k_range[1] >= k_range[0]) || !std::isfinite(k_range[1]))
    throw Error(fmt::format("--k-range: expected 0 <= KMIN <= KMAX N/mm, got {} {}", k_range[0],
                            k_range[1]));
  m.set_property("stiffness", map_linear(m.property(prop), k_range[0], k_range[1]));
}

std::string mesh_written_text(const std::string& out, const TriMesh& m) {
  const Box3 nb = m.bbox();
  std::string k;
  if (m.has_property("stiffness")) {
    const auto& v = m.property("stiffness");
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    k = fmt::format(", stiffness in [{:.4g}, {:.4g}] N/mm", *lo, *hi);
  }
  return fmt::format("wrote {}: {} vertices, {} faces, size {:.4g} x {:.4g} x {:.4g} mm{}\n", out,
                     m.num_vertices(), m.num_triangles(), nb.size().x(), nb.size().y(),
                     nb.size().z(), k);
}

std::string dropped_properties_text(const std::string& path,
                                    const std::vector<std::string>& dropped) {
  std::string s;
  for (const auto& name : dropped)
    s += fmt::format(
        "inhap: warning: {}: the format cannot store vertex property '{}'; it was dropped\n", path,
        name);
  return s;
}

HeightmapMesh heightmap_mesh(const HeightmapMeshOptions& o) {
  Grid h = read_grid(o.height);
  for (auto& v : h.values) v *= o.height_scale;
  if (o.level) level_plane(h);
  std::unique_ptr<Grid> k;
  if (!o.stiffness.empty() && !o.k_from_height.empty())
    throw Error("give either --stiffness MAP or --stiffness-from-height KMIN KMAX, not both");
  if (!o.stiffness.empty()) {
    k = std::make_unique<Grid>(read_grid(o.stiffness));
    if (o.k_range.size() == 2)  // map the map's raw levels [min, max] linearly onto the range
      k->values = map_linear(k->values, o.k_range[0], o.k_range[1]);
  } else if (o.k_from_height.size() == 2) {
    k = std::make_unique<Grid>(h);
    k->values = map_linear(h.values, o.k_from_height[0], o.k_from_height[1]);
  }
  double spacing = o.spacing_mm;
  if (k && (k->width != h.width || k->height != h.height))
    throw Error(
        fmt::format("stiffness map {} is {}x{} but the height map is {}x{}: they must be "
                    "the same size",
                    o.stiffness, k->width, k->height, h.width, h.height));
  if (o.downsample > 1) {  // after levelling and the stiffness mapping: same result per block
    h = downsample(h, o.downsample);
    if (k) *k = downsample(*k, o.downsample);
    spacing *= o.downsample;
  }
  HeightmapMesh out{grid_to_mesh(h, spacing, k.get()), h.width, h.height};
  out.mesh.validate(o.height);  // heights of +-1e308 (or scaled past it): an error naming the file
  return out;
}

std::string heightmap_written_text(const std::string& out, const HeightmapMesh& h) {
  const Box3 b = h.mesh.bbox();
  return fmt::format(
      "wrote {}: {}x{} grid, {} vertices, {} triangles, size {:.4g} x {:.4g} x {:.4g} mm\n", out,
      h.width, h.height, h.mesh.num_vertices(), h.mesh.num_triangles(), b.size().x(), b.size().y(),
      b.size().z());
}

}  // namespace inhap
