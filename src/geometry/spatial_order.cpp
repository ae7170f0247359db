// Morton ordering of a triangle mesh (see spatial_order.hpp). Units: mm.
#include "inhap/geometry/spatial_order.hpp"

#include <algorithm>
#include <numeric>

namespace inhap {

namespace {

// Spreads the low 21 bits of x so that two zero bits separate each bit.
std::uint64_t spread3(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | (x << 32)) & 0x1f00000000ffffULL;
  x = (x | (x << 16)) & 0x1f0000ff0000ffULL;
  x = (x | (x << 8)) & 0x100f00f00f00f00fULL;
  x = (x | (x << 4)) & 0x10c30c30c30c30c3ULL;
  x = (x | (x << 2)) & 0x1249249249249249ULL;
  return x;
}

std::uint64_t quantize(double v, double lo, double extent) {
  constexpr double kMax = double((1u << 21) - 1);
  if (!(extent > 0)) return 0;
  const double u = (v - lo) / extent * kMax;
  return static_cast<std::uint64_t>(std::clamp(u, 0.0, kMax));
}

template <typename T>
std::vector<T> permuted(const std::vector<T>& v, const std::vector<std::int32_t>& from) {
  std::vector<T> out(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) out[i] = v[static_cast<std::size_t>(from[i])];
  return out;
}

std::vector<std::int32_t> order_by(const std::vector<std::uint64_t>& keys) {
  std::vector<std::int32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return keys[static_cast<std::size_t>(a)] < keys[static_cast<std::size_t>(b)];
  });
  return order;
}

}  // namespace

std::uint64_t morton_key(const Vec3& p, const Vec3& lo, const Vec3& extent) {
  return spread3(quantize(p.x(), lo.x(), extent.x())) |
         (spread3(quantize(p.y(), lo.y(), extent.y())) << 1) |
         (spread3(quantize(p.z(), lo.z(), extent.z())) << 2);
}

SpatialOrder sort_spatially(TriMesh& mesh) {
  SpatialOrder order;
  if (mesh.positions.empty()) return order;
  const Box3 box = mesh.bbox();
  // One scale for all axes (a cube): a thin axis (a height map's z) must not weigh as much as
  // the long ones, or points far apart on the surface would sit next to each other in the order.
  const Vec3 lo = box.min;
  const Vec3 extent = Vec3::Constant((box.max - box.min).maxCoeff());
  std::vector<std::uint64_t> keys(mesh.positions.size());
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = morton_key(mesh.positions[i], lo, extent);
  order.vertex_from = order_by(keys);
  std::vector<std::int32_t> to(mesh.positions.size());
  for (std::size_t i = 0; i < to.size(); ++i)
    to[static_cast<std::size_t>(order.vertex_from[i])] = static_cast<std::int32_t>(i);

  keys.assign(mesh.triangles.size(), 0);
  for (std::size_t f = 0; f < keys.size(); ++f) {
    const Tri& t = mesh.triangles[f];
    const Vec3 c = (mesh.positions[static_cast<std::size_t>(t[0])] +
                    mesh.positions[static_cast<std::size_t>(t[1])] +
                    mesh.positions[static_cast<std::size_t>(t[2])]) /
                   3.0;
    keys[f] = morton_key(c, lo, extent);
  }
  order.face_from = order_by(keys);

  mesh.positions = permuted(mesh.positions, order.vertex_from);
  if (mesh.normals.size() == order.vertex_from.size())
    mesh.normals = permuted(mesh.normals, order.vertex_from);
  for (auto& [name, values] : mesh.properties)
    if (values.size() == order.vertex_from.size()) values = permuted(values, order.vertex_from);
  std::vector<Tri> tris = permuted(mesh.triangles, order.face_from);
  for (Tri& t : tris)
    for (auto& v : t) v = to[static_cast<std::size_t>(v)];
  mesh.triangles = std::move(tris);
  return order;
}

}  // namespace inhap
