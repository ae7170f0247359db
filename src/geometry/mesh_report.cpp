// `inhap mesh info|convert|heightmap`: the mesh report, linear maps, scaling. Units: mm, N/mm.
#include "inhap/geometry/mesh_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "inhap/core/error.hpp"

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

}  // namespace inhap
