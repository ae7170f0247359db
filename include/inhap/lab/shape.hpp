// Virtual lab: undeformed geometry of a soft object as an exact signed distance field.
// Units: mm. The object rests on the plane z = 0 (or floats, for a sphere) and is touched from
// +z; "up" is +z everywhere in the lab.
//
// Every query is const, allocation-free and exception-free (used inside the physics substeps).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {
class MeshIndex;
struct TriMesh;
}  // namespace inhap

namespace inhap::lab {

/// Signed distance query result.
struct SurfaceQuery {
  double distance = std::numeric_limits<double>::infinity();  ///< > 0 outside, < 0 inside, mm
  Vec3 normal{0, 0, 1};                                       ///< unit outward normal
  Vec3 closest = Vec3::Zero();                                ///< closest surface point, mm
};

/// Upright cylinder (axis +z) standing on its base: a flat top is the "plane" case.
struct CylinderShape {
  Vec3 base_center{0, 0, 0};
  double radius = 50.0;
  double height = 25.0;
};

/// Spherical cap (dome) standing on its flat base; height == base_radius is a hemisphere.
struct DomeShape {
  Vec3 base_center{0, 0, 0};
  double base_radius = 50.0;
  double height = 30.0;
};

/// Hemisphere standing on its flat face (stored separately for the scene file's sake).
struct HemisphereShape {
  Vec3 base_center{0, 0, 0};
  double radius = 40.0;
};

struct SphereShape {
  Vec3 center{0, 0, 35};
  double radius = 35.0;
};

/// Axis-aligned box.
struct BoxShape {
  Vec3 center{0, 0, 15};
  Vec3 half_size{40, 30, 15};
};

/// Slab on z = 0 whose top carries `ridges` triangular ridges running along y, equally spaced
/// across x (pitch = size_x / ridges, each `ridge_width` wide at its base, flat valleys between).
struct RidgedSlabShape {
  Vec3 base_center{0, 0, 0};
  double size_x = 100.0, size_y = 60.0, thickness = 20.0;
  int ridges = 6;
  double ridge_height = 6.0, ridge_width = 14.0;
};

/// Closed, outward-oriented triangle mesh (PLY/OBJ) used as the undeformed surface; file
/// positions p are placed at U (scale * p) + offset (mm), where U turns the file's up axis
/// (`up` = 'z' or 'y', as in the Stanford models) onto the lab's +z.
struct MeshShape {
  std::string path;  ///< as written in the scene file
  double scale = 1.0;
  Vec3 offset = Vec3::Zero();
  char up = 'z';
  std::shared_ptr<const MeshIndex> index;
  std::shared_ptr<const TriMesh> mesh;  ///< placed, with vertex normals (inside/outside sign)
};

/// Builds a mesh shape from a mesh already in memory (placed as is; normals recomputed).
MeshShape make_mesh_shape(TriMesh mesh, std::string path = "(memory)");

class Shape {
 public:
  using Variant = std::variant<CylinderShape, DomeShape, HemisphereShape, SphereShape, BoxShape,
                               RidgedSlabShape, MeshShape>;

  Shape() : Shape(CylinderShape{}) {}
  Shape(Variant v);  // NOLINT: implicit on purpose (Shape s = BoxShape{...})
  template <class T>
  requires(!std::is_same_v<std::decay_t<T>, Shape> && std::is_constructible_v<Variant, T>)
      Shape(T s)
      : Shape(Variant(std::move(s))) {}  // NOLINT: implicit on purpose

  const Variant& variant() const { return v_; }
  /// "cylinder", "dome", "hemisphere", "sphere", "box", "ridged-slab" or "mesh".
  std::string_view type_name() const;

  /// Exact signed distance, outward normal and closest point (meshes: sign from the
  /// interpolated vertex normal at the closest point).
  SurfaceQuery query(const Vec3& p) const;
  double distance(const Vec3& p) const { return query(p).distance; }
  Box3 bounds() const;

  /// Lowers a probe of radius `probe_radius` straight down (-z) at (x, y) from above the object
  /// and returns its centre where it first touches (signed distance == radius), or nullopt
  /// when it misses. Sphere tracing on the exact distance, tolerance 1e-7 mm.
  std::optional<Vec3> drop(double x, double y, double probe_radius) const;

 private:
  Variant v_;
  std::vector<Vec2> profile_;  // ridged slab: closed (x, z) cross-section polygon, local coords
};

/// Checks a shape's parameters (positive sizes, ridges fit, ...); returns an error message or
/// an empty string.
std::string validate_shape(const Shape& shape);

}  // namespace inhap::lab
